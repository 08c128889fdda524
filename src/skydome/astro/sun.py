"""The Sun (and the Earth's heliocentric position) from VSOP87.

The Earth's heliocentric ecliptic coordinates of date come from the VSOP87D series
(Bretagnon & Francou 1988) truncated as described in ``tools/build_astro_tables.py``
(191 terms; 0.27" max in longitude against the complete series, 1800-2200); Meeus,
*Astronomical Algorithms* ch. 25 "higher accuracy" and ch. 32. The Sun's geocentric
geometric position is minus the Earth's heliocentric one (the Sun's motion about the
barycentre during the 8.3 min light time, < 0.01", is neglected).

Apparent positions add nutation and the annual aberration computed from the Earth's
velocity (first order in v/c), which for the Sun equals the classical -20.4898"/R of
Meeus eq. 25.10 but also holds for the planets and the Moon.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from skydome.astro import frames
from skydome.astro._series import segment_memo, smooth, vsop
from skydome.astro.frames import ARCSEC, AU_KM
from skydome.astro.time import julian_centuries

__all__ = [
    "SUN_SEMIDIAMETER_1AU_ARCSEC",
    "SUN_RADIUS_KM",
    "earth_heliocentric_lbr",
    "earth_heliocentric_ecliptic",
    "earth_heliocentric_state",
    "earth_position_au",
    "sun_geocentric_mean_of_date",
    "sun_apparent_geocentric",
    "sun_angular_diameter",
]

SUN_SEMIDIAMETER_1AU_ARCSEC = 959.63  # Auwers' value, Meeus ch. 55 / Astronomical Almanac
SUN_RADIUS_KM = SUN_SEMIDIAMETER_1AU_ARCSEC * ARCSEC * AU_KM  # 696,000 km (photosphere)

# Meeus eq. 32.3: conversion of VSOP87 (dynamical equinox) to the FK5 system. Measured
# against skyfield (ICRS, IAU 2006/2000A), applying it makes the Sun worse (RMS 0.18" instead
# of 0.14" over 1900-2050), as IAU 2006 precession-nutation refers to the dynamical equinox; it is
# therefore off by default and kept for reproducing Meeus' worked examples.
APPLY_FK5_CORRECTION = False


def _jd(jd_tt: Any) -> np.ndarray:
    return np.asarray(getattr(jd_tt, "jd_tt", jd_tt), dtype=float)


def _fk5(lbr: np.ndarray, jd: np.ndarray) -> np.ndarray:
    """Apply Meeus eq. 32.3 to heliocentric (L, B, R) rows (rad)."""
    t = julian_centuries(jd)
    lp = lbr[0] - np.radians(1.397 * t + 0.00031 * t * t)
    dl = -0.09033 + 0.03916 * (np.cos(lp) + np.sin(lp)) * np.tan(lbr[1])
    db = 0.03916 * (np.cos(lp) - np.sin(lp))
    out = lbr.copy()
    out[0] += dl * ARCSEC
    out[1] += db * ARCSEC
    return out


# The Earth's series' interpolation (_series.smooth): shortest significant period ~15 d (lunar
# terms): 16-day segments of degree 12 interpolate to < 1e-4" (tested; the floor is the
# 40-us resolution of a float64 Julian Date).
_EARTH_SEGMENTS = (16.0, 12)


def earth_heliocentric_lbr(jd_tt: Any, fk5: bool | None = None) -> np.ndarray:
    """Heliocentric ecliptic L, B (rad, L not wrapped) and R (au) of the Earth, mean
    ecliptic and equinox of date (VSOP87D); shape ``(3,) + jd_tt.shape``.

    ``fk5``: apply Meeus eq. 32.3 (default: ``APPLY_FK5_CORRECTION``).
    """
    jd = _jd(jd_tt)
    lbr = smooth(vsop("earth").lbr, jd, *_EARTH_SEGMENTS, memo=segment_memo("earth lbr"))
    if APPLY_FK5_CORRECTION if fk5 is None else fk5:
        lbr = _fk5(lbr, jd.ravel())
    return lbr.reshape((3,) + jd.shape)


def earth_heliocentric_ecliptic(jd_tt: Any, fk5: bool | None = None) -> np.ndarray:
    """Heliocentric position of the Earth (au), mean ecliptic of date axes, (..., 3)."""
    lon, lat, r = earth_heliocentric_lbr(jd_tt, fk5)
    return frames.spherical_to_cartesian(lon, lat, r)


def earth_heliocentric_state(jd_tt: Any, fk5: bool | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Heliocentric position (au) and velocity (au/day) of the Earth, mean ecliptic of date
    axes, each (..., 3), from one evaluation of the series.

    The position is :func:`earth_heliocentric_ecliptic`'s (every term); the velocity takes
    the terms that matter to it (``frames._earth_rate_terms``) as
    ``frames._earth_velocity_ecliptic_of_date`` does. Both come from the same phasors,
    interpolated together where that is cheaper (the position's segments).
    """
    jd = _jd(jd_tt)
    series, keep = vsop("earth"), frames._earth_rate_terms()
    every = np.ones_like(keep)
    lbr6 = smooth(
        lambda x: series.lbr_rates(x, keep, every),
        jd,
        *_EARTH_SEGMENTS,
        memo=segment_memo("earth state"),
    )
    velocity = frames.velocity_from_lbr_rates(lbr6)
    lbr = lbr6[:3]
    if APPLY_FK5_CORRECTION if fk5 is None else fk5:
        lbr = _fk5(lbr, jd.ravel())
    position = frames.spherical_to_cartesian(*lbr)
    return position.reshape(jd.shape + (3,)), velocity.reshape(jd.shape + (3,))


def earth_position_au(jd_tt: Any) -> np.ndarray:
    """Heliocentric position of the Earth (au) in J2000 mean equatorial axes, (..., 3)."""
    jd = _jd(jd_tt)
    m = frames.ecliptic_of_date_to_j2000_matrix(jd)
    return np.einsum("...ij,...j->...i", m, earth_heliocentric_ecliptic(jd))


def sun_geocentric_mean_of_date(jd_tt: Any) -> np.ndarray:
    """Geometric geocentric position of the Sun (au), mean equator and equinox of date."""
    jd = _jd(jd_tt)
    ecl = -earth_heliocentric_ecliptic(jd)
    return np.einsum("...ij,...j->...i", frames.rot_x(-frames.mean_obliquity(jd)), ecl)


def sun_apparent_geocentric(jd_tt: Any) -> dict[str, np.ndarray]:
    """Apparent geocentric place of the Sun, true equator/ecliptic and equinox of date.

    ``jd_tt``: Julian Date(s) TT or a :class:`~skydome.astro.time.Time`. Returns a dict of
    arrays shaped like ``jd_tt``: ``ra``, ``dec``, ``lon``, ``lat`` (rad), ``distance_au``
    (true geometric distance), ``angular_diameter`` (rad).
    """
    jd = _jd(jd_tt)
    eps_a = frames.mean_obliquity(jd)
    dpsi, deps = frames.nutation_angles(jd)
    earth, v_ecl = earth_heliocentric_state(jd)
    to_mean_equator = frames.rot_x(-eps_a)
    g = np.einsum("...ij,...j->...i", to_mean_equator, -earth)  # geocentric Sun, au
    r = np.linalg.norm(g, axis=-1)
    v = np.einsum("...ij,...j->...i", to_mean_equator, v_ecl)
    u = frames.aberrate(g / r[..., None], v)
    u = np.einsum("...ij,...j->...i", frames.nutation_matrix_from_angles(eps_a, dpsi, deps), u)
    ra, dec, _ = frames.cartesian_to_spherical(u)
    lon, lat = frames.equatorial_to_ecliptic(ra, dec, eps_a + deps)
    return {
        "ra": ra,
        "dec": dec,
        "lon": lon,
        "lat": lat,
        "distance_au": r,
        "angular_diameter": sun_angular_diameter(r * AU_KM),
    }


def sun_angular_diameter(distance_km: Any) -> np.ndarray:
    """Angular diameter (rad) of the Sun's photosphere seen from ``distance_km``."""
    d = np.asarray(distance_km, dtype=float)
    return 2.0 * np.arcsin(np.minimum(SUN_RADIUS_KM / d, 1.0))
