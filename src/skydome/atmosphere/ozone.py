"""A standard vertical profile of ozone, shipped as a table, and its column in Dobson units.

The profile is the U.S. Standard ozone of Anderson et al. (1986), "AFGL Atmospheric
Constituent Profiles (0-120 km)", AFGL-TR-86-0110, Table 1f: number density = the table's
air number density × its ozone volume mixing ratio, at 50 altitudes from 0 to 120 km
(``skydome/data/ozone_profile_afgl1986_us_standard.csv``; a U.S. Government work, public
domain). It follows the mid-latitude ozone model of the U.S. Standard Atmosphere 1976
(Table 18: 0.345 atm-cm = 345 DU, peak 4.86e18 m⁻³ at 22 km) and reaches the ground, which
that table does not. Its column is 344.2 DU, its peak 4.89e18 m⁻³ at 22 km.

``ozone_density_profile()`` is the relative profile (1 at the peak) as a tabulated
:class:`~skydome.atmosphere.params.DensityProfile` (log-linear between samples), ready for
``AtmosphereParams.with_(absorption_density=...)``; ``with_ozone(dobson=...)`` then scales it
to any total column.
"""

from __future__ import annotations

from importlib import resources

import numpy as np

from skydome.atmosphere.params import DOBSON_UNIT_PER_M2, DensityProfile
from skydome.errors import ParameterError

#: The shipped profile (see the module docstring and the file's header).
OZONE_PROFILE_FILE = "ozone_profile_afgl1986_us_standard.csv"


def _read_profile_table() -> np.ndarray:
    text = (resources.files("skydome") / "data" / OZONE_PROFILE_FILE).read_text()
    rows = [ln for ln in text.splitlines() if ln and not ln.startswith("#")][1:]
    return np.array([[float(v) for v in r.split(",")] for r in rows])


def standard_ozone_profile() -> tuple[np.ndarray, np.ndarray]:
    """(altitudes_m, number_density_m3): the AFGL 1986 U.S. Standard ozone profile.

    Geometric altitudes 0-120 km (1 km steps to 25 km, then 2.5 and 5 km) and ozone number
    densities in molecules per m³ (fresh arrays, float64).
    """
    t = _read_profile_table()
    return t[:, 0].copy(), t[:, 1].copy()


def column_du(altitudes_m, number_density_m3) -> float:
    """Total column of a tabulated number-density profile, in Dobson units (2.687e20 m⁻²).

    The density is taken as log-linear between samples (linear where a sample is 0), the
    interpolation of ``DensityProfile.tabulated``, and integrated exactly from the first
    sample to the last: Δz (n1 − n0) / ln(n1/n0) per piece.
    """
    z = np.asarray(altitudes_m, dtype=np.float64)
    n = np.asarray(number_density_m3, dtype=np.float64)
    if z.ndim != 1 or z.shape != n.shape or z.size < 2 or np.any(np.diff(z) <= 0):
        raise ParameterError("column_du needs matching 1-D arrays with increasing altitudes")
    if np.any(n < 0) or not np.all(np.isfinite(n)):
        raise ParameterError("number densities must be finite and >= 0")
    n0, n1, dz = n[:-1], n[1:], np.diff(z)
    linear = (n0 == 0.0) | (n1 == 0.0) | np.isclose(n0, n1, rtol=1e-12)
    with np.errstate(divide="ignore", invalid="ignore"):
        pieces = np.where(linear, 0.5 * (n0 + n1) * dz, (n1 - n0) * dz / np.log(n1 / n0))
    return float(np.sum(pieces)) / DOBSON_UNIT_PER_M2


def standard_ozone_column_du() -> float:
    """Total column of :func:`standard_ozone_profile`, 0-120 km, in Dobson units (344.2)."""
    return column_du(*standard_ozone_profile())


def ozone_density_profile() -> DensityProfile:
    """The standard ozone profile relative to its peak (1 at 22 km), as a tabulated
    DensityProfile. Its column is 18.9 km (the layer's thickness at peak density);
    ``AtmosphereParams.with_ozone(dobson)`` divides by it to set any total column."""
    z, n = standard_ozone_profile()
    return DensityProfile.tabulated(z, n / n.max())
