"""Planets Mercury-Neptune: VSOP87D positions (light-time corrected) and magnitudes.

Heliocentric ecliptic coordinates of date come from the VSOP87D series truncated per
planet in ``tools/build_astro_tables.py`` (heliocentric truncation error 1-3.5" over
1800-2200). The geocentric astrometric position is P(t - tau) - E(t) with the light time
tau iterated twice (Meeus ch. 33); aberration and nutation are applied by
:mod:`skydome.astro.observer`.

Apparent V magnitudes follow Mallama & Hilton (2018), "Computing apparent planetary
magnitudes for The Astronomical Almanac", Astronomy and Computing 25, 10-24, eqs. for
each planet's main phase curve (the small secondary corrections for Mars' orbital
longitude, Uranus' sub-latitude and Jupiter/Saturn at very large phase angles are not
applied; they are < 0.1 mag for Earth-based observers). Saturn includes its rings
through the ring tilt B computed from Meeus ch. 45.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from skydome.astro import frames
from skydome.astro._series import segment_memo, smooth, vsop
from skydome.astro.frames import C_AU_PER_DAY
from skydome.astro.sun import earth_heliocentric_ecliptic
from skydome.astro.time import julian_centuries
from skydome.errors import ParameterError

__all__ = [
    "PLANETS",
    "planet_heliocentric_ecliptic",
    "planet_geocentric_ecliptic",
    "planet_magnitude",
    "saturn_ring_tilt",
]

PLANETS = ("mercury", "venus", "mars", "jupiter", "saturn", "uranus", "neptune")


def _check(planet: str) -> str:

    p = str(planet).lower()
    if p not in PLANETS:
        raise ParameterError(f"planet = {planet!r} is not one of {', '.join(PLANETS)}")
    return p


def planet_heliocentric_ecliptic(planet: str, jd_tt: Any) -> np.ndarray:
    """Heliocentric position (au), mean ecliptic and equinox of date, (..., 3)."""
    p = _check(planet)
    jd = np.asarray(jd_tt, dtype=float)
    # 8-day segments of degree 12: the fastest planet (Mercury, 88 d) interpolates to
    # < 1e-4" (tested).
    lon, lat, r = smooth(vsop(p).lbr, jd, 8.0, 12, memo=segment_memo(f"{p} lbr"))
    return frames.spherical_to_cartesian(lon, lat, r).reshape(jd.shape + (3,))


def planet_geocentric_ecliptic(
    planet: str, jd_tt: Any, earth: np.ndarray | None = None, iterations: int = 2
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Geocentric astrometric position (au) of a planet corrected for light time, mean
    ecliptic of date; returns ``(geo, helio_at_emission, tau_days)``.

    ``earth``: the Earth's heliocentric ecliptic position at ``jd_tt`` if already known.
    """
    jd = np.asarray(jd_tt, dtype=float)
    e = earth_heliocentric_ecliptic(jd) if earth is None else earth
    helio = planet_heliocentric_ecliptic(planet, jd)
    tau = np.linalg.norm(helio - e, axis=-1) / C_AU_PER_DAY
    for _ in range(iterations):
        helio = planet_heliocentric_ecliptic(planet, jd - tau)
        tau = np.linalg.norm(helio - e, axis=-1) / C_AU_PER_DAY
    return helio - e, helio, tau


def saturn_ring_tilt(geo_ecl_of_date: np.ndarray, jd_tt: Any) -> np.ndarray:
    """Saturnicentric latitude B (rad) of the Earth referred to the ring plane (Meeus
    eq. 45.3), from Saturn's geocentric ecliptic vector of date."""
    t = julian_centuries(jd_tt)
    inc = np.radians(28.075216 - 0.012998 * t + 0.000004 * t * t)
    node = np.radians(169.508470 + 1.394681 * t + 0.000412 * t * t)
    lam, beta, _ = frames.cartesian_to_spherical(geo_ecl_of_date)
    sb = np.sin(inc) * np.cos(beta) * np.sin(lam - node) - np.cos(inc) * np.sin(beta)
    return np.arcsin(np.clip(sb, -1.0, 1.0))


def planet_magnitude(planet: str, r_au, delta_au, phase_angle_rad, ring_tilt_rad=0.0) -> np.ndarray:
    """Apparent V magnitude (Mallama & Hilton 2018).

    ``r_au``: Sun-planet distance, ``delta_au``: observer-planet distance,
    ``phase_angle_rad``: Sun-planet-observer angle, ``ring_tilt_rad``: Saturn's B.
    """
    p = _check(planet)
    r = np.asarray(r_au, dtype=float)
    d = np.asarray(delta_au, dtype=float)
    a = np.degrees(np.asarray(phase_angle_rad, dtype=float))
    dist = 5.0 * np.log10(r * d)
    if p == "mercury":  # eq. 2
        v = np.polyval(
            [-3.0334e-12, 1.6893e-9, -3.4265e-7, 3.3644e-5, -1.6336e-3, 6.3280e-2, -0.613], a
        )
    elif p == "venus":  # eqs. 3-4
        small = np.polyval([8.938e-9, -2.814e-6, 3.687e-4, -1.044e-3, -4.384], a)
        large = np.polyval([8.39034e-3, -2.81914, 236.05828], a)
        v = np.where(a <= 163.7, small, large)
    elif p == "mars":  # eqs. 6-7
        v = np.where(
            a <= 50.0,
            np.polyval([-1.302e-4, 2.267e-2, -1.601], a),
            np.polyval([3.445e-4, -2.573e-2, -0.367], a),
        )
    elif p == "jupiter":  # eqs. 8-9
        x = a / 180.0
        big = 1.0 - 1.507 * x - 0.363 * x**2 - 0.062 * x**3 + 2.809 * x**4 - 1.876 * x**5
        v = np.where(
            a <= 12.0,
            np.polyval([6.16e-4, -3.7e-4, -9.395], a),
            -9.428 - 2.5 * np.log10(np.maximum(big, 1e-6)),
        )
    elif p == "saturn":  # eq. 10 (globe and rings; used at all phase angles)
        sb = np.abs(np.sin(np.asarray(ring_tilt_rad, dtype=float)))
        v = -8.914 - 1.825 * sb + 0.026 * a - 0.378 * sb * np.exp(-2.25 * a)
    elif p == "uranus":  # eq. 12 without the sub-latitude term
        v = np.polyval([1.045e-4, 6.587e-3, -7.110], a)
    else:  # neptune, eq. 14 (after 2000)
        v = np.polyval([9.617e-5, 7.944e-3, -7.00], a)
    return v + dist
