"""Tabulated spectra shipped with the package, read once and interpolated on demand.

Sources (see the header lines of each CSV in ``skydome/data``):
- CIE 1931 2-degree colour matching functions, 360-830 nm, 5 nm (CVRL ciexyz31).
- CIE 1924 photopic V(lambda) and CIE 1951 scotopic V'(lambda), 5 nm.
- ASTM G-173 extraterrestrial solar spectral irradiance, 10 nm bin means (W m^-2 nm^-1).
- Ozone absorption cross-section at 233 K, 10 nm bin means (m^2): the IUP Bremen data of
  Serdyuchenko et al. (2014, Atmos. Meas. Tech. 7, 625; measurements: Gorshelev et al. 2014,
  ibid. 609; 213-1100 nm, 11 temperatures), each value the mean of the 233 K spectrum over
  [λ, λ + 10 nm). The 48 values are those of Bruneton's 2017 demo (kOzoneCrossSection), which
  states this source and binning. Checked (tests/test_rayleigh_ozone.py): the largest bin is
  600-610 nm, the Chappuis band's centre (Burrows et al. 1999, JQSRT 61, 509), at 5.02e-25 m^2
  (5.02e-21 cm^2); point values of the same 233 K data at 548, 579 and 611 nm, sampled by
  another program, agree within 1.5 %.
- Spectral albedos of surfaces by IGBP land-cover type (grassland, cropland, forest, desert,
  snow, ocean, urban): the reference table of the U.S. EPA's CMAQ model (public domain), at
  its band centres 340-1000 nm.
"""

from __future__ import annotations

from functools import cache
from importlib import resources

import numpy as np

from skydome.errors import ParameterError

WAVELENGTH_MIN_NM = 360.0
WAVELENGTH_MAX_NM = 830.0


@cache
def _table(name: str) -> np.ndarray:
    text = (resources.files("skydome") / "data" / name).read_text()
    rows = [ln for ln in text.splitlines() if ln and not ln.startswith("#")][1:]
    return np.array([[float(v) for v in r.split(",")] for r in rows])


def _check_wavelengths(wavelengths_nm) -> np.ndarray:
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    if (
        not np.all(np.isfinite(wl))
        or wl.min(initial=WAVELENGTH_MIN_NM) < WAVELENGTH_MIN_NM
        or wl.max(initial=WAVELENGTH_MAX_NM) > WAVELENGTH_MAX_NM
    ):
        raise ParameterError(
            f"wavelengths must lie in [{WAVELENGTH_MIN_NM:g}, {WAVELENGTH_MAX_NM:g}] nm, got {wavelengths_nm}"
        )
    return wl


def cmf_xyz(wavelengths_nm) -> np.ndarray:
    """CIE 1931 2-degree colour matching functions x̄, ȳ, z̄, shape (..., 3), linear interpolation."""
    t = _table("cie1931_2deg_cmf_5nm.csv")
    wl = _check_wavelengths(wavelengths_nm)
    return np.stack([np.interp(wl, t[:, 0], t[:, i]) for i in (1, 2, 3)], axis=-1)


def photopic_efficiency(wavelengths_nm) -> np.ndarray:
    """CIE 1924 photopic luminous efficiency V(λ) (peak 1 at 555 nm)."""
    t = _table("cie_luminous_efficiency_5nm.csv")
    return np.interp(_check_wavelengths(wavelengths_nm), t[:, 0], t[:, 1])


def scotopic_efficiency(wavelengths_nm) -> np.ndarray:
    """CIE 1951 scotopic luminous efficiency V'(λ) (peak 1 at 507 nm)."""
    t = _table("cie_luminous_efficiency_5nm.csv")
    return np.interp(_check_wavelengths(wavelengths_nm), t[:, 0], t[:, 2])


def solar_irradiance(wavelengths_nm) -> np.ndarray:
    """Top-of-atmosphere solar spectral irradiance at 1 AU, W m^-2 nm^-1 (ASTM G-173).

    The table holds 10 nm bin means; they are placed at bin centres and interpolated.
    """
    t = _table("solar_ozone_10nm.csv")
    centres = t[:, 0] + 5.0
    return np.interp(_check_wavelengths(wavelengths_nm), centres, t[:, 1])


def ozone_cross_section(wavelengths_nm) -> np.ndarray:
    """Ozone absorption cross-section at 233 K, m^2 per molecule (Serdyuchenko et al. 2014)."""
    t = _table("solar_ozone_10nm.csv")
    centres = t[:, 0] + 5.0
    return np.interp(_check_wavelengths(wavelengths_nm), centres, t[:, 2])


#: The surfaces of ``surface_albedo_igbp.csv``, in its column order.
SURFACES = ("grassland", "cropland", "forest", "desert", "snow", "ocean", "urban")


def surface_albedo(surface: str) -> tuple[np.ndarray, np.ndarray]:
    """The spectral albedo (0-1) of a surface of :data:`SURFACES`: its band centres (nm,
    340-1000) and values, to be interpolated linearly (CMAQ's IGBP reference table)."""
    if surface not in SURFACES:
        raise ParameterError(f"surface {surface!r} must be one of {', '.join(SURFACES)}")
    t = _table("surface_albedo_igbp.csv")
    return t[:, 0].copy(), t[:, 1 + SURFACES.index(surface)].copy()
