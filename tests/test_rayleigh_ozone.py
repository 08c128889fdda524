"""Rayleigh scattering from first principles (Bodhaine et al. 1999), the standard ozone
profile (AFGL 1986 U.S. Standard / U.S. Standard Atmosphere 1976), the ozone cross-section
table, and ozone's part in the blue of the twilight zenith (Hulburt 1953)."""

from __future__ import annotations

import numpy as np
import pytest

from skydome.atmosphere import preset
from skydome.atmosphere.ozone import (
    column_du,
    ozone_density_profile,
    standard_ozone_column_du,
    standard_ozone_profile,
)
from skydome.atmosphere.params import DOBSON_UNIT_PER_M2
from skydome.atmosphere.rayleigh import (
    column_gravity_m_s2,
    king_factor_air,
    mean_molecular_mass_kg_per_mol,
    rayleigh_cross_section_m2,
    rayleigh_optical_depth,
    rayleigh_scattering_per_m,
    refractive_index_air,
)
from skydome.errors import ParameterError
from skydome.spectra.tables import ozone_cross_section

# Bodhaine, Wood, Dutton & Slusser (1999), J. Atmos. Oceanic Technol. 16, 1854, Table 3:
# dry air with 360 ppm CO2; cross-section per molecule (cm^2), Rayleigh optical depth at sea
# level (1013.25 hPa, 45° latitude) and King factor F(air), every 50 nm from 350 to 850 nm
# (the rows of the table at those wavelengths, as transcribed from the journal's table image
# in docs of the public repository migujorg/claude-space-thing; the σ column agrees with the
# paper's own closed-form fit, eq. 29, to 8e-5, tested below).
TABLE3_NM = np.array([350, 400, 450, 500, 550, 600, 650, 700, 750, 800, 850], float)
TABLE3_SIGMA_CM2 = np.array(
    [2.9289e-26, 1.6738e-26, 1.0274e-26, 6.6614e-27, 4.5105e-27, 3.1640e-27,
     2.2856e-27, 1.6926e-27, 1.2803e-27, 9.8642e-28, 7.7235e-28]
)  # fmt: skip
TABLE3_TAU = np.array(
    [0.63031, 0.36022, 0.22111, 0.14336, 0.097069, 0.068092,
     0.049188, 0.036424, 0.027552, 0.021228, 0.016621]
)  # fmt: skip
TABLE3_KING = np.array(
    [1.05312, 1.05126, 1.05011, 1.04935, 1.04882, 1.04844,
     1.04815, 1.04793, 1.04776, 1.04762, 1.04751]
)  # fmt: skip


def test_cross_section_and_optical_depth_match_bodhaine_table3():
    # Bound 0.1 % (the issue asks 1 %): Table 3 prints 5 significant digits (rounding
    # <= 1e-4 of the value at 0.97069 ... 9.9999) and computes with the very formulas
    # implemented here. Measured: σ within 2.9e-5, τ within 3.5e-5, 350-850 nm.
    sigma_cm2 = rayleigh_cross_section_m2(TABLE3_NM) * 1e4
    np.testing.assert_allclose(sigma_cm2, TABLE3_SIGMA_CM2, rtol=1e-3)
    np.testing.assert_allclose(rayleigh_optical_depth(TABLE3_NM), TABLE3_TAU, rtol=1e-3)
    # Table 3's King factors to 5 decimals (rounding 5e-6); measured within 4.8e-6.
    np.testing.assert_allclose(king_factor_air(TABLE3_NM), TABLE3_KING, rtol=0, atol=1e-5)
    # The "near 0.0973" at 550 nm is Hansen & Travis's value (below); Bodhaine's is
    # 0.09707.
    assert rayleigh_optical_depth(550.0) == pytest.approx(0.097069, rel=1e-3)


def test_cross_section_matches_bodhaine_closed_form_fit_eq29():
    # Bodhaine et al. (1999) eq. 29, their least-squares fit to eq. 22 over 250-850 nm:
    # σ (1e-28 cm^2) = (1.0455996 − 341.29061 λ⁻² − 0.90230850 λ²) /
    #                  (1 + 0.0027059889 λ⁻² − 85.968563 λ²), λ in µm.
    # An independent form of the same physics; bound 2e-4 (the fit's residual: measured
    # 7.7e-5 at most over 400-850 nm).
    wl_nm = np.arange(400.0, 851.0, 10.0)
    lam = wl_nm / 1000.0
    fit_cm2 = (
        1e-28
        * (1.0455996 - 341.29061 * lam**-2 - 0.90230850 * lam**2)
        / (1.0 + 0.0027059889 * lam**-2 - 85.968563 * lam**2)
    )
    np.testing.assert_allclose(rayleigh_cross_section_m2(wl_nm) * 1e4, fit_cm2, rtol=2e-4)


def test_refractive_index_at_360_ppm_is_bodhaine_eq21():
    # Bodhaine's eq. 21 is eq. 18 (Peck & Reeder, 300 ppm) scaled by eq. 19 to 360 ppm and
    # printed with 6-7 digits: (n − 1) 1e8 = 8060.77 + 2481070 / (132.274 − λ⁻²) +
    # 17456.3 / (39.32957 − λ⁻²). Its rounding is 1.3e-6 of (n − 1) at most; bound 3e-6.
    wl_nm = np.arange(400.0, 701.0, 25.0)
    inv2 = (wl_nm / 1000.0) ** -2
    eq21 = 1e-8 * (8060.77 + 2481070.0 / (132.274 - inv2) + 17456.3 / (39.32957 - inv2))
    np.testing.assert_allclose(refractive_index_air(wl_nm, 360.0) - 1.0, eq21, rtol=3e-6)
    # 300 ppm is eq. 18 itself; more CO2 raises (n − 1): +0.54 × 60e-6 = +3.24e-5 relative.
    n300 = refractive_index_air(550.0, 300.0) - 1.0
    assert (refractive_index_air(550.0, 360.0) - 1.0) / n300 == pytest.approx(1 + 3.24e-5, abs=1e-9)


def test_optical_depth_within_half_a_percent_of_hansen_travis_1974():
    # Hansen & Travis (1974), Space Sci. Rev. 16, 527 (their fit to Rayleigh optical depth): τ = 0.008569 λ⁻⁴ (1 +
    # 0.0113 λ⁻² + 0.00013 λ⁻⁴), λ in µm, sea level, 1013.25 hPa (0.0973 at 550 nm): an
    # older, independent fit (Edlén's refractive index, constant depolarization 0.0279).
    # Bound 0.5 %; measured −0.29 % to +0.04 % over 400-700 nm.
    wl_nm = np.arange(400.0, 701.0, 10.0)
    lam = wl_nm / 1000.0
    hansen_travis = 0.008569 * lam**-4 * (1.0 + 0.0113 * lam**-2 + 0.00013 * lam**-4)
    np.testing.assert_allclose(rayleigh_optical_depth(wl_nm), hansen_travis, rtol=5e-3)


def test_gravity_mass_and_pressure_scaling():
    # List (1968) via Bodhaine eq. 11 at 45° and sea level: z_c = 5517.56 m, g = 978.916
    # cm/s^2 (by hand: 980.616 − 1.70242 + 0.00221 − 0.0000025); m_a = 28.9649 g/mol at
    # 360 ppm (their text). Bounds: the last printed digit.
    assert column_gravity_m_s2(45.0, 0.0) == pytest.approx(9.78916, abs=2e-5)
    assert mean_molecular_mass_kg_per_mol(360.0) == pytest.approx(28.9649e-3, abs=1e-7)
    # Gravity grows from the equator to the poles by 0.051868 m/s^2 at sea level (the
    # International Gravity Formula 1967: 9.780318 -> 9.832186 m/s^2), so the same pressure
    # holds up less air there; eq. 11 keeps that difference at the column's height within
    # 0.5 % (measured −0.3 %).
    pole_minus_equator = column_gravity_m_s2(90.0) - column_gravity_m_s2(0.0)
    assert pole_minus_equator == pytest.approx(0.051868, rel=5e-3)
    # τ is proportional to pressure (eq. 30): half the pressure, half the optical depth.
    assert rayleigh_optical_depth(500.0, pressure_pa=50662.5) == pytest.approx(
        0.5 * rayleigh_optical_depth(500.0), rel=1e-12
    )


def test_sea_level_scattering_coefficient():
    # β(550 nm) = σ × the US Standard Atmosphere 1976 sea-level number density 2.5470e25
    # m^-3 (its Table I), with σ = 4.5105e-27 cm^2 from Bodhaine's Table 3: 1.1488e-5 m^-1.
    # Bound 1e-4 (Table 3's rounding; measured 1e-5). The `earth` preset (Bruneton 2017)
    # has 13.558e-6 m^-1, 18 % more.
    expected = 4.5105e-31 * 2.5470e25
    assert float(rayleigh_scattering_per_m(550.0, 2.5470e25)) == pytest.approx(expected, rel=1e-4)
    beta = rayleigh_scattering_per_m(np.array([450.0, 550.0]), np.array([[2.5470e25], [0.0]]))
    assert beta.shape == (2, 2) and np.all(beta[1] == 0.0)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: rayleigh_cross_section_m2(100.0), r"wavelength_nm must lie in \[200, 4000\] nm"),
        (lambda: rayleigh_cross_section_m2(550.0, co2_ppm=-1.0), r"co2_ppm = -1.0 ppm"),
        (lambda: rayleigh_scattering_per_m(550.0, -1.0), r"number_density_m3 must be"),
        (lambda: rayleigh_optical_depth(550.0, latitude_deg=91.0), r"latitude_deg = 91.0"),
    ],
)
def test_rayleigh_rejects_bad_input(call, message):
    with pytest.raises(ParameterError, match=message):
        call()


# --- Ozone profile ---

# U.S. Standard Atmosphere 1976 (NOAA-S/T 76-1562), Table 18, mid-latitude ozone model:
# number density (m^-3) every 2 km from 2 to 50 km (as transcribed in the public repository
# migujorg/claude-space-thing from the NTRS scan, pdf page 54); total 0.345 atm-cm =
# 9.27e22 m^-2 = 345 DU (Table 18 footer). An independent source for the shipped AFGL
# profile, whose ozone follows it.
US76_Z_M = np.arange(2000.0, 50001.0, 2000.0)
US76_O3_M3 = np.array(
    [6.8e17, 5.8e17, 5.7e17, 6.5e17, 1.13e18, 2.02e18, 2.35e18, 2.95e18, 4.04e18, 4.77e18,
     4.86e18, 4.54e18, 4.03e18, 3.24e18, 2.52e18, 2.03e18, 1.58e18, 1.22e18, 8.73e17,
     6.07e17, 3.98e17, 2.74e17, 1.69e17, 1.03e17, 6.64e16]
)  # fmt: skip
US76_TOTAL_DU = 345.0


def test_ozone_profile_is_the_afgl_table_and_follows_us76():
    z, n = standard_ozone_profile()
    assert z[0] == 0.0 and z[-1] == 120_000.0 and len(z) == 50 and np.all(np.diff(z) > 0)
    # The shipped number densities are the AFGL table's air density × ozone mixing ratio
    # (the file's other two columns), rounded to 4 digits: within 5e-4.
    from skydome.atmosphere.ozone import _read_profile_table

    t = _read_profile_table()
    np.testing.assert_allclose(t[:, 1], t[:, 2] * t[:, 3] * 1e-6, rtol=5e-4)
    # Anderson et al. (1986) built the U.S. Standard ozone from the 1976 Standard: at the
    # altitudes both tables list (every 2 km to 24 km, 30, 40, 50 km) within 2.5 % of its
    # Table 18 (whose values have 2-3 digits); measured −1.0 % to +2.1 % (16 km).
    common = np.isin(US76_Z_M, z)
    assert common.sum() == 15
    at = np.searchsorted(z, US76_Z_M[common])
    np.testing.assert_allclose(n[at], US76_O3_M3[common], rtol=0.025)


def test_ozone_column_and_peak_are_the_standards():
    # Total column: the 1976 Standard's 345 DU within 1 % (measured 344.2 DU, −0.24 %; the
    # AFGL table adds 0-2 km, which Table 18 does not list, and ends at 120 km).
    assert standard_ozone_column_du() == pytest.approx(US76_TOTAL_DU, rel=0.01)
    # Peak: 22 km in both tables (US76 4.86e18 m^-3, AFGL 4.89e18), within 1 %.
    z, n = standard_ozone_profile()
    assert z[np.argmax(n)] == 22_000.0
    assert n.max() == pytest.approx(4.86e18, rel=0.01)
    # column_du against the trapezoid rule on the same samples (an upper bound for a convex
    # log-linear profile, 0.4 % above): within 1 %, and below it.
    trapezoid_du = float(np.sum(0.5 * (n[1:] + n[:-1]) * np.diff(z))) / DOBSON_UNIT_PER_M2
    assert column_du(z, n) == pytest.approx(trapezoid_du, rel=0.01)
    assert column_du(z, n) < trapezoid_du


def test_ozone_density_profile_scales_to_any_column():
    z, n = standard_ozone_profile()
    profile = ozone_density_profile()
    # The relative profile passes through the table (1 at the 22 km peak).
    np.testing.assert_allclose(profile.density(z), n / n.max(), rtol=1e-12)
    # Its column (DensityProfile's own integrator, to the `earth` top at 100 km) equals
    # column_du's (above 100 km: 1e-6 of the column), within 1e-5.
    top = preset("earth").atmosphere_height_m
    assert profile.column_m(top) * n.max() / DOBSON_UNIT_PER_M2 == pytest.approx(
        standard_ozone_column_du(), rel=1e-5
    )
    # with_ozone(300) on this profile: integrate the resulting number density, absorption
    # extinction / σ at 600 nm × the relative density, by the trapezoid rule on a 10 m grid
    # (error ~1e-7 here), and get 300 DU within 1e-4.
    params = preset("earth").with_(absorption_density=profile).with_ozone(300.0)
    peak_m3 = float(params.absorption_extinction.at(600.0) / ozone_cross_section(600.0))
    h = np.arange(0.0, top + 1.0, 10.0)
    column_m2 = np.trapezoid(peak_m3 * profile.density(h), h)
    assert column_m2 / DOBSON_UNIT_PER_M2 == pytest.approx(300.0, rel=1e-4)
    assert params.ozone_du == pytest.approx(300.0, rel=1e-6)


# --- Ozone cross-sections (skydome/data/solar_ozone_10nm.csv) ---


def test_chappuis_band_of_the_shipped_cross_sections():
    # The table's ozone column is Bruneton's (2017) kOzoneCrossSection: the IUP Bremen data
    # of Serdyuchenko et al. (2014) / Gorshelev et al. (2014) at 233 K, averaged over each
    # 10 nm bin. The Chappuis band is centred near 600-610 nm (Burrows et al. 1999, J.
    # Quant. Spectrosc. Radiat. Transfer 61, 509); its maximum cross-section is about 5.0e-21
    # cm^2 = 5.0e-25 m^2. The largest bin must be 600-610 nm, within 5 % of that (5.019e-25).
    bins_nm = np.arange(360.0, 830.0, 10.0)
    sigma = ozone_cross_section(bins_nm + 5.0)
    assert bins_nm[np.argmax(sigma)] == 600.0
    assert sigma.max() == pytest.approx(5.0e-25, rel=0.05)
    # The same 233 K data set sampled at single wavelengths by another program (CalcMySky,
    # from serdyuchenkogorshelevversionjuly2013): 3.264e-25, 4.514e-25 and 4.544e-25 m^2 at
    # 548.0, 579.3 and 610.7 nm. The bin means interpolated there differ from point values
    # by the band's vibronic structure; bound 3 %, measured −1.5 %, +0.4 %, +1.5 %.
    np.testing.assert_allclose(
        ozone_cross_section([548.0, 579.3, 610.7]), [3.264e-25, 4.514e-25, 4.544e-25], rtol=0.03
    )


# --- Ozone matters at dusk ---


def test_ozone_makes_the_twilight_zenith_blue(ctx):
    """Hulburt (1953, J. Opt. Soc. Am. 43, 113): at civil twilight the zenith sky is lit by
    sunlight that has crossed the ozone layer edge-on, and the Chappuis band's absorption of
    its orange and red, not Rayleigh scattering, makes it blue; without ozone it would be
    grey-yellow. The precomputed renderer at the zenith, Sun at −6°: linear sRGB B/R of
    `earth` (300 DU) against the same air with no ozone.

    Measured: B/R 4.02 with ozone, 1.10 without (ratio 0.27; with the AFGL 1986 ozone
    profile instead of the tent, 3.94 and 1.10). Bounds: removing the ozone at least halves
    B/R, and leaves the zenith nearly grey, B/R below 1.5 (Rayleigh scattering alone of
    reddened light: a pale blue-grey, not Hulburt's deep blue).
    """
    from skydome.atmosphere.precompute_config import PrecomputeConfig
    from skydome.core.cameras import DirectionsCamera, direction_from_angles
    from tests.air_frames import AirFrames

    zenith = np.array([[0.0, 0.0, 1.0]])
    sun = direction_from_angles(-6.0, 90.0)
    blue_over_red = {}
    for du in (None, 0.0):
        r = AirFrames(
            preset("earth", ozone_du=du), config=PrecomputeConfig(wavelengths="accurate", orders=4)
        )
        try:
            rgb = r.render(DirectionsCamera(zenith), 0, 0, sun_direction=sun).data[0, 0, :3]
        finally:
            r.release()
        assert np.all(rgb > 0)
        blue_over_red[du] = float(rgb[2] / rgb[0])
    with_ozone, without = blue_over_red[None], blue_over_red[0.0]
    assert with_ozone > 2.0  # the blue twilight zenith
    assert without < 0.5 * with_ozone
    assert without < 1.5
