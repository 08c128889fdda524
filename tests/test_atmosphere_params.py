"""Atmosphere parameters: presets against their sources, validation."""

import numpy as np
import pytest

from skydome.atmosphere import PRESETS, DensityProfile, Spectrum, earth, preset
from skydome.errors import ParameterError


def test_earth_matches_seed_001_appendix_b():
    p = earth()
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


def test_ozone_column_is_300_dobson():
    # The tent integrates to 15 km; peak number density x 15 km = 300 DU = 8.06e22 m^-2.
    from skydome.atmosphere.presets import OZONE_PEAK_NUMBER_DENSITY

    h = np.linspace(0, 60e3, 60001)
    column = np.trapezoid(earth().absorption_density.density(h), h) * OZONE_PEAK_NUMBER_DENSITY
    assert column == pytest.approx(300 * 2.687e20, rel=1e-6)


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
