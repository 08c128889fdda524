"""The Martian atmosphere from published profiles (skydome.atmosphere.mars_atmosphere) and its
sky: butterscotch by day, blue around the setting Sun."""

from __future__ import annotations

import numpy as np
import pytest

from skydome.atmosphere import mars_atmosphere as mars
from skydome.atmosphere import preset
from skydome.io.packaged import read_packaged_csv

MARS_GRAVITY_M_S2 = 3.711  # NASA Mars fact sheet, at the mean radius
MARS_MOLAR_MASS_KG_PER_MOL = 43.34e-3  # NASA Mars fact sheet: mean molecular weight
AVOGADRO_PER_MOL = 6.02214076e23


def test_gas_profile_reproduces_the_published_table():
    # Justus, Duvall & Keller (2005) Table 1 at its own heights: the tabulated profile is
    # log-linear between them, so it returns them to float rounding (bound 0.5 %, issue 14).
    t = read_packaged_csv(mars.MARS_PROFILE_FILE)
    profile = mars.mars_gas_density()
    rho0 = mars.mars_profile()["density_kg_m3"][0]
    got = profile.density(t["height_km"] * 1000.0) * rho0
    np.testing.assert_allclose(got, t["density_kg_m3"], rtol=5e-3)


def test_the_table_is_hydrostatic_and_an_ideal_gas():
    # Independent checks of the transcription: p = rho R T / M with the fact sheet's mean
    # molecular weight, 43.34 g/mol, to 1.5 % (the table's own M rises from 43.50 to 43.80
    # g/mol with height: Mars-GRAM's composition), and the
    # pressure drop between levels equals the weight of the gas between them, g rho dz, to 2 %
    # (g falls 0.6 % per 10 km; trapezoid over ~2.5 km steps).
    t = read_packaged_csv(mars.MARS_PROFILE_FILE)
    r_gas = 8.314462 / MARS_MOLAR_MASS_KG_PER_MOL
    np.testing.assert_allclose(
        t["pressure_Pa"], t["density_kg_m3"] * r_gas * t["temperature_K"], rtol=0.015
    )
    z = t["height_km"] * 1000.0
    g = MARS_GRAVITY_M_S2 * (mars.MARS_RADIUS_M / (mars.MARS_RADIUS_M + z)) ** 2
    weight = np.log(t["pressure_Pa"][:-1] / t["pressure_Pa"][1:])
    expected = 0.5 * (g[:-1] * t["density_kg_m3"][:-1] / t["pressure_Pa"][:-1]
                      + g[1:] * t["density_kg_m3"][1:] / t["pressure_Pa"][1:]) * np.diff(z)  # fmt: skip
    np.testing.assert_allclose(weight, expected, rtol=0.02)


def test_surface_pressure_is_martian():
    # Extrapolated 2.17 km down to the areoid: 583 Pa, against Mars' mean surface pressure of
    # about 610 Pa (NASA fact sheet 636 Pa at the mean radius; it varies 400-870 Pa by season
    # and place): within 10 %.
    p0 = mars.mars_profile()["pressure_Pa"][0]
    assert p0 == pytest.approx(610.0, rel=0.10)


def test_rayleigh_optical_depth_from_the_column_mass():
    # tau = sigma_CO2 x N_column, N_column = p0 N_A / (g M): the hydrostatic column with the
    # fact sheet's M, independent of the density table's shape and of its number density.
    # Within 3 % (g falls with height; M differs from the table's by 0.4-1 %).
    params = preset("mars")
    wl = np.array([450.0, 550.0, 650.0])
    tau = params.rayleigh_scattering.at(wl) * params.rayleigh_density.column_m(
        params.atmosphere_height_m
    )
    n0 = mars.mars_ground_number_density_m3()
    sigma = params.rayleigh_scattering.at(wl) / n0
    p0 = mars.mars_profile()["pressure_Pa"][0]
    column = p0 / MARS_GRAVITY_M_S2 / MARS_MOLAR_MASS_KG_PER_MOL * AVOGADRO_PER_MOL
    np.testing.assert_allclose(tau, sigma * column, rtol=0.03)


def test_dust_optics_are_what_the_tool_builds():
    # One row of mars_dust.csv rebuilt from its k by Mie theory: the same albedo and weights.
    from skydome.atmosphere import mie

    d = read_packaged_csv(mars.MARS_DUST_FILE)
    i = int(np.argmin(np.abs(d["wavelength_nm"] - 560.0)))
    th = np.concatenate([np.linspace(0.0, 10.0, 101), np.linspace(10.5, 180.0, 340)])
    mu = np.cos(np.radians(th))
    optics = mie.bulk_optics(1.5 + 1j * d["k"][i], d["wavelength_nm"][i] / 1000.0, 1.71, 0.25, mu)
    assert optics.ssa == pytest.approx(d["ssa"][i], abs=1e-4)
    assert optics.asymmetry == pytest.approx(d["asymmetry"][i], abs=1e-4)
    fit = (th >= 1.0) & (th <= 150.0)
    w = mie.fit_hg_lobes(np.radians(th[fit]), optics.phase[fit])
    names = [k for k in d if k.startswith("hg_")]
    np.testing.assert_allclose(w, [d[k][i] for k in names], atol=1e-4)


def test_dust_albedo_optical_depth_and_forward_peak():
    params = preset("mars")
    assert params.aod_550 == pytest.approx(mars.DUST_TAU_550, rel=1e-6)
    ssa = params.mie_scattering.at([440.0, 550.0, 700.0]) / params.mie_extinction.at(
        [440.0, 550.0, 700.0]
    )
    np.testing.assert_allclose(ssa, [0.62, 0.90, 0.97], atol=0.005)
    # Diffraction: the peak's height grows as x^2 = (2 pi r / lambda)^2, so at 2 deg the blue
    # (450 nm) phase function is well above the red (650 nm): (650/450)^2 = 2.1 for the
    # peak itself; at 2 deg, past the blue peak's core, at least 1.5x.
    p = params.mie_phase_function(np.cos(np.radians(2.0)), [450.0, 650.0])
    assert p[0] > 1.5 * p[1]


def test_dust_profile_follows_conrath():
    # q(p) = exp(nu (1 - p0/p)): the dust-to-gas ratio at 40 km, where p0/p ~ 86. Both
    # profiles are resampled every 500 m between the table's levels (log-linear), and the
    # resampled ratio misses the mixing ratio's curvature between them: 2e-3 (1.3e-3 seen).
    prof = mars.mars_profile()
    i = int(np.argmin(np.abs(prof["altitude_m"] - 40_000.0)))
    ratio = mars.mars_dust_density().density(prof["altitude_m"][i]) / mars.mars_gas_density(
    ).density(prof["altitude_m"][i])  # fmt: skip
    expected = np.exp(mars.CONRATH_NU * (1.0 - prof["pressure_Pa"][0] / prof["pressure_Pa"][i]))
    assert ratio == pytest.approx(expected, rel=2e-3)


def _sky_b_over_r(sun_elevation_deg: float, points):
    from skydome.core.cameras import DirectionsCamera, direction_from_angles
    from tests.air_frames import precomputed_frames

    sun = direction_from_angles(sun_elevation_deg, 180.0)
    dirs = np.array([direction_from_angles(e, a) for e, a in points])
    frame = precomputed_frames("mars").render(DirectionsCamera(dirs), 0, 0, sun_direction=sun)
    rgb = frame.data[0, :, :3].astype(np.float64)
    assert np.all(np.isfinite(rgb)) and np.all(rgb > 0.0)
    return rgb[:, 2] / rgb[:, 0]


def test_blue_around_the_setting_sun_butterscotch_elsewhere():
    # Sunsets seen by Viking, Pathfinder, Spirit and Curiosity: a blue glow a few degrees
    # around the Sun in a butterscotch sky. Sun 3 deg up: 2 deg above the Sun, blue exceeds
    # red (B/R > 1); 90 deg away B/R < 0.3.
    b_over_r = _sky_b_over_r(3.0, [(5.0, 180.0), (3.0, 270.0), (3.0, 90.0), (30.0, 0.0)])
    assert b_over_r[0] > 1.0, b_over_r
    assert b_over_r[1:].max() < 0.3, b_over_r


def test_daytime_sky_is_butterscotch():
    # Sun 45 deg: the sky 60-90 deg from it is red over blue (Pathfinder's "butterscotch").
    b_over_r = _sky_b_over_r(45.0, [(20.0, 90.0), (60.0, 0.0), (10.0, 270.0)])
    assert b_over_r.max() < 0.4, b_over_r
