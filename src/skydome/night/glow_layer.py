"""The sky-glow layers: airglow and zodiacal light (space stage) and light pollution (volume
stage, after the atmosphere), and the zenith brightness of each for reports.

>>> from skydome import Sky
>>> from skydome.night import AirglowLayer, ZodiacalLightLayer, LightPollutionLayer, City
>>> sky = Sky("Valletta", "2018-03-01T23:00Z", extra_layers=[
...     AirglowLayer(), ZodiacalLightLayer(),
...     LightPollutionLayer.from_bortle(8, cities=[City(300, 20, 400_000)])])

Their GLSL is ``shaders/night/airglow.glsl``, ``zodiacal_light.glsl`` and
``light_pollution.glsl``; the float64 formulas are in ``skydome.night.airglow``,
``.zodiacal`` and ``.light_pollution``. In the abstract mode (no place or time) the layers
draw nothing (the light-pollution layer passes what lies behind it through unchanged).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skydome.astro.photometry import mag_to_optical_depth, mag_to_s10
from skydome.core.basis import SpectralBasis
from skydome.core.cameras import CameraInputs
from skydome.core.layer import BehindInputs, DrawContext, Layer
from skydome.core.lights import SkyState
from skydome.core.refraction_table import AirlessTableInputs, RefractionTable
from skydome.errors import check_range
from skydome.gpu.inputs import ShaderInputs
from skydome.night import airglow as ag
from skydome.night import light_pollution as lp
from skydome.night import zodiacal as zl
from skydome.physics.packing import mat3
from skydome.physics.refraction import horizon_dip_sin
from skydome.spectra import SRGB_LUMINANCE, conversion_matrix
from skydome.spectra.tables import photopic_efficiency, solar_irradiance


def _solar_luminance(basis: SpectralBasis) -> float:
    """Photopic luminance (cd/m^2) of transfer values of 1 at every wavelength (the tabulated
    solar spectrum), in the basis's own RGBS conversion."""

    wl = basis.wavelengths_nm
    return float(SRGB_LUMINANCE @ (conversion_matrix(wl, "rgbs") @ np.ones(len(wl)))[:3])


def _reddened_luminance_ratio(elongation_deg: float) -> float:
    """Luminance of the reddened zodiacal spectrum over the solar one at equal 500 nm
    radiance (1 nm integration with the CIE V(lambda))."""

    g = np.arange(360.0, 831.0, 1.0)
    sun = solar_irradiance(g) * photopic_efficiency(g)
    return float(sun @ zl.reddening(g, elongation_deg) / sun.sum())


def _linear_texture(ctx, data: np.ndarray):
    """A float32 texture of ``data`` (rows, columns, channels), filtered bilinearly and
    clamped at its edges."""
    data = np.ascontiguousarray(data, dtype="f4")
    tex = ctx.texture((data.shape[1], data.shape[0]), data.shape[2], data.tobytes(), dtype="f4")
    tex.filter = (ctx.LINEAR, ctx.LINEAR)
    tex.repeat_x = tex.repeat_y = False
    return tex


def _vec4(v) -> tuple[float, float, float, float]:
    return tuple(float(x) for x in np.asarray(v, dtype=np.float64).ravel()[:4])


@dataclass(frozen=True)
class AirglowInputs(ShaderInputs):
    """``night/airglow.glsl``: the zenith airglow (cd/m^2 per output channel), the squared
    ratio of the observer's radius to the layer's, the sine of the horizon's dip."""

    u_airglow_zenith: tuple[float, float, float, float]
    u_radius_ratio_sq: float
    u_dip_sin: float


@dataclass(frozen=True)
class ZodiacalInputs(ShaderInputs):
    """``night/zodiacal_light.glsl``: where the table's nodes lie in texture coordinates, the
    ENU -> helio-ecliptic matrix (column-major), the light's colour near and far from the
    Sun (per S10), the table of Leinert et al. 1998 (a texture)."""

    u_grid_map: tuple[float, float, float, float]
    u_enu_to_helioecliptic: tuple[float, ...]
    u_colour_near: tuple[float, float, float, float]
    u_colour_far_minus_near: tuple[float, float, float, float]
    u_zodiacal_grid: object


@dataclass(frozen=True)
class LightPollutionInputs(ShaderInputs):
    """``night/light_pollution.glsl``: the artificial zenith glow and its colour, the slab's
    optical depth, the horizon's dip, the cities (direction east/north, luminance at 45 deg)
    and the shape constants of their glows."""

    u_lp_zenith: tuple[float, float, float, float]
    u_lp_colour: tuple[float, float, float, float]
    u_tau: float
    u_dip_sin: float
    u_num_cities: int
    u_city: list[float]
    u_kappa: float
    u_eta: float


class AirglowLayer(Layer):
    """The airglow: ``zenith_s10`` (S10, V) at solar minimum, or ``zenith_mag_arcsec2``
    instead, scaled by the solar-cycle factor for ``solar_flux_sfu`` (10.7 cm flux, sfu;
    default 80, solar minimum) and brightened to the horizon by the van Rhijn factor for a
    layer at ``height_m``."""

    name = "airglow"
    stage = "space"
    #: The van Rhijn brightening varies over degrees (scene.graph may draw it reduced).
    smooth_deg = 2.0
    shader = "night/airglow.glsl"

    def __init__(
        self,
        zenith_s10: float = ag.AIRGLOW_ZENITH_S10,
        *,
        zenith_mag_arcsec2: float | None = None,
        solar_flux_sfu: float = ag.SOLAR_MINIMUM_SFU,
        height_m: float = ag.AIRGLOW_HEIGHT_M,
        enabled: bool = True,
    ):
        super().__init__(enabled=enabled)
        if zenith_mag_arcsec2 is not None:
            m = check_range("zenith_mag_arcsec2", zenith_mag_arcsec2, 15.0, 30.0, "mag/arcsec^2")
            zenith_s10 = float(mag_to_s10(m))
        self.zenith_s10, self.solar_flux_sfu = ag.check_airglow_parameters(
            zenith_s10, solar_flux_sfu
        )

        self.height_m = check_range("airglow height_m", height_m, 50_000.0, 300_000.0, "m")
        self._colour = None
        self._active = False

    def zenith_luminance(self) -> float:
        """The zenith airglow above the air (cd/m^2)."""
        return float(
            ag.s10_to_luminance(ag.airglow_zenith_s10(self.zenith_s10, self.solar_flux_sfu))
        )

    def colour(self, basis: SpectralBasis) -> np.ndarray:
        """Output channels per cd/m^2 of airglow in ``basis``."""
        if self._colour is None or self._colour[0] is not basis:
            f = ag.airglow_relative_spectrum(basis.wavelengths_nm)
            self._colour = (basis, basis.colour(f))
        return self._colour[1]

    def update(self, state: SkyState) -> None:
        self._active = state.observer is not None

    def draw(self, frame: DrawContext) -> None:
        if not self._active:
            return
        r_obs = ag.EARTH_RADIUS_M + max(frame.altitude_m, 0.0)
        r_layer = ag.EARTH_RADIUS_M + self.height_m
        if r_obs >= r_layer:
            return  # a camera above the layer: not modelled
        inputs = AirglowInputs(
            u_airglow_zenith=_vec4(self.zenith_luminance() * self.colour(frame.basis)),
            u_radius_ratio_sq=(r_obs / r_layer) ** 2,
            u_dip_sin=horizon_dip_sin(frame.altitude_m),
        )
        fpass = self.full_screen_pass(
            frame.ctx, self.shader, (CameraInputs, AirglowInputs), frame.camera
        )
        fpass.draw(frame.fbo, frame.view, inputs)

    def info(self) -> dict:
        return {"airglow_zenith_mag": float(ag.luminance_to_mag(self.zenith_luminance()))}


class ZodiacalLightLayer(Layer):
    """The zodiacal light of Leinert et al. 1998 table 17, placed by the observer's ecliptic
    and the Sun's ecliptic longitude at the state's time; ``scale`` multiplies it."""

    name = "zodiacal_light"
    stage = "space"
    #: Leinert's table has nodes 5-15 deg apart (scene.graph may draw it reduced).
    smooth_deg = 1.0
    shader = "night/zodiacal_light.glsl"

    def __init__(self, *, scale: float = 1.0, enabled: bool = True):

        super().__init__(enabled=enabled)
        self.scale = check_range("zodiacal scale", scale, 0.0, 100.0)
        self._texture = None
        self._matrix = None
        self._key = None
        self._colours = None
        self._refraction = 1.0
        self._refraction_table = RefractionTable()

    def prepare(self, graph) -> None:
        super().prepare(graph)
        if self._texture is None:
            self._texture = _linear_texture(graph.ctx, zl.zodiacal_grid())

    def colours(self, basis: SpectralBasis) -> tuple[np.ndarray, np.ndarray]:
        """Channels per cd/m^2 of solar-type light of equal 500 nm radiance, reddened as at
        elongation 30 deg (near) and 90 deg (far)."""
        if self._colours is None or self._colours[0] is not basis:
            y_sun = _solar_luminance(basis)
            wl = basis.wavelengths_nm
            out = [
                basis.to_output @ zl.zodiacal_relative_spectrum(wl, e) / y_sun
                for e in zl.REDDENING_ELONGATION_DEG
            ]
            self._colours = (basis, tuple(out))
        return self._colours[1]

    def update(self, state: SkyState) -> None:
        if state.observer is None or state.time is None:
            self._matrix = None
            return
        obs, t = state.observer, state.time
        key = (float(obs.latitude), float(obs.longitude), float(np.ravel(t.jd_tt)[0]))
        if key != self._key:
            self._matrix = zl.helioecliptic_matrix(obs, t)
            self._key = key
        self._refraction = state.refraction_scale

    def draw(self, frame: DrawContext) -> None:
        if self._matrix is None:
            return
        near, far = self.colours(frame.basis)
        nu, nv = zl.GRID_SHAPE
        inputs = ZodiacalInputs(
            # Node i of n at texture coordinate (i + 0.5) / n.
            u_grid_map=((nu - 1) / nu, (nv - 1) / nv, 0.5 / nu, 0.5 / nv),
            u_enu_to_helioecliptic=mat3(self._matrix),
            u_colour_near=_vec4(self.scale * near),
            u_colour_far_minus_near=_vec4(self.scale * (far - near)),
            u_zodiacal_grid=self._texture,
        )
        fpass = self.full_screen_pass(
            frame.ctx, self.shader, (CameraInputs, ZodiacalInputs, AirlessTableInputs),
            frame.camera,
        )  # fmt: skip
        airless = self._refraction_table.inputs(frame.ctx, self._refraction)
        fpass.draw(frame.fbo, frame.view, inputs, airless)

    def release(self) -> None:
        super().release()
        if self._texture is not None:
            self._texture.release()
            self._texture = None
        self._refraction_table.release()


class LightPollutionLayer(Layer):
    """Light pollution (volume stage; put it after the atmosphere layer): writes what lies
    behind plus the artificial glow of ``model`` (a ``LightPollution``), which already holds
    the air's extinction. ``LightPollutionLayer.from_bortle(8)`` and
    ``LightPollutionLayer(zenith_mag_arcsec2=18.2)`` build the model too."""

    name = "light_pollution"
    stage = "volume"
    shader = "night/light_pollution.glsl"

    def __init__(self, model: lp.LightPollution | None = None, *, enabled: bool = True, **kw):
        super().__init__(enabled=enabled)
        self.model = model if model is not None else lp.LightPollution(**kw)
        self._active = False
        self._colour = None

    @classmethod
    def from_bortle(cls, bortle_class: int, **kwargs) -> LightPollutionLayer:
        enabled = kwargs.pop("enabled", True)
        return cls(lp.LightPollution.from_bortle(bortle_class, **kwargs), enabled=enabled)

    def colour(self, basis: SpectralBasis) -> np.ndarray:
        if self._colour is None or self._colour[0] is not basis:
            f = lp.lamp_relative_spectrum(self.model.lamp, basis.wavelengths_nm)
            self._colour = (basis, basis.colour(f))
        return self._colour[1]

    def update(self, state: SkyState) -> None:
        self._active = state.observer is not None

    def draw(self, frame: DrawContext) -> None:
        m = self.model
        colour = self.colour(frame.basis)
        cities = np.zeros((lp.MAX_CITIES, 4))
        n = len(m.cities) if self._active else 0
        for k, (city, l45) in enumerate(zip(m.cities, m.city_luminance_45(), strict=True)):
            a = math.radians(city.azimuth_deg)
            cities[k] = (math.sin(a), math.cos(a), l45, 0.0)
        zenith = m.zenith_cd_m2 if self._active else 0.0
        inputs = LightPollutionInputs(
            u_lp_zenith=_vec4(zenith * colour),
            u_lp_colour=_vec4(colour),
            u_tau=float(mag_to_optical_depth(m.extinction_mag)),
            u_dip_sin=horizon_dip_sin(frame.altitude_m),
            u_num_cities=n,
            u_city=cities.ravel().tolist(),
            u_kappa=lp.CITY_AZIMUTH_KAPPA,
            u_eta=lp.CITY_ELEVATION_ETA,
        )
        fpass = self.full_screen_pass(
            frame.ctx, self.shader, (CameraInputs, BehindInputs, LightPollutionInputs),
            frame.camera,
        )  # fmt: skip
        fpass.draw(frame.fbo, frame.view, self.behind_inputs(frame), inputs)

    def info(self) -> dict:
        return {"light_pollution_zenith_mag": self.model.zenith_mag()}


def zenith_brightness(state: SkyState, layers) -> dict[str, float]:
    """The zenith V brightness (mag/arcsec^2) of each sky-glow layer in ``layers`` for a
    ``state``, keyed by layer name (enabled layers only; inf where one adds nothing): the
    airglow and the zodiacal light above the air, the light pollution as seen from the ground.
    For reports (the CLI)."""
    out: dict[str, float] = {}
    for layer in layers:
        if not getattr(layer, "enabled", True):
            continue
        if isinstance(layer, AirglowLayer):
            lum = layer.zenith_luminance() if state.observer is not None else 0.0
        elif isinstance(layer, ZodiacalLightLayer):
            if state.observer is None or state.time is None:
                lum = 0.0
            else:
                m = zl.helioecliptic_matrix(state.observer, state.time)
                dlon, beta = zl.helioecliptic_coordinates(np.array([0.0, 0.0, 1.0]), m)
                lum = layer.scale * float(zl.zodiacal_luminance(dlon, beta))
                lum *= _reddened_luminance_ratio(float(zl.elongation_deg(dlon, beta)))
        elif isinstance(layer, LightPollutionLayer):
            lum = layer.model.zenith_cd_m2 if state.observer is not None else 0.0
            lum += (
                sum(
                    l45 * float(lp.city_profile(0.0, 0.0, layer.model.extinction_mag))
                    for l45 in layer.model.city_luminance_45()
                )
                if state.observer is not None
                else 0.0
            )
        else:
            continue
        out[layer.name] = float(ag.luminance_to_mag(lum))
    return out
