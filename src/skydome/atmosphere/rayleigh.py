"""Rayleigh scattering of dry air from first principles (Bodhaine et al. 1999).

Bodhaine, Wood, Dutton & Slusser (1999), "On Rayleigh optical depth calculations",
J. Atmos. Oceanic Technol. 16, 1854-1861 (equation numbers below are theirs):

- refractive index of dry air at 288.15 K and 1013.25 hPa with 300 ppm CO2, Peck & Reeder
  (1972), eq. 18; scaled to other CO2 concentrations by Edlén's (1966) factor, eq. 19
  (at 360 ppm this is their eq. 21);
- King correction factor of air, eq. 23: the N2 and O2 factors of Bates (1984), eqs. 5-6,
  with Ar 1.00 and CO2 1.15, weighted by volume fraction;
- cross-section per molecule, eq. 22: σ = 24π³ (n² − 1)² / (λ⁴ N_s² (n² + 2)²) · F_air,
  with N_s = 2.546899e19 cm⁻³, the number density at which n was measured;
- optical depth of the whole column, eq. 30: τ = σ P A / (m_a g), with the mean molecular
  mass of dry air m_a (their eq. 17 of CO2) and the gravity of List (1968) at the
  mass-weighted column height above the site, their eq. 11.

Wavelengths are used as given, as Bodhaine et al. do (their Table 3 is computed that way);
σ is independent of the air's density, so the scattering coefficient at any altitude is
σ times the number density there.
"""

from __future__ import annotations

import math

import numpy as np

from skydome.errors import ParameterError, check_range

#: Avogadro's number used by Bodhaine et al. (1999), per mole.
AVOGADRO_PER_MOL = 6.0221367e23
#: Number density of air at 288.15 K and 1013.25 hPa, at which the refractive index of
#: Peck & Reeder (1972) holds: 2.546899e19 cm⁻³ (Bodhaine et al. 1999, eq. 24), per m³.
STANDARD_AIR_NUMBER_DENSITY_M3 = 2.546899e25
#: Sea-level pressure of the US Standard Atmosphere 1976 and of Bodhaine's Table 3, Pa.
SEA_LEVEL_PRESSURE_PA = 101325.0
#: Bates (1984) King factors of the minor constituents (Bodhaine et al. 1999, eq. 23).
KING_FACTOR_AR = 1.00
KING_FACTOR_CO2 = 1.15
#: Volume percentages of N2, O2 and Ar in dry air used in Bodhaine et al. (1999), eq. 23.
_N2_PERCENT, _O2_PERCENT, _AR_PERCENT = 78.084, 20.946, 0.934

#: Wavelength range (nm) of the formulas: Peck & Reeder fitted 230-1690 nm; Bates' King
#: factors hold over 200-1000 nm (outside, σ is an extrapolation).
WAVELENGTH_RANGE_NM = (200.0, 4000.0)
CO2_PPM_RANGE = (0.0, 10_000.0)


def _wavelengths_um(wavelength_nm) -> np.ndarray:
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    lo, hi = WAVELENGTH_RANGE_NM
    if not np.all(np.isfinite(wl)) or np.any(wl < lo) or np.any(wl > hi):
        raise ParameterError(f"wavelength_nm must lie in [{lo:g}, {hi:g}] nm, got {wavelength_nm}")
    return wl / 1000.0


def refractive_index_air(wavelength_nm, co2_ppm: float = 360.0) -> np.ndarray:
    """Refractive index n of dry air at 288.15 K and 1013.25 hPa (dimensionless).

    Peck & Reeder (1972) for 300 ppm CO2 (Bodhaine et al. 1999, eq. 18), times Edlén's
    CO2 factor 1 + 0.54 (C − 0.0003), C the CO2 volume fraction (their eq. 19).
    """
    co2 = check_range("co2_ppm", co2_ppm, *CO2_PPM_RANGE, "ppm")
    inv_wl2 = _wavelengths_um(wavelength_nm) ** -2.0
    n300_minus_1 = 1e-8 * (
        8060.51 + 2_480_990.0 / (132.274 - inv_wl2) + 17_455.7 / (39.32957 - inv_wl2)
    )
    return 1.0 + n300_minus_1 * (1.0 + 0.54 * (co2 * 1e-6 - 0.0003))


def king_factor_air(wavelength_nm, co2_ppm: float = 360.0) -> np.ndarray:
    """King correction factor F_air = (6 + 3ρ)/(6 − 7ρ) of dry air (dimensionless).

    Bodhaine et al. (1999) eq. 23: F(N2) = 1.034 + 3.17e-4 λ⁻² and F(O2) = 1.096 +
    1.385e-3 λ⁻² + 1.448e-4 λ⁻⁴ (Bates 1984, λ in µm), F(Ar) = 1.00, F(CO2) = 1.15, weighted
    by their volume percentages (78.084, 20.946, 0.934 and the CO2's).
    """
    co2_percent = check_range("co2_ppm", co2_ppm, *CO2_PPM_RANGE, "ppm") * 1e-4
    inv_wl2 = _wavelengths_um(wavelength_nm) ** -2.0
    f_n2 = 1.034 + 3.17e-4 * inv_wl2
    f_o2 = 1.096 + 1.385e-3 * inv_wl2 + 1.448e-4 * inv_wl2**2
    weighted = (
        _N2_PERCENT * f_n2
        + _O2_PERCENT * f_o2
        + _AR_PERCENT * KING_FACTOR_AR
        + co2_percent * KING_FACTOR_CO2
    )
    return weighted / (_N2_PERCENT + _O2_PERCENT + _AR_PERCENT + co2_percent)


def rayleigh_cross_section_m2(wavelength_nm, co2_ppm: float = 360.0) -> np.ndarray:
    """Rayleigh scattering cross-section per molecule of dry air, m² (Bodhaine eq. 22).

    σ = 24π³ (n² − 1)² / (λ⁴ N_s² (n² + 2)²) · F_air, with n and N_s at 288.15 K and
    1013.25 hPa. E.g. 4.51e-31 m² (4.51e-27 cm²) at 550 nm for 360 ppm CO2.
    """
    wl_m = _wavelengths_um(wavelength_nm) * 1e-6
    n2 = refractive_index_air(wavelength_nm, co2_ppm) ** 2
    ns = STANDARD_AIR_NUMBER_DENSITY_M3
    return (
        24.0
        * math.pi**3
        * (n2 - 1.0) ** 2
        / (wl_m**4 * ns**2 * (n2 + 2.0) ** 2)
        * king_factor_air(wavelength_nm, co2_ppm)
    )


def rayleigh_scattering_per_m(
    wavelength_nm, number_density_m3, co2_ppm: float = 360.0
) -> np.ndarray:
    """Rayleigh scattering coefficient β = σ(λ) N of dry air, per metre.

    ``number_density_m3``: molecules per m³ (e.g. 2.5470e25 at sea level in the US Standard
    Atmosphere 1976); broadcasts against ``wavelength_nm``.
    """
    n = np.asarray(number_density_m3, dtype=np.float64)
    if not np.all(np.isfinite(n)) or np.any(n < 0):
        raise ParameterError(f"number_density_m3 must be finite and >= 0, got {number_density_m3}")
    return rayleigh_cross_section_m2(wavelength_nm, co2_ppm) * n


def mean_molecular_mass_kg_per_mol(co2_ppm: float = 360.0) -> float:
    """Mean molecular mass of dry air, kg/mol: m_a = 15.0556 C + 28.9595 g/mol, C the CO2
    volume fraction (Bodhaine et al. 1999, eq. 17; 28.9649 g/mol at 360 ppm)."""
    co2 = check_range("co2_ppm", co2_ppm, *CO2_PPM_RANGE, "ppm")
    return (15.0556 * co2 * 1e-6 + 28.9595) * 1e-3


def column_gravity_m_s2(latitude_deg: float = 45.0, altitude_m: float = 0.0) -> float:
    """Acceleration of gravity at the mass-weighted height of the air column above a site, m/s².

    Bodhaine et al. (1999) eq. 11 (List 1968): sea-level g₀(φ) = 980.6160 (1 − 0.0026373
    cos 2φ + 0.0000059 cos² 2φ) cm/s², reduced to the height z_c = 0.73737 z + 5517.56 m
    (the mass-weighted mean height of the US Standard Atmosphere above altitude z) by a cubic
    in z_c. 9.789 m/s² at 45° and sea level.
    """
    lat = math.radians(check_range("latitude_deg", latitude_deg, -90.0, 90.0, "deg"))
    z = check_range("altitude_m", altitude_m, -500.0, 10_000.0, "m")
    c2 = math.cos(2.0 * lat)
    g0 = 980.6160 * (1.0 - 0.0026373 * c2 + 0.0000059 * c2**2)
    zc = 0.73737 * z + 5517.56
    g_cm_s2 = (
        g0
        - (3.085462e-4 + 2.27e-7 * c2) * zc
        + (7.254e-11 + 1.0e-13 * c2) * zc**2
        - (1.517e-17 + 6.0e-20 * c2) * zc**3
    )
    return g_cm_s2 / 100.0


def rayleigh_optical_depth(
    wavelength_nm,
    pressure_pa: float = SEA_LEVEL_PRESSURE_PA,
    latitude_deg: float = 45.0,
    altitude_m: float = 0.0,
    co2_ppm: float = 360.0,
) -> np.ndarray:
    """Vertical Rayleigh optical depth of the air above a site (dimensionless).

    Bodhaine et al. (1999) eq. 30: τ = σ P A / (m_a g), the cross-section times the column
    of molecules that the surface pressure ``pressure_pa`` holds up against the gravity
    ``column_gravity_m_s2(latitude_deg, altitude_m)``. 0.0971 at 550 nm, 1013.25 hPa, 45°,
    sea level.
    """
    p = check_range("pressure_pa", pressure_pa, 0.0, 2e5, "Pa")
    column_m2 = (
        p
        * AVOGADRO_PER_MOL
        / (mean_molecular_mass_kg_per_mol(co2_ppm) * column_gravity_m_s2(latitude_deg, altitude_m))
    )
    return rayleigh_cross_section_m2(wavelength_nm, co2_ppm) * column_m2
