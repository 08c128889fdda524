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

import math

import numpy as np

from skydome.astro.eclipses import sky_sunlit_weight, sun_visible_at
from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.atmosphere.precomputed import PrecomputedSky, camera_position_km
from skydome.atmosphere.presets import preset
from skydome.atmosphere.single import SingleScatteringSky
from skydome.atmosphere.sky_view import check_sky_view_size
from skydome.core.basis import SpectralBasis
from skydome.core.layer import DrawContext, Layer, LayerHost
from skydome.core.lights import SkyState
from skydome.core.services import AirLights, AirService, EclipseSkyInputs, LookupTables
from skydome.errors import ParameterError, check_choice
from skydome.gpu.shared import SharedResource
from skydome.gpu.textures import release_all
from skydome.physics.constants import AU_KM
from skydome.physics.geometry import elevation_deg
from skydome.spectra import solar_luminance

#: The models that draw the air.
MODELS = ("precomputed", "single")


#: The Moon's light on the air is left out (its sky-view table not re-aimed, nothing drawn
#: for it) while the Sun's airless elevation is at least this (deg) and the Moon gives less
#: than MOON_OUTSHONE_RATIO of the Sun's illuminance (the full Moon gives ~2.5e-6 of it): the
#: moonlit sky then adds < 1e-5 of the sunlit one at any pixel of sky or ground (measured,
#: a Moon 34 deg up, 4 days past full: 7.7e-6 at Sun 2.4 deg, 2.9e-6 at 7 deg; checked
#: < 1e-4 in tests/test_time_steps.py), far below an 8-bit step; the clouds and the ground
#: see the same lights. During a solar eclipse the Moon's light is kept.
MOON_OUTSHONE_ABOVE_DEG = 2.0
MOON_OUTSHONE_RATIO = 1e-4


def _outshone(moon, sun) -> bool:
    """Whether the Sun's light makes the Moon's on the air negligible (see above)."""
    return (
        elevation_deg(sun.direction_true) >= MOON_OUTSHONE_ABOVE_DEG
        and moon.illuminance_lux < MOON_OUTSHONE_RATIO * sun.illuminance_lux
    )


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
        self._holder: SharedResource | None = None  # self.sky, shared with fresh() copies
        self._donor: SharedResource | None = None
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
        donor, self._donor = self._donor, None
        if self.sky is None and donor is not None and donor.serves(host.ctx):
            self._holder, self.sky = donor, donor.take()
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
                self._holder = SharedResource(self.sky, host.ctx)
        output = "rgbs" if self.model == "single" else self.sky.config.output
        self.spectral_basis = SpectralBasis.for_wavelengths(self.sky.wavelengths_nm, output)

    def fresh(self) -> AtmosphereLayer:
        """A new layer with this one's arguments (``Layer.fresh``) that, once prepared on
        the same context, shares this one's precomputed sky: its tables, compiled passes
        and sky-view tables, which a new instant then re-aims only as far as the lights
        moved (``SkyViewTables.still_aimed``): ``Sky.at`` makes no shader and no table
        anew. The last layer of the set to be released frees it."""
        layer = super().fresh()
        if self._holder is not None and self.model == "precomputed" and self.cache:
            layer._donor = self._holder
            layer._last_sun = self._last_sun  # the Sun's table, kept while it is dark
        return layer

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
        if (
            self.moonlight and moon is not None and self.model == "precomputed"
            and not (state.solar_eclipse is None and _outshone(moon, sun))
        ):  # fmt: skip
            ratio = moon.illuminance_lux / self._solar_lux() / self.params.solar_scale
            moon_direction = tuple(float(v) for v in moon.direction_true)
            moon_scale = tuple(float(v) for v in ratio * self._moon_tint(moon))
        sun_scale = (AU_KM / sun.distance_km) ** 2  # the tables hold the Sun at 1 au
        eclipse = None
        if state.solar_eclipse is not None and self.model == "precomputed":
            # The clouds and the ground get the eclipsed Sun; the sky passes weigh the
            # uneclipsed Sun's light per direction (atmosphere/eclipse_sky.glsl).
            ecl = state.solar_eclipse
            per_direction, correction = eclipse_sky_mode(
                self.params, ecl, sun.direction_true, sun.angular_radius_rad, state.ground_m
            )
            if per_direction:
                eclipse = EclipseSkyInputs(
                    u_eclipse_moon_km=tuple(float(v) for v in ecl.moon_km),
                    u_eclipse_moon_radius_km=float(ecl.moon_radius_km),
                    u_eclipse_sun_radius=float(sun.angular_radius_rad),
                    u_eclipse_sky_scale=sun_scale * correction,
                    u_eclipse_air=eclipse_air(self.params),
                    u_eclipse_channels=eclipse_channels(self.spectral_basis),
                )
            sun_scale *= ecl.visible_fraction
        elif state.solar_eclipse is not None:
            sun_scale *= state.solar_eclipse.visible_fraction
        if state.lunar_eclipse is not None and moon_direction is not None:
            moon_scale = tuple(v * state.lunar_eclipse.moon_light_factor for v in moon_scale)
        self._lights = AirLights(
            sun_direction=tuple(float(v) for v in direction),
            sun_scale=sun_scale,
            moon_direction=moon_direction,
            moon_scale=moon_scale,
            eclipse=eclipse,
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
        eclipse = None if elevation_deg(lights.sun_direction) < dark else lights.eclipse
        return AirLights(sun, scale, moon, moon_scale, eclipse)

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
            holder, self._holder = self._holder, None
            if holder is None:
                self.sky.release()
            else:
                holder.drop()
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


def eclipse_air(params) -> tuple[float, float, float, float]:
    """The air's extinction for a solar eclipse's sky weights (``atmosphere/eclipse_sky.glsl``):
    Rayleigh scattering (1/km) at the ground and its scale height (km), aerosol extinction
    (1/km) and its scale height (km), at 550 nm, the heights fitted over the lowest 4 km
    (Rayleigh) and 1 km (aerosol) of the params' density profiles."""
    c = params.coefficients(np.array([550.0]))

    def fit(profile, beta, height_m):
        rho0 = float(profile.density(0.0))
        rho1 = float(profile.density(height_m))
        h = height_m / math.log(rho0 / rho1) if rho0 > rho1 > 0 else 8000.0
        return float(beta) * rho0 * 1000.0, h / 1000.0

    br, hr = fit(params.rayleigh_density, c["rayleigh_scattering"][0], 4000.0)
    bm, hm = fit(params.mie_density, c["mie_extinction"][0], 1000.0)
    return (br, hr, bm, hm)


#: Effective wavelengths (nm) of the R, G, B and scotopic channels for the eclipse's weights.
RGBS_EFFECTIVE_NM = (612.0, 549.0, 465.0, 507.0)


def eclipse_channels(basis: SpectralBasis) -> tuple[float, float, float, float]:
    """Rayleigh extinction of each output channel relative to 550 nm's (lambda^-4), for the
    eclipse's sky weights: the effective wavelengths of R, G, B and the scotopic channel, or
    the spectral basis's own 4 wavelengths."""
    wl = RGBS_EFFECTIVE_NM if basis.output == "rgbs" else tuple(basis.wavelengths_nm[:4])
    return tuple(float((550.0 / w) ** 4) for w in wl)


#: Directions (unit ENU) where :func:`eclipse_sky_mode` samples the sky's weights: the
#: zenith and elevations 1, 5, 15 and 40 deg at 8 azimuths.
_MODE_DIRS = np.array(
    [[0.0, 0.0, 1.0]]
    + [
        [math.cos(e) * math.sin(a), math.cos(e) * math.cos(a), math.sin(e)]
        for e in np.radians([1.0, 5.0, 15.0, 40.0])
        for a in np.radians(np.arange(0.0, 360.0, 45.0))
    ]
)
#: Relative spread of the sky's weights below which a solar eclipse's sky is scaled as a
#: whole (no per-direction pass): 5 % of the sky's light, at the horizon, is hardly seen;
#: at Dallas on 2024-04-08 the sky is weighed per direction from 18:28 to 19:02 UTC
#: (totality 18:40:47-18:44:44), each frame then costing ~7x an ordinary one on llvmpipe.
UNIFORM_SKY_TOLERANCE = 0.05


def eclipse_sky_mode(params, eclipse, sun_direction, sun_radius_rad, ground_m=0.0):
    """How a solar eclipse dims the sky: ``(per_direction, correction)``.

    Far from the Moon's umbra (most of a partial eclipse) every view ray's air sees the same
    part of the Sun as the observer: the sky is the uneclipsed one times the limb-darkened
    visible fraction, like the direct sunlight (``per_direction`` False). Where the sky's
    weights (``skydome.astro.eclipses.sky_sunlit_weight``, uniform disks) at a few
    directions differ from the observer's uniform-disk fraction by more than
    UNIFORM_SKY_TOLERANCE, the sky passes weigh each direction
    (``atmosphere/eclipse_sky.glsl``); ``correction`` = the limb-darkened fraction over the
    uniform one (faded to 1 towards totality) keeps the two modes continuous where they
    meet."""
    bottom = params.bottom_radius_m / 1000.0
    top = params.top_radius_m / 1000.0
    r_km = bottom + max(float(ground_m), 0.0) / 1000.0
    args = (eclipse.moon_km, eclipse.moon_radius_km, sun_direction, sun_radius_rad)
    weights = sky_sunlit_weight(r_km, _MODE_DIRS, *args, eclipse_air(params), bottom, top)
    uniform = float(sun_visible_at(np.zeros(3), *args))
    spread = float(np.max(np.abs(weights - uniform)))
    if spread <= UNIFORM_SKY_TOLERANCE * max(uniform, 1e-9):
        return False, 1.0
    # the limb-darkened over the uniform fraction, faded to 1 as the Sun's last 2 % goes
    ratio = eclipse.visible_fraction / uniform if uniform > 0.0 else 1.0
    correction = 1.0 + (np.clip(ratio, 0.25, 4.0) - 1.0) * min(uniform / 0.02, 1.0)
    return True, float(correction)
