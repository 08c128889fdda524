"""Spectra and colour against published values."""

import numpy as np
import pytest

from skydome.errors import ParameterError
from skydome.spectra import (
    LINEAR_SRGB_TO_XYZ,
    LUMINOUS_SOLAR_CONSTANT_LX,
    cmf_xyz,
    photopic_efficiency,
    scotopic_efficiency,
    solar_irradiance,
    spectral_to_rgbs_matrix,
    wavelengths,
)


def test_cie_tables_published_points():
    # CIE 1931: y_bar(555) = 1.0000, x_bar(600) = 1.0622, z_bar(445) = 1.7826 (CIE 15:2004).
    x, y, z = cmf_xyz([555.0, 600.0, 445.0]).T
    assert y[0] == pytest.approx(1.0, abs=1e-4)
    assert x[1] == pytest.approx(1.0622, abs=1e-4)
    assert z[2] == pytest.approx(1.7826, abs=1e-4)
    # V(λ) equals y_bar; V'(507) = 0.9982 and V'(505) = 0.9982 around the 507 nm peak.
    assert photopic_efficiency(555.0) == pytest.approx(1.0, abs=1e-4)
    assert scotopic_efficiency(505.0) == pytest.approx(0.998, abs=2e-3)


def test_srgb_white_is_d65():
    # IEC 61966-2-1: linear sRGB (1, 1, 1) is D65 with Y = 1: XYZ = (0.9505, 1.0000, 1.0890).
    np.testing.assert_allclose(LINEAR_SRGB_TO_XYZ @ np.ones(3), [0.9505, 1.0, 1.0890], atol=5e-4)


def test_luminous_solar_constant():
    # Unit transfer spectrum = the extraterrestrial Sun itself; its illuminance at 1 AU is the
    # luminous solar constant, 133 334 lx (Darula, Kittler & Gueymard 2005, LEUKOS 1(3)),
    # skydome's one value of it. Measured 133 177 lx (-0.118 %, from the packaged table's
    # 10 nm bins, see LUMINOUS_SOLAR_CONSTANT_LX); 0.2 % bound. Any error in the table, the
    # CIE functions, the 683 lm/W or the integration weights of that size fails it.
    assert LUMINOUS_SOLAR_CONSTANT_LX == 133_334.0
    m = spectral_to_rgbs_matrix(wavelengths("accurate"))
    rgb = m[:3] @ np.ones(m.shape[1])
    y = LINEAR_SRGB_TO_XYZ[1] @ rgb
    assert y == pytest.approx(LUMINOUS_SOLAR_CONSTANT_LX, rel=0.002)
    # The Sun is slightly warm of D65 in sRGB: R > G > B, all positive.
    assert rgb[0] > rgb[1] > rgb[2] > 0


def test_solar_irradiance_published_bins():
    # ASTM G-173 extraterrestrial spectrum: about 1.9 W/m^2/nm near 500 nm, 1.4 near 700 nm.
    assert solar_irradiance(505.0) == pytest.approx(1.92, rel=0.05)
    assert solar_irradiance(705.0) == pytest.approx(1.41, rel=0.05)


@pytest.mark.parametrize("mode", ["fast", "accurate"])
def test_spectral_modes_reproduce_fine_integration(mode):
    # Skylight-like transfer spectra (Rayleigh λ^-4 scattering times extinction over air
    # masses 1..10) converted from the mode's samples agree with a 1 nm integration within
    # 0.5% (16 wavelengths) or 4% (4 wavelengths, the documented cost of the fast mode).
    tol = {"fast": 0.04, "accurate": 0.005}[mode]
    fine = np.arange(360.0, 831.0)
    wl = wavelengths(mode)
    for airmass in (1.0, 3.0, 10.0):

        def f(w, airmass=airmass):
            return (w / 550.0) ** -4 * np.exp(-airmass * 0.1 * (w / 550.0) ** -4)

        ref = spectral_to_rgbs_matrix(fine) @ f(fine)
        got = spectral_to_rgbs_matrix(wl) @ f(wl)
        np.testing.assert_allclose(got, ref, rtol=tol)


def test_bad_wavelengths():
    with pytest.raises(ParameterError):
        wavelengths("ultra")
    with pytest.raises(ParameterError):
        wavelengths([400, 500, 600])  # not a multiple of 4
    with pytest.raises(ParameterError):
        cmf_xyz([300.0])
