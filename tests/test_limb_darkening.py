"""The Sun's limb darkening against published profiles, and the disk's normalisation.

Sources:
- Neckel & Labs (1994), Solar Physics 153, 91-114, their table of the fifth-order polynomial
  coefficients A_0..A_5 of I(mu)/I(1) measured in 30 continuum windows (303-1099 nm), with
  the disk-mean to centre intensity ratio in the last column. Transcribed from ISP-SST/sstred
  ``red_neckel_coefficients.pro`` (the table branch); the 445.125, 541.760 and 669.400 nm
  rows appear digit for digit in a second, unrelated copy (the ExpanseSky HDRP sky shader).
- Cox (ed., 2000), Allen's Astrophysical Quantities, 4th ed., Sec. 14.7: the quadratic law
  I/I(1) = 1 - u - v + u mu + v mu^2, through SolarSoft's ``darklimb_u.pro``/``darklimb_v.pro``
  fifth-order fits of u(lambda) and v(lambda) (lambda in Angstrom, 4000-15000 A), as copied
  in several sunpy-based limb-correction scripts (identical digits). An independent data set
  and law (older observations, two parameters).
"""

import math

import numpy as np
import pytest

from skydome.celestial.limb_darkening import (
    ANGULAR_RADIUS_MAX_RAD,
    centre_to_disk_ratio,
    disk_mean_intensity,
    disk_normalisation,
    disk_radiance_factor,
    limb_coefficients,
    limb_darkening,
    mu_from_radius,
    mu_from_sky_angle,
)
from skydome.errors import ParameterError
from skydome.spectra import wavelengths

# Neckel & Labs (1994) table: wavelength (nm), A_0..A_5, disk-mean / centre intensity.
NL94 = np.array(
    [
        [303.327, 0.08011, 0.70695, 0.49910, -0.31080, -0.02177, 0.04642, 0.6826],
        [310.843, 0.08160, 0.71609, 0.69685, -0.87703, 0.47008, -0.08760, 0.6883],
        [320.468, 0.08833, 0.77285, 0.65382, -1.04647, 0.72921, -0.19775, 0.6985],
        [329.897, 0.09188, 0.92459, 0.19604, -0.39546, 0.23599, -0.05303, 0.7116],
        [349.947, 0.11012, 1.02168, -0.10924, -0.00055, -0.08688, 0.06487, 0.7260],
        [365.875, 0.12828, 1.04969, 0.17482, -1.13371, 1.23882, -0.45990, 0.7445],
        [374.086, 0.12579, 0.85402, 0.54601, -1.15048, 0.88928, -0.26462, 0.7288],
        [390.915, 0.12995, 0.91836, -0.07566, 0.19149, -0.28712, 0.12298, 0.7204],
        [401.970, 0.12323, 1.08648, -0.43974, 0.45912, -0.32759, 0.09850, 0.7303],
        [416.319, 0.12814, 1.19947, -0.84407, 1.07201, -0.79537, 0.23982, 0.7380],
        [427.930, 0.14249, 1.28796, -1.19564, 1.68603, -1.36658, 0.44572, 0.7495],
        [443.885, 0.16220, 1.24893, -0.92165, 0.89978, -0.50148, 0.11220, 0.7588],
        [445.125, 0.15248, 1.38517, -1.49615, 1.99886, -1.48155, 0.44119, 0.7596],
        [457.345, 0.16604, 1.38544, -1.52275, 2.00232, -1.45969, 0.42864, 0.7651],
        [477.427, 0.19571, 1.30551, -1.25845, 1.50626, -1.05472, 0.30570, 0.7751],
        [492.905, 0.20924, 1.30798, -1.20411, 1.21505, -0.67196, 0.14381, 0.7823],
        [519.930, 0.23695, 1.29927, -1.28034, 1.37760, -0.85054, 0.21706, 0.7925],
        [541.760, 0.26073, 1.27428, -1.30352, 1.47085, -0.96618, 0.26384, 0.8002],
        [559.950, 0.26892, 1.34319, -1.58427, 1.91271, -1.31350, 0.37295, 0.8061],
        [579.880, 0.28392, 1.36896, -1.75998, 2.22154, -1.56074, 0.44630, 0.8125],
        [610.975, 0.30854, 1.36620, -1.83572, 2.33221, -1.63082, 0.45959, 0.8221],
        [640.970, 0.33644, 1.30590, -1.79238, 2.45040, -1.89979, 0.59943, 0.8290],
        [669.400, 0.34685, 1.37539, -2.04425, 2.70493, -1.94290, 0.55999, 0.8360],
        [700.875, 0.37885, 1.25553, -1.70908, 2.19647, -1.59554, 0.47378, 0.8434],
        [748.710, 0.40627, 1.22842, -1.67877, 2.05535, -1.39972, 0.38845, 0.8524],
        [811.760, 0.42977, 1.25182, -1.85164, 2.31949, -1.59101, 0.44155, 0.8621],
        [869.600, 0.45396, 1.25101, -2.02958, 2.75410, -2.02287, 0.59338, 0.8701],
        [948.850, 0.47855, 1.19813, -1.86296, 2.36939, -1.64367, 0.46056, 0.8773],
        [1046.60, 0.49870, 1.21429, -2.06976, 2.80703, -2.05247, 0.60221, 0.8841],
        [1098.95, 0.51149, 1.19354, -2.00174, 2.66936, -1.94981, 0.57715, 0.8890],
    ]
)
GAP_WINDOW_NM = 374.086  # the one window between Neckel's 372.98 and 385 nm fits
FITTED = NL94[NL94[:, 0] != GAP_WINDOW_NM]

# SolarSoft darklimb_u / darklimb_v: u, v = sum_i c_i lambda_A^i (Allen's AQ, 4th ed.).
ALLEN_U = (-8.9829751, 0.0069093916, -1.8144591e-6, 2.2540875e-10, -1.3389747e-14, 3.0453572e-19)
ALLEN_V = (9.2891180, -0.0062212632, 1.5788029e-6, -1.9359644e-10, 1.1444469e-14, -2.599494e-19)

SUN_ALPHA_1AU = math.radians(959.63 / 3600.0)  # IAU solar semidiameter at 1 AU


def _table_profile(row, mu):
    return np.polynomial.polynomial.polyval(mu, row[1:7])


def _allen_profile(wavelength_nm, mu):
    lam_a = 10.0 * wavelength_nm
    u = np.polynomial.polynomial.polyval(lam_a, ALLEN_U)
    v = np.polynomial.polynomial.polyval(lam_a, ALLEN_V)
    return 1.0 - u - v + u * mu + v * mu**2


def test_coefficients_sum_to_one_everywhere():
    # I(1)/I(1) = 1 by construction of Neckel's fits (a_10, a_11, a_15 close the sums). The
    # 5-6 digit published coefficients leave <= 1e-5; a sign slip in any a_k5 (as in one
    # public copy's a_55 = +0.003347) breaks it by > 1e-3.
    wl = np.linspace(250.0, 1200.0, 2000)
    a = limb_coefficients(wl)
    assert a.shape == (2000, 6)
    np.testing.assert_allclose(a.sum(axis=-1), 1.0, atol=1e-5)
    np.testing.assert_allclose(limb_darkening(1.0, wl), 1.0, atol=1e-5)


@pytest.mark.parametrize("row_nm", [401.970, 457.345, 610.975, 700.875])
def test_profile_matches_neckel_labs_table_within_2_percent(row_nm):
    # The brief's check: at blue and red windows the profile at mu = 0.1, 0.3, 0.5, 0.7 is
    # within 2 % of Neckel & Labs' (1994) tabulated polynomial. Measured: max 1.44 %
    # (610.975 nm, mu = 0.1); 0.32, 0.36, 0.47 % at the other three.
    row = NL94[NL94[:, 0] == row_nm][0]
    mu = np.array([0.1, 0.3, 0.5, 0.7])
    np.testing.assert_allclose(limb_darkening(mu, row_nm), _table_profile(row, mu), rtol=0.02)


def test_profile_matches_every_fitted_window():
    # All 29 windows Neckel's analytic fits cover (303-1099 nm). The fits smooth the
    # window-to-window scatter of the measurements (Neckel & Labs: irregular variations of
    # the means are usually < 1 % but reach 2 % or more). Measured max: 4.58 % at mu = 0.1
    # (303.3 nm), 2.37 % at mu >= 0.3 (365.9 nm), 0.80 % at mu = 0.7 (365.9 nm).
    for row in FITTED:
        got = lambda mu, row=row: limb_darkening(mu, row[0])  # noqa: E731
        np.testing.assert_allclose(got(0.1), _table_profile(row, 0.1), rtol=0.05)
        mu = np.array([0.3, 0.5, 0.7, 0.9])
        np.testing.assert_allclose(got(mu), _table_profile(row, mu), rtol=0.025)


def test_gap_bridge_stays_near_the_one_gap_window():
    # 374.086 nm lies where Neckel gives no fit; the linear bridge is 7.7 % high at mu = 0.1
    # and 3.1 % at mu = 0.5 (documented); bounded here at 8 % / 3.5 % so a worse bridge fails.
    row = NL94[NL94[:, 0] == GAP_WINDOW_NM][0]
    ratio = limb_darkening([0.1, 0.5, 0.9], GAP_WINDOW_NM) / _table_profile(row, [0.1, 0.5, 0.9])
    assert np.all(np.abs(ratio - 1.0) < [0.08, 0.035, 0.005])


def test_disk_mean_matches_neckel_labs_column():
    # The table's last column is the disk-mean to centre ratio 2 sum A_k/(k+2): the table's
    # own A_k reproduce it to its 4 decimals (checks the transcription and the closed form),
    # in 29 of 30 rows. The 365.875 nm row as transcribed sums to 0.99800, not 1, and gives
    # 0.7435 for 0.7445; A_2 = 0.17682 instead of 0.17482 would fix both, so one digit of
    # that row is likely wrong in the copy. Left as found; only this check skips it (it moves
    # that row's profile by <= 0.002, well inside the profile tests' bounds).
    own = 2.0 * np.sum(NL94[:, 1:7] / np.arange(2.0, 8.0), axis=1)
    clean = NL94[:, 0] != 365.875
    np.testing.assert_allclose(own[clean], NL94[clean, 7], atol=1.5e-4)
    np.testing.assert_allclose(NL94[clean, 1:7].sum(axis=1), 1.0, atol=3e-5)
    # Neckel's fits against the column: measured max 0.93 % (365.9 nm), 0.41 % at 385-1099 nm.
    np.testing.assert_allclose(disk_mean_intensity(FITTED[:, 0]), FITTED[:, 7], rtol=0.01)
    red = FITTED[FITTED[:, 0] > 385.0]
    np.testing.assert_allclose(disk_mean_intensity(red[:, 0]), red[:, 7], rtol=0.005)
    np.testing.assert_allclose(centre_to_disk_ratio(red[:, 0]), 1.0 / red[:, 7], rtol=0.005)


def test_independent_allen_quadratic_law_agrees_within_a_few_percent():
    # Allen's AQ quadratic law, a different data set and a two-parameter law that cannot
    # follow the steep drop at the extreme limb. Measured over 400-825 nm: max 3.20 % at
    # mu >= 0.3 (400 nm, mu = 0.3), 5.20 % at mu = 0.1 (825 nm); disk means within 1.17 %.
    wl = np.arange(400.0, 830.0, 25.0)[:, None]
    mu = np.array([0.3, 0.5, 0.7, 0.9])
    np.testing.assert_allclose(limb_darkening(mu, wl), _allen_profile(wl, mu), rtol=0.035)
    np.testing.assert_allclose(limb_darkening(0.1, wl), _allen_profile(wl, 0.1), rtol=0.06)
    lam_a = 10.0 * wl[:, 0]
    u = np.polynomial.polynomial.polyval(lam_a, ALLEN_U)
    v = np.polynomial.polynomial.polyval(lam_a, ALLEN_V)
    allen_mean = 2.0 * ((1.0 - u - v) / 2.0 + u / 3.0 + v / 4.0)
    np.testing.assert_allclose(disk_mean_intensity(wl[:, 0]), allen_mean, rtol=0.0125)


def test_limb_darker_in_blue_than_red():
    # I(0.2)/I(1): 0.323 at 400 nm, 0.575 at 700 nm (Neckel); also monotonic in mu and in
    # wavelength across the renderer's grid at the limb.
    blue, red = limb_darkening(0.2, [400.0, 700.0])
    assert blue < red
    grid = wavelengths("accurate")
    prof = limb_darkening(np.linspace(0.0, 1.0, 101)[:, None], grid)
    assert np.all(np.diff(prof, axis=0) > 0)
    assert np.all(np.diff(limb_darkening(0.2, grid[grid > 400])) > 0)


def test_geometry_against_ray_tracing():
    # Independent check of sin(psi) = sin(theta)/sin(alpha): intersect rays from an observer
    # at distance d with a sphere of radius R, take the outward normal at the first hit and
    # its cosine with the ray back to the observer. Equal to rounding (1e-10).
    for d_over_r in (1.05, 3.0, 215.03):
        alpha = math.asin(1.0 / d_over_r)
        theta = np.linspace(0.0, 0.9999 * alpha, 301)
        ray = np.stack([np.sin(theta), np.zeros_like(theta), np.cos(theta)], axis=-1)
        centre = np.array([0.0, 0.0, d_over_r])  # R = 1, observer at the origin
        b = ray @ centre
        t_hit = b - np.sqrt(b * b - (d_over_r**2 - 1.0))
        normal = ray * t_hit[:, None] - centre
        mu_ray = -np.sum(normal * ray, axis=-1)
        np.testing.assert_allclose(mu_from_sky_angle(theta, alpha), mu_ray, atol=1e-10)
    assert mu_from_radius(0.6) == pytest.approx(0.8, abs=1e-15)
    assert mu_from_radius(1.0) == 0.0 and mu_from_radius(0.0) == 1.0


def _gnomonic_disk_integral(alpha, wavelength_nm, n=2400):
    """Sum of f dOmega over a square grid in the tangent plane of the disk centre (midpoint
    rule; dOmega = dx dy / (1 + x^2 + y^2)^1.5), independent of the module's quadrature."""
    half = math.tan(alpha) * 1.001
    h = 2.0 * half / n
    x = -half + h * (np.arange(n) + 0.5)
    total = 0.0
    for chunk in np.array_split(x, 8):
        r2 = chunk[:, None] ** 2 + x[None, :] ** 2
        theta = np.arctan(np.sqrt(r2))
        f = disk_radiance_factor(theta, alpha, wavelength_nm)
        total += float(np.sum(f * h * h / (1.0 + r2) ** 1.5))
    return total


@pytest.mark.parametrize("alpha", [SUN_ALPHA_1AU, 0.5])
@pytest.mark.parametrize("wl", [400.0, 700.0])
def test_disk_integrates_to_one(alpha, wl):
    # The brief: a disk of radiance E_sun * f delivers E_sun, integral f dOmega = 1 within
    # 1e-4 by 2D quadrature in solid angle. The 2400^2 midpoint grid resolves the disk's
    # edge to ~1e-5 (measured: 1.5e-6 to 3.7e-6). alpha = 0.5 rad exercises the exact
    # finite-distance geometry; a flat-disk mapping rho = theta/alpha would integrate to
    # 1.0135 there (400 nm).
    assert _gnomonic_disk_integral(alpha, wl) == pytest.approx(1.0, abs=1e-4)


def test_normalisation_limits():
    # Small disk: N = Omega_disk * D (1 + O(alpha^2)); at 1 AU within 1e-6 (measured 4e-7 to
    # 8e-7). Any alpha: N is the exact integral, so f at the centre equals 1/N.
    a = SUN_ALPHA_1AU
    omega = 4.0 * math.pi * math.sin(a / 2.0) ** 2
    grid = wavelengths("accurate")
    n = disk_normalisation(a, grid)
    np.testing.assert_allclose(n, omega * disk_mean_intensity(grid), rtol=1e-6)
    np.testing.assert_allclose(disk_radiance_factor(0.0, a, grid), 1.0 / n, rtol=1e-14)
    assert disk_radiance_factor(2.0 * a, a, 550.0) == 0.0
    assert disk_normalisation([a, 0.1, 1.0], 550.0).shape == (3,)


def test_grid_shapes_and_clamping():
    grid = wavelengths("accurate")  # 380-755 nm, 16 wavelengths
    assert limb_coefficients(grid).shape == (16, 6)
    assert limb_coefficients(550.0).shape == (6,)
    np.testing.assert_array_equal(limb_coefficients(200.0), limb_coefficients(300.0))
    np.testing.assert_array_equal(limb_coefficients(1500.0), limb_coefficients(1100.0))
    # The 372.98-385 nm bridge joins both fits continuously.
    for edge in (372.98, 385.0):
        lo, hi = limb_coefficients([edge - 1e-7, edge + 1e-7])
        np.testing.assert_allclose(lo, hi, atol=1e-7)
    assert limb_darkening([[0.5], [0.2]], [400.0, 500.0, 600.0]).shape == (2, 3)


@pytest.mark.parametrize(
    ("call", "text"),
    [
        (lambda: limb_darkening(0.5, float("nan")), "wavelength_nm = nan"),
        (lambda: limb_coefficients([500.0, -3.0]), "wavelength_nm = -3.0"),
        (lambda: disk_mean_intensity(0.0), "wavelength_nm = 0.0"),
        (lambda: limb_darkening(1.2, 500.0), "mu = 1.2 is outside the valid range [0, 1]"),
        (lambda: limb_darkening(float("nan"), 500.0), "mu = nan"),
        (lambda: mu_from_radius(-0.1), "rho = -0.1"),
        (lambda: disk_normalisation(0.0, 500.0), "angular_radius_rad = 0.0"),
        (lambda: disk_radiance_factor(0.0, 2.0, 500.0), f"(0, {ANGULAR_RADIUS_MAX_RAD}]"),
        (lambda: disk_radiance_factor(-0.1, 0.01, 500.0), "theta_rad = -0.1"),
        (lambda: mu_from_sky_angle(0.02, 0.01), "theta_rad = 0.02"),
        (lambda: limb_darkening(0.5, "blue"), "wavelength_nm must be a number"),
    ],
)
def test_bad_input_errors(call, text):
    with pytest.raises(ParameterError, match=None) as info:
        call()
    assert text in str(info.value)
    assert "\n" not in str(info.value)
