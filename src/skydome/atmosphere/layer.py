"""The atmosphere layer: the frame graph's volume of air.

Two models draw it:

- ``"precomputed"`` (the default): every scattering order from tables
  (:class:`~skydome.atmosphere.precomputed.PrecomputedSky`); the light the space layers drew
  (the Sun's and the Moon's disks, the stars) is multiplied by the transmittance of each
  pixel's ray, per output channel, and the sky's in-scattered light of the Sun and of the
  Moon (its second light) is added; the ground hides what lies beyond;
- ``"single"``: single scattering marched per pixel
  (:class:`~skydome.atmosphere.single.SingleScatteringSky`), with its own Sun disk and
  nothing behind it: a reference of the first order.

The moonlit sky is the sunlit sky's tables lit from the Moon's direction, scaled by the
Moon's illuminance and coloured per channel by the Moon's spectrum relative to the Sun's
(``Light.relative_spectrum``). The layer offers the other layers its tables and lights as
an :class:`~skydome.core.services.AirService`.
"""

from __future__ import annotations

import numpy as np

from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.atmosphere.precomputed import PrecomputedSky, camera_position_km
from skydome.atmosphere.presets import preset
from skydome.atmosphere.single import SingleScatteringSky
from skydome.atmosphere.sky_view import check_sky_view_size
from skydome.core.basis import SpectralBasis
from skydome.core.layer import DrawContext, Layer, LayerHost
from skydome.core.lights import SkyState
from skydome.core.services import AirLights, AirService, LookupTables
from skydome.errors import ParameterError, check_choice
from skydome.gpu.textures import release_all
from skydome.physics.constants import AU_KM
from skydome.physics.geometry import elevation_deg
from skydome.spectra import solar_luminance

#: The models that draw the air.
MODELS = ("precomputed", "single")


def atmosphere_params(atmosphere: str | AtmosphereParams) -> AtmosphereParams:
    """A preset by name, or the given AtmosphereParams."""

    if isinstance(atmosphere, AtmosphereParams):
        return atmosphere
    if isinstance(atmosphere, str):
        return preset(atmosphere)
    raise ParameterError(f"atmosphere {atmosphere!r} must be a preset name or an AtmosphereParams")


class AtmosphereLayer(Layer):
    """The air of a preset or of ``AtmosphereParams``.

    Args:
        atmosphere: a preset name or AtmosphereParams.
        model: "precomputed" (every scattering order, tables) or "single" (single
            scattering, marched per pixel).
        config: the precomputed model's tables (``PrecomputeConfig``; default: 16
            wavelengths, 4 orders).
        moonlight: light the sky by the Moon too (when the scene has one).
        sky_view: for a camera inside the air, draw from sky-view tables (False: look every
            pixel up in the 4D tables, for comparisons).
        sky_view_size: (azimuth, elevation) texels of the sky-view tables (default 256 x
            256; 128 x 128 costs a quarter to re-aim and differs by <= 0.16 % RMS at 640 x
            360, measured at Sun 30 to -8 deg: time-lapses use it).
        samples, jitter, spectral: the single-scattering model's samples per view ray,
            ordered offsets and wavelength set.
        cache: keep the tables in the disk cache and share them in GPU memory (False:
            precompute them afresh for this layer).
        progress: ``progress(stage, fraction)`` during a table precomputation.
    """

    name = "atmosphere"
    stage = "volume"
    merges_smooth = True  # its composite reads the reduced smooth light (common/behind.glsl)

    def __init__(
        self,
        atmosphere: str | AtmosphereParams = "earth",
        *,
        model: str = "precomputed",
        config: PrecomputeConfig | None = None,
        moonlight: bool = True,
        sky_view: bool = True,
        sky_view_size: tuple[int, int] | None = None,
        samples: int = 16,
        jitter: bool = True,
        spectral: str = "accurate",
        cache: bool = True,
        progress=None,
        enabled: bool = True,
    ):
        super().__init__(enabled=enabled)
        check_choice("model", model, MODELS, "model")
        self.params = atmosphere_params(atmosphere)
        self.model = model
        self.config = config
        self.moonlight = bool(moonlight)
        self.sky_view = bool(sky_view)
        self.sky_view_size = None if sky_view_size is None else check_sky_view_size(sky_view_size)
        self.samples, self.jitter, self.spectral = samples, bool(jitter), spectral
        self.cache = bool(cache)
        self._progress = progress
        self.sky: PrecomputedSky | SingleScatteringSky | None = None
        self.spectral_basis: SpectralBasis | None = None
        self._lights: AirLights | None = None
        self._last_sun = None
        self._tint: np.ndarray | None = None
        self._tint_of = None
        self._transmittance: dict = {}
        self._outputs: dict = {}
        #: Draw each pixel's view direction instead of radiance (single model): a
        #: debugging aid for the cameras.
        self.output_directions = False
        if model == "single":  # checked now, not at the first frame
            SingleScatteringSky.check_samples(samples)

    # ------------------------------------------------------------------ stages

    def prepare(self, host: LayerHost) -> None:
        super().prepare(host)
        if self.sky is None:
            if self.model == "single":
                self.sky = SingleScatteringSky(
                    host.ctx, self.params, spectral=self.spectral,
                    view_samples=self.samples, jitter=self.jitter,
                )  # fmt: skip
            else:
                extra = {} if self.sky_view_size is None else {"sky_view_size": self.sky_view_size}
                self.sky = PrecomputedSky(
                    host.ctx, self.params, self.config, cache=self.cache,
                    progress=self._progress, sky_view=self.sky_view, **extra,
                )  # fmt: skip
        output = "rgbs" if self.model == "single" else self.sky.config.output
        self.spectral_basis = SpectralBasis.for_wavelengths(self.sky.wavelengths_nm, output)

    def services(self) -> tuple:
        return (_AirOfLayer(self),) if self.model == "precomputed" else ()

    def update(self, state: SkyState) -> None:
        sun = state.sun
        # The tables' light paths are straight: the air is lit from the airless direction
        # (the apparent one is for the disk, which the Sun layer draws refracted; the
        # single model draws its own disk, where the Sun is seen). It is also continuous:
        # the refraction laws stop at the horizon.
        direction = sun.direction if self.model == "single" else sun.direction_true
        moon_direction, moon_scale = None, (0.0,) * 4
        moon = state.moon
        if self.moonlight and moon is not None and self.model == "precomputed":
            ratio = moon.illuminance_lux / self._solar_lux() / self.params.solar_scale
            moon_direction = tuple(float(v) for v in moon.direction_true)
            moon_scale = tuple(float(v) for v in ratio * self._moon_tint(moon))
        self._lights = AirLights(
            sun_direction=tuple(float(v) for v in direction),
            # The tables hold the Sun at 1 au: scale by the true distance.
            sun_scale=(AU_KM / sun.distance_km) ** 2,
            moon_direction=moon_direction,
            moon_scale=moon_scale,
        )

    def lights(self) -> AirLights:
        """The lights of the last update as the tables see them."""
        if self._lights is None:
            raise ParameterError("the atmosphere layer has no lights before its first update")
        return self._lights

    def _solar_lux(self) -> float:
        """Illuminance (lx) of the tabulated solar spectrum at 1 au, as the tables see it."""
        return solar_luminance(self.spectral_basis.wavelengths_nm)

    def _moon_tint(self, moon) -> np.ndarray:
        """Per output channel: the Moon's light relative to the Sun's at equal luminance."""
        if moon.relative_spectrum is None:
            return np.ones(4)
        if self._tint is None or self._tint_of is not moon.relative_spectrum:
            basis = self.spectral_basis
            wl = basis.wavelengths_nm
            self._tint = basis.colour(moon.relative_spectrum(wl)) / basis.colour(np.ones(len(wl)))
            self._tint_of = moon.relative_spectrum
        return self._tint

    def _frame_lights(self, altitude_m: float) -> AirLights:
        """The lights for a frame from ``altitude_m``: a light far enough below the horizon
        adds exactly nothing, so its sky-view table is left as it is (not re-aimed) and its
        light out."""
        lights = self.lights()
        dark = self.sky.dark_below_deg(altitude_m)
        sun, scale = lights.sun_direction, lights.sun_scale
        if elevation_deg(sun) < dark:
            scale = 0.0
            if self._last_sun is not None:
                sun = self._last_sun
        self._last_sun = sun
        moon, moon_scale = lights.moon_direction, lights.moon_scale
        if moon is not None and elevation_deg(moon) < dark:
            moon, moon_scale = None, (0.0,) * 4
        return AirLights(sun, scale, moon, moon_scale)

    def draw(self, frame: DrawContext) -> None:
        if self.model == "single":
            self.sky.draw(frame, self.lights(), directions=self.output_directions)
            return
        lights = self._frame_lights(frame.altitude_m)
        behind = self.behind_inputs(frame)
        if frame.depth_map is None:
            self.sky.draw(frame, lights, behind)
            return
        _, _, tw, th = frame.tile
        tex, fbo = self._transmittance_target(frame, (tw, th))
        self.sky.draw(frame, lights, behind, depth_map=frame.depth_map, transmittance_fbo=fbo)
        self._outputs["transmittance"] = tex

    def _transmittance_target(self, frame: DrawContext, size):
        """A framebuffer drawing into the frame's target (with its depth buffer: the ground
        pass above the air tests it) and a transmittance texture of the same size (kept per
        target)."""
        key = id(frame.target)
        if key not in self._transmittance:
            ctx = self.graph.ctx
            tex = ctx.texture(size, 4, dtype="f4")
            fbo = ctx.framebuffer(
                color_attachments=[frame.target, tex],
                depth_attachment=frame.fbo.depth_attachment,
            )
            self._transmittance[key] = (tex, fbo, frame.target)
        tex, fbo, _ = self._transmittance[key]
        return tex, fbo

    def outputs(self) -> dict:
        """Textures of the last tile beside the frame (``transmittance``: the RGB
        transmittance to a user's scene, with a depth map), then forgotten."""
        out, self._outputs = self._outputs, {}
        return out

    def lookup(self) -> LookupTables:
        return self.sky.lookup()

    def info(self) -> dict:
        return {} if self.sky is None else {"model": self.model, **self.sky.info()}

    def release(self) -> None:
        super().release()
        for tex, fbo, _ in self._transmittance.values():
            release_all(fbo, tex)
        self._transmittance.clear()
        if self.sky is not None:
            self.sky.release()
            self.sky = None


class _AirOfLayer(AirService):
    """The atmosphere layer's :class:`AirService`."""

    def __init__(self, layer: AtmosphereLayer):
        self._layer = layer
        p = layer.params
        self.bottom_radius_m = p.bottom_radius_m
        self.top_radius_m = p.top_radius_m
        self.solar_scale = p.solar_scale

    def lights(self) -> AirLights:
        return self._layer.lights()

    def lookup(self) -> LookupTables:
        return self._layer.lookup()

    def ground_albedo(self) -> float:
        return self._layer.sky.ground_albedo

    def camera_position_km(self, altitude_m: float) -> tuple[float, float, float]:
        return camera_position_km(self._layer.params, altitude_m)

    def aerial_perspective(self, radius_km: float, lights: AirLights):
        return self._layer.sky.aerial_perspective(radius_km, lights)
