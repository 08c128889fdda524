"""Illuminance on the ground at a place and time (or under an abstract Sun), a solar
eclipse included.

Without an eclipse this is :func:`skydome.atmosphere.illuminance.horizontal_illuminance` at
the place's ground, the Sun at its true distance: the sky lit from the Sun's airless
elevation, the direct beam along the refracted ray (the apparent elevation's path and
cosine), dimmed as refraction flattens the disk, as the renderer draws it. In a solar eclipse
(``skydome.scene.eclipses``), the direct sunlight is the uneclipsed part of the Sun's
limb-darkened flux, and the sky's light is the renderer's: the uneclipsed Sun's sky
radiance times, per direction, the sunlit weight of the view ray
(``skydome.astro.eclipses.sky_sunlit_weight``, the float64 twin of the sky passes'
``atmosphere/eclipse_sky.glsl``), or, far from the umbra, the uneclipsed sky times the
visible fraction (``skydome.atmosphere.layer.eclipse_sky_mode``, as the renderer). The
diffuse illuminance is the uneclipsed one times the ratio of the two skies'
cosine-weighted integrals over the upper hemisphere (Gauss-Legendre
in the sine of the elevation, 48 x 96 directions).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from skydome.astro.eclipses import sky_sunlit_weight
from skydome.atmosphere import precompute_probe as probe
from skydome.atmosphere.illuminance import horizontal_illuminance
from skydome.atmosphere.layer import RGBS_EFFECTIVE_NM, eclipse_air, eclipse_sky_mode
from skydome.atmosphere.presets import preset
from skydome.atmosphere.tables import shared_tables
from skydome.gpu import shared_context
from skydome.physics.constants import AU_KM, M_PER_KM
from skydome.physics.geometry import elevation_deg
from skydome.physics.refraction import refraction_flattening
from skydome.scene.state import state_at
from skydome.spectra import SRGB_LUMINANCE

__all__ = ["CORONA_FRACTION", "place_illuminance", "state_illuminance"]

#: The corona's irradiance over the Sun's: 2 int_1^inf B(rho) rho drho for Baumbach's B
#: (skydome.astro.eclipses.baumbach_corona).
CORONA_FRACTION = 2e-6 * (0.0532 / 0.5 + 1.425 / 5.0 + 2.565 / 15.0)


def _hemisphere(n_el: int = 48, n_az: int = 96) -> tuple[np.ndarray, np.ndarray]:
    """Directions of the upper hemisphere and their weights for int f cos(zenith) dOmega."""
    x, w = np.polynomial.legendre.leggauss(n_el)
    s = 0.5 * (x + 1.0)  # sin(elevation) = cos(zenith), 0..1
    ws = 0.5 * w
    az = (np.arange(n_az) + 0.5) / n_az * 2.0 * np.pi
    c = np.sqrt(1.0 - s * s)
    dirs = np.stack(
        [
            c[:, None] * np.sin(az)[None, :],
            c[:, None] * np.cos(az)[None, :],
            np.broadcast_to(s[:, None], (n_el, n_az)),
        ],
        axis=-1,
    ).reshape(-1, 3)
    weights = (ws * s)[:, None] * np.full(n_az, 2.0 * np.pi / n_az)[None, :]
    return dirs, weights.ravel()


def place_illuminance(
    observer,
    time: Any,
    *,
    atmosphere: Any = "earth",
    config=None,
    altitude_m: float | None = None,
) -> dict[str, float]:
    """Horizontal illuminance (lx) from the Sun and the sky at ``observer`` (an
    ``skydome.astro.Observer``) and ``time``, with the zenith luminance (cd/m^2), the Sun's
    airless elevation (deg) and ``eclipse_fraction``: the fraction of the Sun's
    limb-darkened luminous flux the Moon hides (0 without an eclipse).

    ``altitude_m``: the height (m) above sea level, the atmosphere's ground, where the light
    is measured; by default the place's ground (its elevation, 0 below sea level), the
    height a render of the place counts from (Paranal's 2635 m hold 27 % less air above
    them than the sea's shore)."""
    return state_illuminance(
        state_at(observer, time), atmosphere=atmosphere, config=config, altitude_m=altitude_m
    )


def state_illuminance(
    state, *, atmosphere: Any = "earth", config=None, altitude_m: float | None = None
) -> dict[str, float]:
    """:func:`place_illuminance` for the lights of a ``scene.state.SkyState``: a place's at
    an instant, or an abstract Sun's (``abstract_state``: its elevation the apparent one, as
    ``render --sun-elevation`` draws it); ``altitude_m`` by default the state's ground."""
    params = preset(atmosphere) if isinstance(atmosphere, str) else atmosphere
    if altitude_m is None:
        altitude_m = state.ground_m
    sun = state.sun
    sun_el = float(elevation_deg(sun.direction_true))
    sun_scale = (AU_KM / sun.distance_km) ** 2
    # the direct beam along the refracted ray, as the Sun is seen and drawn (its apparent
    # elevation), dimmed as the refraction flattens its disk; the sky lit from the airless
    # direction
    seen_el = float(sun.elevation_deg)
    (res,) = horizontal_illuminance(
        sun_el, altitude_m=altitude_m, atmosphere=params, config=config, sun_scale=sun_scale,
        beam_elevation_deg=seen_el,
        beam_scale=refraction_flattening(seen_el, state.refraction_scale),
    )  # fmt: skip
    out = res.to_dict()
    ecl = state.solar_eclipse
    out["eclipse_fraction"] = 0.0 if ecl is None else float(ecl.hidden_fraction)
    out["sun_distance_au"] = sun.distance_km / AU_KM
    if ecl is None:
        return out
    visible = ecl.visible_fraction
    tables, _ = shared_tables(shared_context(), params, config)
    dirs, weights = _hemisphere()
    # the tables' Sun at the airless azimuth and elevation (as the illuminance probe's)
    sun_dir = np.asarray(sun.direction_true, dtype=np.float64)
    radiance, _ = probe.sky_radiance(tables, dirs, sun_dir, altitude_m=altitude_m)
    r_km = (params.bottom_radius_m + altitude_m) / M_PER_KM
    channels = [(550.0 / w) ** 4 for w in RGBS_EFFECTIVE_NM[:3]]
    weight = sky_sunlit_weight(
        r_km, dirs, ecl.moon_km, ecl.moon_radius_km, sun_dir, sun.angular_radius_rad,
        eclipse_air(params), params.bottom_radius_m / M_PER_KM, params.top_radius_m / M_PER_KM,
        channels=channels,
    )  # fmt: skip
    lum_full = radiance[:, :3] @ SRGB_LUMINANCE
    lum_ecl = (radiance[:, :3] * weight) @ SRGB_LUMINANCE
    full = float(np.sum(lum_full * weights))
    per_direction, correction = eclipse_sky_mode(
        params, ecl, sun_dir, sun.angular_radius_rad, state.ground_m
    )
    if per_direction:  # as the renderer: the sky per direction, or scaled as a whole
        ratio = float(np.sum(lum_ecl * weights)) / full * correction if full > 0 else visible
    else:
        ratio = visible
    zenith = sky_sunlit_weight(
        r_km, np.array([0.0, 0.0, 1.0]), ecl.moon_km, ecl.moon_radius_km, sun_dir,
        sun.angular_radius_rad, eclipse_air(params), params.bottom_radius_m / M_PER_KM,
        params.top_radius_m / M_PER_KM,
    )  # fmt: skip
    zenith = float(zenith) * correction if per_direction else visible
    # The corona (Baumbach's profile integrated over rho >= 1: 1.125e-6 of the Sun's
    # irradiance) shows whenever the Moon covers part of the disk, as in the renderer.
    direct = out["direct_horizontal_lux"] * (visible + CORONA_FRACTION)
    diffuse = out["diffuse_horizontal_lux"] * ratio
    out.update(
        direct_horizontal_lux=direct,
        diffuse_horizontal_lux=diffuse,
        total_horizontal_lux=direct + diffuse,
        zenith_luminance_cd_m2=out["zenith_luminance_cd_m2"] * zenith,
        total_horizontal_scotopic_lux=out["total_horizontal_scotopic_lux"]
        * (direct + diffuse)
        / max(res.total_horizontal_lux, 1e-300),
        zenith_scotopic_luminance=out["zenith_scotopic_luminance"] * zenith,
        sky_eclipse_ratio=ratio,
    )
    return out
