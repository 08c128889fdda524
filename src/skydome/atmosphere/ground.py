"""What lies below the horizon: the ground's kinds (``Sky(ground=...)``, ``--ground``) and the
layer that blacks the ground out for environment maps.

- a number: a grey Lambertian ground of that albedo (0-1), lit by the Sun and the sky and
  seen through the air; the atmosphere's multiple scattering is computed with it too;
- a surface's name (``SURFACES``: grassland, cropland, forest, desert, snow, ocean, urban):
  a Lambertian ground of that surface's spectral albedo (CMAQ's IGBP reference table,
  ``skydome.spectra.surface_albedo``), in the tables too: the measured Earth's presets stand
  on grassland (the urban, maritime and desert airs on urban, ocean and desert ground);
- ``"none"``: no ground that reflects (albedo 0 for the surface and the tables): the lower
  hemisphere holds only the light of the air in front of where the ground would be (the
  horizon's haze, the Earth's shadow in it at dusk), dark beneath;
- ``"black"``: exactly zero wherever the camera's ray meets the planet (the sky above keeps
  the atmosphere's own ground light), for HDRIs used with a ground of the user's own;
- an image file (PNG, JPEG, TIFF): a landscape panorama in front of the sky (hills, trees,
  buildings; ``LandscapeLayer``), an equirect image twice as wide as it is high, north at
  its left edge and east a quarter across (as skydome's own equirect maps), the horizon its
  middle row, its colours Lambertian reflectances (sRGB) and its alpha the coverage
  (transparent where the sky shows), lit as the level ground at the camera is and seen
  through LANDSCAPE_KM of air; below it (and where it is transparent) the atmosphere's
  ground;
- None (the default): the atmosphere's own ground albedo (grassland for ``earth``).

The horizon is the planet's for the camera's height (a ray below the dip meets the ground),
the same test as the atmosphere's own (``ray_hits_ground``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from skydome.atmosphere.params import Spectrum, surface_spectrum
from skydome.core.cameras import CameraInputs
from skydome.core.layer import BehindInputs, DrawContext, Layer
from skydome.core.services import AirService, LightInputs
from skydome.errors import ParameterError
from skydome.gpu.inputs import ShaderInputs
from skydome.io.images import read_user_image
from skydome.physics.refraction import horizon_dip_sin
from skydome.spectra import SURFACES

#: The ground's kinds by name.
GROUND_KINDS = ("none", "black")
#: Image files a landscape panorama may be (by suffix), and their formats.
LANDSCAPE_SUFFIXES = (".png", ".jpg", ".jpeg", ".tif", ".tiff")
#: How far the landscape stands (km): the aerial perspective in front of it.
LANDSCAPE_KM = 3.0
#: The largest panorama (pixels) and file (bytes) read.
MAX_LANDSCAPE_SIDE = 16384
MAX_LANDSCAPE_PIXELS = 16384 * 8192
MAX_LANDSCAPE_BYTES = 512 * 2**20
#: GL's internal format of an sRGB texture with alpha (sampling decodes to linear values).
GL_SRGB8_ALPHA8 = 0x8C43


def is_landscape(ground) -> bool:
    """Whether a ground setting names a landscape panorama (an image file)."""
    return isinstance(ground, str) and ground.lower().endswith(LANDSCAPE_SUFFIXES)


def parse_ground(value: str | float | None) -> str | float | None:
    """A ground setting checked: None, "none", "black" or an albedo within [0, 1] (a number
    or its text). ParameterError names the setting otherwise."""
    if value is None:
        return None
    if isinstance(value, bool):
        raise ParameterError(f"ground must be none, black or an albedo 0..1, got {value!r}")
    if isinstance(value, str):
        text = value.strip().lower()
        if text in GROUND_KINDS or text in SURFACES:
            return text
        if text.endswith(LANDSCAPE_SUFFIXES):
            path = Path(value.strip()).expanduser()
            if not path.is_file():
                raise ParameterError(f"ground: the landscape panorama {value!r} is not a file")
            return str(path)
        try:
            value = float(text)
        except ValueError:
            raise ParameterError(
                f"ground {value!r} must be none, black, an albedo 0..1 (e.g. 0.2), a surface "
                f"({', '.join(SURFACES)}) or a landscape panorama (.png, .jpg, .tif)"
            ) from None
    try:
        albedo = float(value)
    except (TypeError, ValueError):
        raise ParameterError(
            f"ground must be none, black or an albedo 0..1, got {value!r}"
        ) from None
    if not (math.isfinite(albedo) and 0.0 <= albedo <= 1.0):
        raise ParameterError(f"ground albedo {value!r} must be within [0, 1]")
    return albedo


def ground_albedo(ground: str | float | None) -> float | Spectrum | None:
    """The albedo the atmosphere is computed with for a ground setting (None: its own)."""
    if ground == "none":
        return 0.0
    if isinstance(ground, float):
        return ground
    if ground in SURFACES:
        return surface_spectrum(ground)
    return None


@dataclass(frozen=True)
class GroundInputs(ShaderInputs):
    """``atmosphere/ground_black.glsl``: the sine of the ground horizon's dip."""

    u_dip_sin: float


class BlackGroundLayer(Layer):
    """Zero light wherever the camera's ray meets the ground (volume stage: put it last, after
    the clouds and the weather): the lower hemisphere of an environment map left black. The
    horizon is the atmosphere layer's ground sphere seen from the camera's height."""

    name = "ground"
    stage = "volume"
    shader = "atmosphere/ground_black.glsl"

    def draw(self, frame: DrawContext) -> None:
        air = self.graph.find_service(AirService)
        bottom_m = air.bottom_radius_m if air is not None else 6_371_000.0
        inputs = GroundInputs(u_dip_sin=horizon_dip_sin(frame.altitude_m, bottom_m))
        fpass = self.full_screen_pass(
            frame.ctx, self.shader, (CameraInputs, BehindInputs, GroundInputs), frame.camera
        )
        fpass.draw(frame.fbo, frame.view, self.behind_inputs(frame), inputs)


@dataclass(frozen=True)
class LandscapeInputs(ShaderInputs):
    """``atmosphere/landscape.glsl``: the panorama (an sRGB texture: linear reflectance and
    coverage) and how far it stands (km)."""

    u_landscape: object
    u_landscape_km: float
    u_landscape_lod: float


def read_landscape(path: str) -> np.ndarray:
    """The panorama at ``path`` as (H, W, 4) uint8 sRGB + alpha, top row first; checked: a
    regular image file (``read_user_image``), twice as wide as high (to a pixel)."""
    img = read_user_image(
        path,
        what="landscape panorama",
        max_pixels=MAX_LANDSCAPE_PIXELS,
        max_side=MAX_LANDSCAPE_SIDE,
        max_bytes=MAX_LANDSCAPE_BYTES,
    )
    with img:
        if abs(img.width - 2 * img.height) > 1:
            raise ParameterError(
                f"landscape panorama {path!r} is {img.width} x {img.height}: an equirect "
                "panorama is twice as wide as it is high"
            )
        return np.asarray(img.convert("RGBA"), dtype=np.uint8)


class LandscapeLayer(Layer):
    """A landscape panorama in front of the sky (volume stage: put it last): see the module
    docstring for the image's layout. ``distance_km``: how far it stands (aerial
    perspective). Needs the precomputed atmosphere (its lookups light and veil it)."""

    name = "landscape"
    stage = "volume"
    shader = "atmosphere/landscape.glsl"

    def __init__(self, path: str, *, distance_km: float = LANDSCAPE_KM, enabled: bool = True):
        super().__init__(enabled=enabled)
        self.path = str(path)
        self.distance_km = float(distance_km)
        if not (math.isfinite(self.distance_km) and 0.0 < self.distance_km <= 100.0):
            raise ParameterError(f"landscape distance_km {distance_km!r} must be within (0, 100]")
        self._pixels = read_landscape(self.path)  # checked now: a bad file fails at once
        self._texture = None

    def prepare(self, host) -> None:
        super().prepare(host)
        self.air = host.service(AirService)
        rows = np.ascontiguousarray(self._pixels[::-1])  # GL rows: the bottom first
        h, w = rows.shape[:2]
        ctx = host.ctx
        tex = ctx.texture((w, h), 4, rows.tobytes(), internal_format=GL_SRGB8_ALPHA8)
        tex.build_mipmaps()
        tex.filter = (ctx.LINEAR_MIPMAP_LINEAR, ctx.LINEAR)
        tex.repeat_x, tex.repeat_y = True, False  # the azimuth wraps round
        self._texture = tex
        self._pixels = None

    def draw(self, frame: DrawContext) -> None:
        air = self.air
        lookup = air.lookup()
        lights = air.lights().inputs(air.camera_position_km(frame.altitude_m), air.solar_scale)
        # the mip level of the camera's pixel (0 for a direction map: no pixel size)
        texel_rad = 2.0 * math.pi / self._texture.width
        pixel_rad = frame.camera.pixel_angle(*frame.frame_size)
        lod = max(math.log2(pixel_rad / texel_rad), 0.0) if pixel_rad > 0.0 else 0.0
        inputs = (frame.view, lookup.inputs, lights, self.behind_inputs(frame),
                  LandscapeInputs(self._texture, self.distance_km, lod))  # fmt: skip
        fpass = self.full_screen_pass(
            frame.ctx, self.shader, (CameraInputs, type(lookup.inputs), LightInputs,
                                     BehindInputs, LandscapeInputs),
            frame.camera, lookup.defines,
        )  # fmt: skip
        fpass.draw(frame.fbo, *inputs)

    def release(self) -> None:
        super().release()
        if self._texture is not None:
            self._texture.release()
            self._texture = None
