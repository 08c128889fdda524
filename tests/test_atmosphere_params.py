"""Atmosphere parameters: presets against their sources, validation."""

import numpy as np
import pytest

from skydome.atmosphere import (
    PRESETS,
    DensityProfile,
    Spectrum,
    earth,
    earth_bruneton,
    preset,
)
from skydome.errors import ParameterError

#: The presets' spectral grid: 360-830 nm every 5 nm (the range the renderer samples).
GRID_NM = np.arange(360.0, 831.0, 5.0)


def test_earth_bruneton_matches_seed_001_appendix_b():
    # The seeds' Earth, kept as earth_bruneton (until the measured Earth it was `earth`): all
    # of its physics is seed 001 appendix B, exactly. The stored Monte Carlo reference
    # (tests/data/ms_reference_earth*.npz) was made with it; test_ms_reference.py ties the
    # file to this preset's digest.
    p = earth_bruneton()
    c = p.coefficients([680.0, 550.0, 440.0])
    # Appendix B: Rayleigh (5.802, 13.558, 33.100)e-3 /km; Mie 3.996e-3 scattering,
    # 0.444e-3 absorption; g 0.8; radii 6360 km, height 100 km; albedo 0.3.
    np.testing.assert_allclose(
        c["rayleigh_scattering"], [5.802e-6, 13.558e-6, 33.100e-6], rtol=2e-3
    )
    np.testing.assert_allclose(c["mie_scattering"], 3.996e-6)
    np.testing.assert_allclose(c["mie_extinction"] - c["mie_scattering"], 0.444e-6, rtol=1e-9)
    # Ozone (0.650, 1.881, 0.085)e-3 /km "at 680, 550, 440 nm": these are Bruneton's 10 nm
    # bin means (bins starting at those wavelengths), which our table places at the bin
    # centres, 685, 555 and 445 nm; 300 DU over 15 km reproduces them to 0.1%.
    ozone = p.absorption_extinction.at([685.0, 555.0, 445.0])
    np.testing.assert_allclose(ozone, [0.650e-6, 1.881e-6, 0.085e-6], rtol=2e-3)
    assert p.mie_g == 0.8 and p.bottom_radius_m == 6.36e6 and p.atmosphere_height_m == 1e5
    # Density profiles: e^(-h/8000), e^(-h/1200), ozone tent max(0, 1 - |h - 25 km| / 15 km).
    h = np.array([0.0, 8000.0, 1200.0, 10e3, 25e3, 32.5e3, 40e3, 60e3])
    np.testing.assert_allclose(p.rayleigh_density.density(h), np.exp(-h / 8000.0), rtol=1e-12)
    np.testing.assert_allclose(p.mie_density.density(h), np.exp(-h / 1200.0), rtol=1e-12)
    np.testing.assert_allclose(
        p.absorption_density.density(h), np.maximum(0, 1 - np.abs(h - 25e3) / 15e3), atol=1e-12
    )
    # The rest of its physics: top at 6460 km, Mie scattering and extinction grey over the
    # whole grid, Rayleigh λ^-4 through 13.558e-6 /m at 550 nm, albedo 0.3 everywhere, the Sun
    # (959.63" radius at 1 AU, the tabulated solar spectrum, as for every Earth preset).
    from skydome.spectra.tables import solar_irradiance

    assert p.top_radius_m == 6.46e6 and p.sun_angular_radius_rad == pytest.approx(
        np.radians(959.63 / 3600.0), rel=1e-12
    )
    g = p.coefficients(GRID_NM)
    np.testing.assert_array_equal(g["mie_scattering"], 3.996e-6)
    np.testing.assert_array_equal(g["mie_extinction"], 4.440e-6)
    np.testing.assert_allclose(
        g["rayleigh_scattering"], 13.558e-6 * (GRID_NM / 550.0) ** -4.0, rtol=1e-4
    )
    np.testing.assert_array_equal(g["ground_albedo"], 0.3)
    np.testing.assert_allclose(g["solar_irradiance"], solar_irradiance(GRID_NM), rtol=1e-12)
    assert p.aod_550 == pytest.approx(4.44e-6 * 1200.0, rel=1e-6) and p.ozone_du == pytest.approx(
        300.0, rel=1e-9
    )


def test_earth_is_the_measured_earth():
    # earth (the default since the measured Earth): Rayleigh from Bodhaine et al. 1999 times
    # the U.S. Standard Atmosphere 1976 sea-level number density, 1.149e-5 /m at 550 nm
    # (measured 1.14882e-5; the seeds' Bruneton value 13.558e-6 is 18 % more), its vertical
    # optical depth through the standard's tabulated air 0.0971 (measured 0.09712), 300 DU
    # of AFGL ozone, OPAC clean-continental aerosol at AOD 0.1 (the preset's definitions).
    p = earth()
    assert p.coefficients([550.0])["rayleigh_scattering"][0] == pytest.approx(1.149e-5, rel=1e-3)
    h = np.linspace(0.0, p.atmosphere_height_m, 200_001)
    tau = p.coefficients([550.0])["rayleigh_scattering"][0] * np.trapezoid(
        p.rayleigh_density.density(h), h
    )
    assert tau == pytest.approx(0.0971, rel=1e-3)
    assert p.ozone_du == pytest.approx(300.0, rel=1e-9)
    assert p.aod_550 == pytest.approx(0.1, rel=1e-6)
    assert p.bottom_radius_m == 6.36e6 and p.atmosphere_height_m == 1e5


@pytest.mark.parametrize("name", list(PRESETS))
def test_every_preset_builds_with_finite_coefficients(name):
    # Every preset builds, and over the whole grid its coefficients are finite and
    # non-negative, Mie scattering <= extinction (an albedo <= 1), the ground albedo in
    # [0, 1], Rayleigh positive, the Sun's irradiance positive; its AOD, ozone column and
    # Mie g are finite (g within the validated range).
    p = PRESETS[name]()
    c = p.coefficients(GRID_NM)
    for key, values in c.items():
        assert values.shape == GRID_NM.shape, (name, key)
        assert np.all(np.isfinite(values)) and np.all(values >= 0.0), (name, key)
    assert np.all(c["mie_scattering"] <= c["mie_extinction"] * (1 + 1e-12)), name
    assert np.all(c["ground_albedo"] <= 1.0), name
    assert np.all(c["rayleigh_scattering"] > 0.0) and np.all(c["solar_irradiance"] > 0.0), name
    assert np.isfinite(p.aod_550) and np.isfinite(p.ozone_du), name
    assert -0.999 <= p.mie_g <= 0.999, name
    assert p.top_radius_m > p.bottom_radius_m > 0.0, name


def test_ozone_column_is_300_dobson():
    # The seeds' tent (earth_bruneton) integrates to 15 km; peak number density x 15 km =
    # 300 DU = 8.06e22 m^-2 (OZONE_PEAK_NUMBER_DENSITY is the tent's peak, so it applies to
    # earth_bruneton only; earth's AFGL profile is checked through its absorption below).
    from skydome.atmosphere.presets import OZONE_PEAK_NUMBER_DENSITY
    from skydome.spectra.tables import ozone_cross_section

    h = np.linspace(0, 60e3, 60001)
    tent = earth_bruneton().absorption_density.density(h)
    column = np.trapezoid(tent, h) * OZONE_PEAK_NUMBER_DENSITY
    assert column == pytest.approx(300 * 2.687e20, rel=1e-6)
    # earth: peak number density k(600 nm) / σ(600 nm), times its profile's column (to
    # 100 km, 0.5 m steps; the AFGL nodes every 500 m lie on the grid): 300 DU to 1e-4.
    p = earth()
    h = np.linspace(0, p.atmosphere_height_m, 200_001)
    n_peak = p.absorption_extinction.at(600.0) / ozone_cross_section(600.0)
    column = np.trapezoid(p.absorption_density.density(h), h) * n_peak
    assert column == pytest.approx(300 * 2.687e20, rel=1e-4)


def test_nishita_preset_matches_seed_002():
    c = preset("earth_nishita").coefficients([680.0, 550.0, 440.0])
    # Seed 002: 5.8e-6, 13.5e-6, 33.1e-6 /m; Mie 21e-6 with extinction 1.1x.
    np.testing.assert_allclose(c["rayleigh_scattering"], [5.8e-6, 13.5e-6, 33.1e-6], rtol=0.01)
    np.testing.assert_allclose(c["mie_extinction"] / c["mie_scattering"], 1.1)


@pytest.mark.parametrize("name", list(PRESETS))
def test_presets_are_valid_and_distinct(name):
    p = preset(name)
    assert p.name == name
    assert p.digest() == preset(name).digest()
    others = {preset(n).digest() for n in PRESETS if n != name}
    assert p.digest() not in others


def test_validation_names_value_and_range():
    with pytest.raises(ParameterError, match=r"mie_g = 1.5 .*\[-0.999, 0.999\]"):
        earth().with_(mie_g=1.5)
    with pytest.raises(ParameterError, match="top_radius_m"):
        earth().with_(top_radius_m=6_000_000.0)
    with pytest.raises(ParameterError, match="ground_albedo"):
        earth().with_(ground_albedo=Spectrum.constant(1.5))
    with pytest.raises(ParameterError, match="mie_extinction"):
        earth().with_(mie_extinction=Spectrum.constant(1e-6))
    with pytest.raises(ParameterError, match="unknown atmosphere preset 'venus'"):
        preset("venus")
    with pytest.raises(ParameterError):
        DensityProfile.exponential(-5.0)


def test_params_are_immutable():
    p = earth()
    with pytest.raises(AttributeError):
        p.mie_g = 0.5  # type: ignore[misc]
