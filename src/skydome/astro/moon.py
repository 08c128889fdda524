"""The Moon: the lunar theory ELP/MPP02 with the constants fitted to DE405/DE406.

J. Chapront & G. Francou, "The lunar theory ELP revisited. Introduction of new planetary
perturbations", A&A 404, 735-742 (2003); the series are IMCCE's public distribution of the
theory (ftp://cyrano-se.obspm.fr/pub/2_lunar_solutions/2_elpmpp02/), as converted by
Y. T. Liu (https://github.com/ytliu0/ElpMpp02, whose docs/ElpMpp02.tex documents the
formulation and gives the test positions of ``tests/astro/test_moon_elpmpp02.py``).
``tools/build_moon_elpmpp02.py`` applies the DE405 fit, truncates the 35 901 terms to
those with |A| (10 cy)^n >= 0.003" (or 0.01 km) and writes ``moon_elpmpp02.npz``: 1977
terms, within 0.16" (longitude), 0.11" (latitude) and 0.33 km of the complete series over
1900-2100 (measured; 0.035" / 0.026" RMS). Against DE421 over 1950-2050, geocentric: 0.23"
max, 0.052" RMS (``tests/astro/test_moon_elpmpp02.py``; topocentric apparent places in
``tests/astro/test_astro_vs_skyfield.py``).

Every term is A T^n sin(phi0 + i . args), T in Julian centuries TDB (TT here) from
J2000.0, args the Delaunay arguments D, F, l, l', the mean longitudes of the planets and
zeta = W1 + 5028.79695" T. The sums give the longitude V from the fixed departure point of
J2000 on the mean ecliptic of date (V = W1 + sum; W1's rate 1732559343.7"/cy is free of
the precession), the latitude U and the distance r. The ELP frame's rotation to J2000,
(Laskar's P, Q; the tex eq. for X, Y, Z) is a rotation about the node of the ecliptic of
date on that of J2000 by their inclination, which the precession from J2000 to the
ecliptic and equinox of date undoes; what is left is the general precession in longitude:
lambda = V + p_A (IAU 2006, IERS Conventions 2010 eq. 5.39), beta = U.

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
    J2000,
    PhasorPlan,
    PhasorSums,
    SegmentMemo,
    cheb_matrix,
    clenshaw,
    integer_combination_plan,
)
from skydome.astro.frames import ARCSEC
from skydome.astro.time import julian_centuries
from skydome.io.packaged import read_packaged_npz

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
ELP_FILE = "moon_elpmpp02.npz"
ELP_FORMAT = 1  # tools/build_moon_elpmpp02.py FORMAT_VERSION
# General precession in longitude p_A (IAU 2006; IERS Conventions 2010 eq. 5.39), rad per T^k
P_A_RAD = np.array([0.0, 5028.796195, 1.1054348, 0.00007964, -0.000023857, -0.0000000383]) * ARCSEC


def _jd(jd_tt: Any) -> np.ndarray:
    return np.asarray(getattr(jd_tt, "jd_tt", jd_tt), dtype=float)


# Dense or long arrays of times are cut into segments (aligned on J2000) of one of these
# lengths (days), the one with the least work (_LunarSeries.__call__); a segment's series is
# expanded in Chebyshev polynomials of its time from phasors at its centre.
SEGMENT_DAYS = (8.0, 32.0)
# Chebyshev coefficients kept: each group's dropped ones sum to less than this (rad; the
# distance in km counted at the Moon's distance, 1 km = 2.6e-6 rad).
CHEB_TOL_RAD = 1e-13
# The first-order correction of the rates is applied where it can exceed this (rad).
FIX_TOL_RAD = 1e-11
MEAN_DISTANCE_KM = 385000.0
# Segments per block in the segment evaluation (the phasor table stays a few MB).
SEGMENT_BLOCK = 1024
# Groups per product in the segment evaluation: those of a chunk share its coefficient count.
CHUNK = 48
# Work of the segments' evaluation (fixed, per segment, per time and coefficient) and of the
# direct sums per time, in one unit (measured CPU time: 4e-3 s, 2e-5 s, 1.3e-8 s and
# 1.2e-5 s, NumPy 2, x86-64).
COST_FIXED, COST_SEGMENT, COST_COEFFICIENT, COST_DIRECT = 3e5, 1500.0, 1.0, 900.0


class _LunarSeries:
    """The packaged ELP/MPP02 series, summed either term by term at every time
    (:meth:`direct`) or per segment of time (:meth:`segments`).

    Terms sharing a multiplier vector, coordinate c (0 V, 1 U, 2 r) and power n of T are
    merged into groups g with weights W_g = sum -i A exp(i phi0) (A sin(phi0 + x) =
    Re(-i A exp(i phi0) exp(ix))), sorted by (c, n).
    """

    def __init__(self) -> None:
        tool = "tools/build_moon_elpmpp02.py"
        terms, _ = read_packaged_npz(ELP_FILE, "terms", ELP_FORMAT, "lunar series", tool)
        self.poly, _ = read_packaged_npz(ELP_FILE, "args", ELP_FORMAT, "lunar series", tool)
        key = np.column_stack([terms[:, :2], terms[:, 4:]]).astype(int)
        groups, which = np.unique(key, axis=0, return_inverse=True)
        self.weight = np.zeros(groups.shape[0], dtype=complex)
        np.add.at(self.weight, which.ravel(), -1j * terms[:, 2] * np.exp(1j * terms[:, 3]))
        self.rows = 4 * groups[:, 0] + groups[:, 1]  # sorted
        self.n_max = int(groups[:, 1].max())
        self.mult = groups[:, 2:].astype(float)
        args, arg_of_group = np.unique(groups[:, 2:], axis=0, return_inverse=True)
        self.plan = integer_combination_plan(args)
        self.group_slot = self.plan.outputs[arg_of_group.ravel()]
        self.direct_sums = PhasorSums(
            PhasorPlan(self.plan.n_base, self.plan.steps, list(self.group_slot)),
            np.arange(self.rows.size),
            self.weight,
            self.rows,
            12,
        )
        self.tables = {d: self._segment_tables(d) for d in SEGMENT_DAYS}
        self.memos = {d: SegmentMemo() for d in SEGMENT_DAYS}

    def _segment_tables(self, days: float) -> dict:
        """What the segments of ``days`` need: the plan returning the groups' phasors in the
        order of the products, the coefficients and the chunks (see :meth:`segments`)."""
        # Chebyshev coefficients of exp(i w0 h x) and x exp(i w0 h x), x in [-1, 1], h half
        # a segment (days), w0 the argument's rate at J2000 (rad/day)
        h = 0.5 * days
        w0 = self.mult @ self.poly[:13, 1] / 36525.0
        nodes, mat = cheb_matrix(64)
        e = np.exp(1j * np.outer(w0 * h, nodes))  # (G, 64)
        c0, c1 = e @ mat.T, (e * nodes) @ mat.T  # (G, 64)
        # each group's coefficients up to where its tail is below CHEB_TOL_RAD
        coord = self.rows // 4
        scale = np.abs(self.weight) / np.where(coord == 2, MEAN_DISTANCE_KM, 1.0)
        tail = np.cumsum((scale[:, None] * np.abs(c0))[:, ::-1], axis=1)[:, ::-1]
        n_coef = np.sum(tail >= CHEB_TOL_RAD, axis=1)
        p = int(n_coef.max())
        # The arguments' rates change (D, F, l, l', zeta have T^2.. terms: l 31.5"/cy^2): a
        # segment's expansion about w0 is corrected to first order, exp(i w h x) ~
        # exp(i w0 h x) (1 + i (w - w0) h x), for the groups where the correction can exceed
        # FIX_TOL_RAD within 20 centuries of J2000.
        k = np.arange(2, self.poly.shape[1])
        rate2 = np.abs(self.mult) @ np.abs(self.poly[:13, 2:] @ (k * 20.0 ** (k - 1)))
        fix = scale * rate2 / 36525.0 * h >= FIX_TOL_RAD
        # order: by row, then by number of coefficients (descending): coefficient j of a
        # chunk is then a sum over its first groups
        order = np.lexsort((-n_coef, self.rows))
        n_coef, fix, w, rows = n_coef[order], fix[order], self.weight[order], self.rows[order]
        c0, c1 = w[:, None] * c0[order, :p], w[:, None] * c1[order, :p]
        fixed = np.flatnonzero(fix)
        c1 = 1j * h * c1[fixed]
        return {
            "n_cheb": p,
            "plan": PhasorPlan(self.plan.n_base, self.plan.steps, list(self.group_slot[order])),
            "mult_fix": self.mult[order][fixed],
            "fix": fixed,
            "products": (
                # (real, imaginary) coefficients (P, groups) and chunks of CHUNK groups of
                # one row, each summed over its first group's coefficients
                (c0.real.T.copy(), c0.imag.T.copy(), _chunks(rows, n_coef)),
                (c1.real.T.copy(), c1.imag.T.copy(), _chunks(rows[fixed], n_coef[fixed])),
            ),
        }

    def base_angles(self, t: np.ndarray) -> np.ndarray:
        """D, F, l, l', Me .. Ne, zeta (rad) at ``t`` (Julian centuries); (13, N)."""
        return _horner(self.poly[:13], t)

    def finish(self, rows: np.ndarray, t: np.ndarray) -> np.ndarray:
        """(lambda, beta, r) from the sums V, U, r at ``t`` (rows (3, N)): V + W1 + p_A."""
        rows[0] += _horner(self.poly[13:], t)[0] + _horner(P_A_RAD[None, :], t)[0]
        return rows

    def __call__(self, jd_tt: np.ndarray) -> np.ndarray:
        """(lambda, beta, r) by the cheapest of the direct sums and the segments; (3, N).

        The segments already computed in this process (``self.memos``) cost only their
        Chebyshev sums; which way a call goes does not matter (they agree within 1e-5")."""
        jd = np.asarray(jd_tt, dtype=float).ravel()
        best, days, located = COST_DIRECT * jd.size, None, {}
        if jd.size > 16:
            for d in SEGMENT_DAYS:
                seg = np.floor((jd - J2000) / d)
                located[d] = (seg, self.memos[d].locate(seg))
                new = self.memos[d].missing(seg, located[d][1])
                p = self.tables[d]["n_cheb"]
                cost = COST_SEGMENT * new.size + COST_COEFFICIENT * jd.size * p
                cost += COST_FIXED if new.size else 0.0
                best, days = (cost, d) if cost < best else (best, days)
        if days is None:
            return self.direct(jd)
        return self.segments(jd, days, *located[days])

    def direct(self, jd_tt: np.ndarray) -> np.ndarray:
        """(lambda, beta, r) term by term at every time; (3, N)."""
        t = julian_centuries(np.asarray(jd_tt, dtype=float).ravel())
        args = self.base_angles(t)
        rows = self.direct_sums(lambda blk: args[:, blk], t.size).reshape(3, 4, t.size)
        out = rows[:, self.n_max].copy()
        for n in range(self.n_max - 1, -1, -1):  # Horner in T
            out = out * t + rows[:, n]
        return self.finish(out, t)

    def segments(
        self, jd_tt: np.ndarray, days: float, seg: np.ndarray | None = None, located=None
    ) -> np.ndarray:
        """(lambda, beta, r) from Chebyshev series on segments of ``days``; (3, N). The
        segments' coefficients are kept in ``self.memos[days]`` for later calls (``seg``,
        ``located``: the times' segments and where the memo holds them, if known)."""
        jd = np.asarray(jd_tt, dtype=float).ravel()
        seg = np.floor((jd - J2000) / days) if seg is None else seg
        coef, pos = self.memos[days].coefficients(
            seg, lambda new: self._segment_coefficients(new, days), located
        )
        x = (jd - J2000) / (0.5 * days) - (2.0 * seg + 1.0)
        return self.finish(clenshaw(coef, pos, x), julian_centuries(jd))

    def _segment_coefficients(self, segments: np.ndarray, days: float) -> np.ndarray:
        """Chebyshev coefficients (P + 1, 3, M) of V, U, r on the ``segments`` (M,) of
        ``days``, segment i being [J2000 + i days, J2000 + (i + 1) days).

        In a segment of centre t_c and half-length h, a group's phasor is
        exp(i theta(t_c)) exp(i w h x) with x = (t - t_c) / h (the arguments' curvature
        moves them by < 1e-6" within h); the Chebyshev coefficients of exp(i w h x) are
        tabulated once, so that a segment's coefficients are products of its phasors with
        that table (einsum: BLAS's threads stall on a busy machine at these sizes). Powers
        of T: T^n = T_c^n + n T_c^(n-1) dT (the next term < 1e-9").
        """
        tab = self.tables[days]
        h = 0.5 * days
        t_c = julian_centuries(J2000 + (segments + 0.5) * days)
        p = tab["n_cheb"]
        coef = np.zeros((p + 1, 3, segments.size))  # (P + 1, C, M): one more for x * series
        k = np.arange(2, self.poly.shape[1])
        for start in range(0, segments.size, SEGMENT_BLOCK):
            blk = slice(start, min(start + SEGMENT_BLOCK, segments.size))
            tb = t_c[blk]
            z = tab["plan"].run(self.base_angles(tb))  # (G, m)
            # first-order rate correction: i (w(t_c) - w0) h x exp(i w0 h x)
            # (einsum, not BLAS: see above)
            d_rate = np.einsum(
                "ak,km->am", self.poly[:13, 2:] * k / 36525.0, tb ** (k - 1)[:, None]
            )
            zf = z[tab["fix"]] * np.einsum("fa,am->fm", tab["mult_fix"], d_rate)
            part = np.zeros((3, self.n_max + 1, p, tb.size))
            for (cr, ci, chunks), zz in zip(tab["products"], (z, zf), strict=True):
                zr, zi = np.ascontiguousarray(zz.real), np.ascontiguousarray(zz.imag)
                for c, n, g0, g1, nj in chunks:
                    part[c, n, :nj] += np.einsum("jg,gm->jm", cr[:nj, g0:g1], zr[g0:g1])
                    part[c, n, :nj] -= np.einsum("jg,gm->jm", ci[:nj, g0:g1], zi[g0:g1])
            coef[:p, :, blk] += part[:, 0].transpose(1, 0, 2)
            for n in range(1, self.n_max + 1):
                pn = part[:, n].transpose(1, 0, 2)  # (P, C, m)
                coef[:p, :, blk] += tb**n * pn
                # n T_c^(n-1) dT x-times the series: x T_0 = T_1, x T_j = (T_j+1 + T_j-1) / 2
                dt = n * tb ** (n - 1) * (h / 36525.0) * pn
                coef[1, :, blk] += dt[0]
                coef[2:, :, blk] += 0.5 * dt[1:]
                coef[: p - 1, :, blk] += 0.5 * dt[1:]
        return coef


def _horner(poly: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Polynomials ``poly`` (K, D) (coefficients of t^0 .. t^(D-1)) at ``t`` (N,); (K, N)."""
    out = np.broadcast_to(poly[:, -1:], (poly.shape[0], t.size)).copy()
    for k in range(poly.shape[1] - 2, -1, -1):
        out *= t
        out += poly[:, k : k + 1]
    return out


def _chunks(rows: np.ndarray, n_coef: np.ndarray) -> list[tuple[int, int, int, int, int]]:
    """(c, n, first, stop, coefficients) of runs of at most CHUNK groups of one row ``4 c + n``
    (``rows`` sorted, ``n_coef`` descending within a row)."""
    out = []
    for r in np.unique(rows):
        a, b = np.searchsorted(rows, (r, r + 1))
        for g0 in range(int(a), int(b), CHUNK):
            g1 = min(g0 + CHUNK, int(b))
            out.append((int(r) // 4, int(r) % 4, g0, g1, int(n_coef[g0])))
    return out


@functools.cache
def _series() -> _LunarSeries:
    return _LunarSeries()


def _moon_direct(jd_tt: np.ndarray) -> np.ndarray:
    """(lambda, beta) in rad (lambda unwrapped), mean ecliptic and equinox of date, and the
    distance in km, every term at every time; shape (3, N)."""
    return _series().direct(jd_tt)


def moon_ecliptic_of_date(jd_tt: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Geometric geocentric ecliptic longitude, latitude (rad, mean ecliptic and equinox of
    date) and distance (km, Earth centre to Moon centre) of the Moon (ELP/MPP02)."""
    jd = _jd(jd_tt)
    # Dense or long arrays: Chebyshev series on segments of 8 or 32 days, equal to the
    # direct sums within 1e-5" (tests/astro/test_astro_frames.py)
    lam, beta, dist = (x.reshape(jd.shape) for x in _series()(jd))
    return np.mod(lam, 2 * np.pi), beta, dist


def moon_geocentric_mean_of_date(jd_tt: Any) -> np.ndarray:
    """Geometric geocentric position of the Moon (km), mean equator and equinox of date."""
    jd = _jd(jd_tt)
    lam, beta, dist = moon_ecliptic_of_date(jd)
    ecl = frames.spherical_to_cartesian(lam, beta, dist)
    return np.einsum("...ij,...j->...i", frames.rot_x(-frames.mean_obliquity(jd)), ecl)


def moon_apparent_geocentric(jd_tt: Any) -> dict[str, np.ndarray]:
    """Apparent geocentric place of the Moon (lambda + dpsi, true obliquity; Meeus ch. 47).

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
    c = frames.dot3(to_sun, to_obs)
    x = frames.norm3(np.cross(to_sun, to_obs))
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
