"""The Moon: ELP2000-82 as truncated by Meeus, *Astronomical Algorithms* ch. 47.

All terms of Meeus' tables 47.A (longitude, distance) and 47.B (latitude) are used, with
the additive terms A1, A2, A3 and the eccentricity factor E (eq. 47.6). Meeus quotes an
accuracy of about 10" in longitude and 4" in latitude; measured against DE421 it is
better (see ``tests/astro/test_vs_skyfield.py``).

The positions are geocentric, referred to the mean ecliptic and equinox of date. The
apparent position adds nutation; annual aberration and the light time cancel to first
order for a geocentric body moving with the Earth, which is handled exactly in
:mod:`skydome.astro.observer` by evaluating the Moon at ``t - tau``.

Phase quantities follow Meeus ch. 48: the phase angle i, the illuminated fraction
k = (1 + cos i) / 2 (eq. 48.1) and the position angle of the bright limb chi (eq. 48.5).
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np

from skydome.astro import frames
from skydome.astro._series import (
    PhasorSums,
    integer_combination_plan,
    smooth,
    tables,
    unit_phasor,
)
from skydome.astro.time import julian_centuries

__all__ = [
    "MOON_RADIUS_KM",
    "moon_ecliptic_of_date",
    "moon_geocentric_mean_of_date",
    "moon_apparent_geocentric",
    "moon_angular_diameter",
    "phase_angle",
    "illuminated_fraction",
    "bright_limb_position_angle",
]

MOON_RADIUS_KM = 1737.4  # IAU/IAG 2015 mean radius
DEG = np.pi / 180.0


def _jd(jd_tt: Any) -> np.ndarray:
    return np.asarray(getattr(jd_tt, "jd_tt", jd_tt), dtype=float)


@functools.cache
def _moon_periodic_sums() -> PhasorSums:
    """Sums of Meeus tables 47.A/47.B from the phasors exp(i(kD D + kM M + kM' M' + kF F)).

    Rows 3q + k, k = |kM| (the power of E the row takes): q = 0 the longitude terms
    sum A sin(arg), q = 1 the distance terms sum A cos(arg), q = 2 the latitude terms
    sum A sin(arg), A sin(x) = Re(-iA exp(ix)). The table is unscaled (1e-6 deg, 1e-3 km).
    """
    tab = tables()
    lr, bt = tab["moon_lr"], tab["moon_b"]
    mult, which = np.unique(np.concatenate([lr[:, :4], bt[:, :4]]), axis=0, return_inverse=True)
    plan = integer_combination_plan(mult.astype(int))
    which = which.ravel()
    n_lr = lr.shape[0]
    k_lr = np.abs(lr[:, 1]).astype(int)
    k_b = np.abs(bt[:, 1]).astype(int)
    return PhasorSums(
        plan,
        np.concatenate([which[:n_lr], which[:n_lr], which[n_lr:]]),
        np.concatenate([-1j * lr[:, 4], lr[:, 5] + 0j, -1j * bt[:, 4]]),
        np.concatenate([k_lr, 3 + k_lr, 6 + k_b]),
        9,
    )


def _moon_direct(jd_tt: np.ndarray) -> np.ndarray:
    """(lambda, beta) in rad (lambda unwrapped) and distance in km; shape (3, N)."""
    t = julian_centuries(np.asarray(jd_tt, dtype=float).ravel())
    # Meeus eq. 47.1-47.5 (degrees)
    lp = 218.3164477 + t * (481267.88123421 + t * (-0.0015786 + t * (1 / 538841 - t / 65194000)))
    d = 297.8501921 + t * (445267.1114034 + t * (-0.0018819 + t * (1 / 545868 - t / 113065000)))
    m = 357.5291092 + t * (35999.0502909 + t * (-0.0001536 + t / 24490000))
    mp = 134.9633964 + t * (477198.8675055 + t * (0.0087414 + t * (1 / 69699 - t / 14712000)))
    f = 93.2720950 + t * (483202.0175233 + t * (-0.0036539 + t * (-1 / 3526000 + t / 863310000)))
    a1 = (119.75 + 131.849 * t) * DEG
    a2 = (53.09 + 479264.290 * t) * DEG
    a3 = (313.45 + 481266.484 * t) * DEG
    e = 1.0 - t * (0.002516 + 0.0000074 * t)  # eq. 47.6
    fund = np.stack([d, m, mp, f]) * DEG  # (4, N)
    lpr, mpr, fr = lp * DEG, mp * DEG, f * DEG

    rows = _moon_periodic_sums()(lambda blk: fund[:, blk], t.size)  # (9, N)
    e_pow = np.stack([np.ones_like(e), e, e * e])  # E^|multiple of M| (Meeus p. 338)
    sl, sr, sb = (np.sum(e_pow * rows[3 * q : 3 * q + 3], axis=0) for q in range(3))
    # additive terms (Meeus p. 338): Venus (A1), Jupiter (A2), flattening of the Earth
    args = np.stack([a1, lpr - fr, a2, lpr, a3, a1 - fr, a1 + fr, lpr - mpr, lpr + mpr])
    sines = np.empty_like(args)
    unit_phasor(args, np.empty_like(args), sines)
    sl += np.einsum("k,kn->n", [3958.0, 1962.0, 318.0], sines[:3])
    sb += np.einsum("k,kn->n", [-2235.0, 382.0, 175.0, 175.0, 127.0, -115.0], sines[3:])
    lam = (lp + sl * 1e-6) * DEG
    beta = sb * 1e-6 * DEG
    dist = 385000.56 + sr * 1e-3
    return np.stack([lam, beta, dist])


def moon_ecliptic_of_date(jd_tt: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Geometric geocentric ecliptic longitude, latitude (rad, mean equinox of date) and
    distance (km, Earth centre to Moon centre) of the Moon (Meeus ch. 47)."""
    jd = _jd(jd_tt)
    # Shortest period in the series ~7 d: 2-day segments of degree 12 interpolate to
    # < 1e-4" (tested; the floor is the 40-us resolution of a float64 Julian Date).
    out = smooth(_moon_direct, jd, step_days=2.0, degree=12)
    lam, beta, dist = (x.reshape(jd.shape) for x in out)
    return np.mod(lam, 2 * np.pi), beta, dist


def moon_geocentric_mean_of_date(jd_tt: Any) -> np.ndarray:
    """Geometric geocentric position of the Moon (km), mean equator and equinox of date."""
    jd = _jd(jd_tt)
    lam, beta, dist = moon_ecliptic_of_date(jd)
    ecl = frames.spherical_to_cartesian(lam, beta, dist)
    return np.einsum("...ij,...j->...i", frames.rot_x(-frames.mean_obliquity(jd)), ecl)


def moon_apparent_geocentric(jd_tt: Any) -> dict[str, np.ndarray]:
    """Apparent geocentric place of the Moon (Meeus ch. 47: lambda + dpsi, true obliquity).

    Returns a dict of arrays: ``lon``, ``lat`` (apparent, true equinox of date), ``ra``,
    ``dec`` (rad), ``distance_km`` and ``angular_diameter`` (rad, geocentric). Light time
    (0.7") is not applied here, to match Meeus' definition; :mod:`skydome.astro.observer`
    applies it.
    """
    jd = _jd(jd_tt)
    lam, beta, dist = moon_ecliptic_of_date(jd)
    dpsi, deps = frames.nutation_angles(jd)
    eps = frames.mean_obliquity(jd) + deps
    lon = np.mod(lam + dpsi, 2 * np.pi)
    ra, dec = frames.ecliptic_to_equatorial(lon, beta, eps)
    return {
        "lon": lon,
        "lat": beta,
        "ra": ra,
        "dec": dec,
        "distance_km": dist,
        "angular_diameter": moon_angular_diameter(dist),
    }


def moon_angular_diameter(distance_km: Any) -> np.ndarray:
    """Angular diameter (rad) of the Moon seen from ``distance_km`` (centre to observer)."""
    d = np.asarray(distance_km, dtype=float)
    return 2.0 * np.arcsin(np.minimum(MOON_RADIUS_KM / d, 1.0))


def phase_angle(moon_vec, sun_vec) -> np.ndarray:
    """Phase angle i (rad): angle at the Moon between the Sun and the observer.

    ``moon_vec``, ``sun_vec``: observer-to-Moon and observer-to-Sun vectors (..., 3) in the
    same axes and units (Meeus eq. 48.2-48.3 in vector form).
    """
    m = np.asarray(moon_vec, dtype=float)
    s = np.asarray(sun_vec, dtype=float)
    to_sun = s - m
    to_obs = -m
    c = np.sum(to_sun * to_obs, axis=-1)
    x = np.linalg.norm(np.cross(to_sun, to_obs), axis=-1)
    return np.arctan2(x, c)


def illuminated_fraction(phase_angle_rad) -> np.ndarray:
    """Illuminated fraction of the disk k = (1 + cos i) / 2 (Meeus eq. 48.1)."""
    return 0.5 * (1.0 + np.cos(np.asarray(phase_angle_rad, dtype=float)))


def bright_limb_position_angle(ra_moon, dec_moon, ra_sun, dec_sun) -> np.ndarray:
    """Position angle chi (rad, from celestial north through east, [0, 2pi)) of the
    midpoint of the Moon's bright limb (Meeus eq. 48.5)."""
    a, d, a0, d0 = (np.asarray(x, dtype=float) for x in (ra_moon, dec_moon, ra_sun, dec_sun))
    y = np.cos(d0) * np.sin(a0 - a)
    x = np.sin(d0) * np.cos(d) - np.cos(d0) * np.sin(d) * np.cos(a0 - a)
    return np.mod(np.arctan2(y, x), 2 * np.pi)
