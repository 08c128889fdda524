"""The phasor evaluation of the periodic series equals the term-by-term one.

The series of :mod:`skydome.astro._series` (VSOP87D), :mod:`skydome.astro.moon` (ELP/MPP02)
and :mod:`skydome.astro.frames` (nutation, Earth velocity) build every term's
exp(i argument) from a few cosines and sines by complex multiplication. Here each is
compared, on 10,000 random instants of 1900-2050, with a straightforward evaluation kept in
this file: one cosine (or sine) per term and per time, as Meeus writes the series. The
required agreement is 1e-9 rad (0.2 mas) in angles and 1e-9 relative in distances and
rates; the differences measured are 1e-12 rad or less (rounding of arguments near 1e4 rad).
"""

from importlib.resources import files

import numpy as np
import pytest

from skydome.astro import frames, moon
from skydome.astro._series import (
    DAYS_PER_MILLENNIUM,
    J2000,
    PHASOR_BLOCK_TIMES,
    frequency_plan,
    integer_combination_plan,
    tables,
    unit_phasor,
    vsop,
)
from skydome.astro.planets import PLANETS

ANGLE_TOL_RAD = 1e-9
REL_TOL = 1e-9
DEG = np.pi / 180.0


@pytest.fixture(scope="module")
def jd_random() -> np.ndarray:
    rng = np.random.default_rng(2024)
    return 2415020.5 + rng.random(10_000) * 54786.0  # 1900-01-01 .. 2050-01-01


# --------------------------------------------------------------------------- references


def _vsop_reference(planet: str, jd: np.ndarray) -> np.ndarray:
    """Meeus eq. 32.1-32.2 term by term: X = sum_a tau^a sum A cos(B + C tau); (3, N)."""
    t = tables()
    a = t[f"vsop_{planet}_A"] * 1e-8
    b, c = t[f"vsop_{planet}_B"], t[f"vsop_{planet}_C"]
    coord, power = t[f"vsop_{planet}_coord"], t[f"vsop_{planet}_power"]
    tau = (jd - J2000) / DAYS_PER_MILLENNIUM
    out = np.zeros((3, jd.size))
    for k in range(3):
        for p in range(int(power.max()) + 1):
            sel = (coord == k) & (power == p)
            cosines = np.cos(b[sel, None] + c[sel, None] * tau[None, :])
            out[k] += tau**p * (a[sel] @ cosines)
    return out


def _earth_rates_reference(jd: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """L, B, R and d/dt (per day) of the selected Earth terms, term by term; (6, N)."""
    s = vsop("earth")  # terms sorted by (coord, power); ``keep`` refers to that order
    tau = (jd - J2000) / DAYS_PER_MILLENNIUM
    out = np.zeros((6, jd.size))
    for t in np.flatnonzero(keep):
        arg = s.b[t] + s.c[t] * tau
        p = int(s.power[t])
        out[s.coord[t]] += s.a[t] * tau**p * np.cos(arg)
        d_dtau = s.a[t] * (
            (p * tau ** (p - 1) if p else 0.0) * np.cos(arg) - tau**p * s.c[t] * np.sin(arg)
        )
        out[3 + s.coord[t]] += d_dtau / DAYS_PER_MILLENNIUM
    return out


def _nutation_reference(jd: np.ndarray) -> np.ndarray:
    """IAU 1980 nutation of Meeus table 22.A, one sine and one cosine per term; (2, N)."""
    tab = tables()
    t = (jd - J2000) / 36525.0
    arg = tab["nut_args"].astype(float) @ frames._fundamental_args(t)
    dpsi = (tab["nut_dpsi"][:, :1] + tab["nut_dpsi"][:, 1:] * t) * np.sin(arg)
    deps = (tab["nut_deps"][:, :1] + tab["nut_deps"][:, 1:] * t) * np.cos(arg)
    return np.stack([dpsi.sum(axis=0), deps.sum(axis=0)]) * (1e-4 * frames.ARCSEC)


def _moon_reference(jd: np.ndarray) -> np.ndarray:
    """ELP/MPP02 as packaged, term by term: A T^n sin(phi0 + i . args); (lambda, beta) rad
    (V + W1 + p_A) and distance km; (3, N)."""
    with np.load(files("skydome.data").joinpath(moon.ELP_FILE)) as z:
        terms, poly = z["terms"], z["args"]
    t = (jd - J2000) / 36525.0
    tp = t[None, :] ** np.arange(poly.shape[1])[:, None]
    args = poly[:13] @ tp
    out = np.zeros((3, jd.size))
    out[0] = poly[13] @ tp + np.polynomial.polynomial.polyval(t, moon.P_A_RAD)
    for c, n, a, phi, *mult in terms:
        out[int(c)] += a * t**n * np.sin(phi + np.asarray(mult) @ args)
    return out


# --------------------------------------------------------------------------- tests


@pytest.mark.parametrize("planet", ("earth",) + PLANETS)
def test_vsop_phasors_equal_term_by_term(planet, jd_random):
    ours = vsop(planet).lbr(jd_random)
    ref = _vsop_reference(planet, jd_random)
    assert np.abs(ours[:2] - ref[:2]).max() < ANGLE_TOL_RAD
    assert np.abs(ours[2] / ref[2] - 1.0).max() < REL_TOL


def test_earth_rates_phasors_equal_term_by_term(jd_random):
    keep = frames._earth_rate_terms()
    ours = frames._earth_lbr_rates(jd_random)
    ref = _earth_rates_reference(jd_random, keep)
    assert np.abs(ours[:2] - ref[:2]).max() < ANGLE_TOL_RAD
    assert np.abs(ours[2] / ref[2] - 1.0).max() < REL_TOL
    # rates: relative to the orbital motion, dL/dt = 0.0172 rad/day (0.0172 au/day)
    assert np.abs(ours[3:] - ref[3:]).max() < REL_TOL * 0.0172


def test_nutation_phasors_equal_term_by_term(jd_random):
    ours = frames._nutation_direct(jd_random)
    ref = _nutation_reference(jd_random)
    assert np.abs(ours - ref).max() < 1e-3 * ANGLE_TOL_RAD  # measured ~1e-17 rad


def test_moon_phasors_equal_term_by_term(jd_random):
    ours = moon._moon_direct(jd_random)
    ref = _moon_reference(jd_random)
    assert np.abs(ours[:2] - ref[:2]).max() < ANGLE_TOL_RAD
    assert np.abs(ours[2] / ref[2] - 1.0).max() < REL_TOL


@pytest.mark.parametrize("days", moon.SEGMENT_DAYS)
def test_moon_segments_equal_direct_sums(days, jd_random):
    """The Chebyshev series of segments (for dense or long arrays) against the direct sums:
    1e-5" over 1900-2050 and 3e-4" in 1-2 AD (the first-order rate correction is made for
    20 centuries, and the unwrapped longitude, 1.7e5 rad, rounds at 4e-11 rad per operation;
    measured 3e-6" and 1.3e-4" at 32 days)."""
    series = moon._series()
    far = J2000 - 19.5 * 36525.0 + np.linspace(-18000.0, 18000.0, 2000)
    for jd, tol in ((jd_random, 1e-5), (far, 3e-4)):
        ours, ref = series.segments(jd, days), series.direct(jd)
        assert np.abs(ours[:2] - ref[:2]).max() < tol * frames.ARCSEC
        assert np.abs(ours[2] - ref[2]).max() < tol * frames.ARCSEC * 4e5  # km at the Moon


@pytest.mark.parametrize("n", [1, 3, PHASOR_BLOCK_TIMES, PHASOR_BLOCK_TIMES + 1])
def test_phasor_blocks_and_small_arrays(n, jd_random):
    jd = jd_random[:n]
    ours, ref = moon._moon_direct(jd), _moon_reference(jd)
    # the Moon's longitude is unwrapped (~6e3 rad: 1e-12 rad per rounding; measured 4e-11)
    assert np.abs(ours[:2] - ref[:2]).max() < 1e-10
    assert np.abs(ours[2] / ref[2] - 1.0).max() < 1e-12
    ours, ref = vsop("mars").lbr(jd), _vsop_reference("mars", jd)
    assert np.abs(ours[:2] - ref[:2]).max() < 1e-11
    assert np.abs(ours[2] / ref[2] - 1.0).max() < 1e-12


def test_integer_combination_plan_products():
    rng = np.random.default_rng(5)
    mult = rng.integers(-4, 5, size=(40, 5))
    mult[0] = 0  # the constant term
    x = rng.uniform(-1e4, 1e4, size=(5, 7))  # |D, M, M', F| < 1e4 rad in 1900-2050
    z = integer_combination_plan(mult).run(x)
    # the reference's own argument rounds to 1e-16 * 1e5 rad
    np.testing.assert_allclose(z, np.exp(1j * (mult @ x)), rtol=0, atol=3e-11)


def test_unit_phasor_half_angle():
    x = np.concatenate([np.linspace(-4 * np.pi, 4 * np.pi, 4001), [np.pi, -np.pi, 0.0, 1.2e4]])
    c, s = np.empty_like(x), np.empty_like(x)
    unit_phasor(x, c, s)
    assert np.abs(c - np.cos(x)).max() < 2e-15 and np.abs(s - np.sin(x)).max() < 2e-15


def test_frequency_plan_products():
    base = np.array([6283.07585, 529.6909650946, 77713.7714681205])
    freqs = np.array([0.0, base[0], 2 * base[0], base[1], base[0] + base[1], 3 * base[1], base[2]])
    plan, c_base = frequency_plan(freqs)
    assert c_base.size == 3  # the sums and multiples come from products
    tau = np.linspace(-0.1, 0.05, 9)
    z = plan.run(c_base[:, None] * tau[None, :])
    np.testing.assert_allclose(z, np.exp(1j * freqs[:, None] * tau[None, :]), rtol=0, atol=1e-11)
