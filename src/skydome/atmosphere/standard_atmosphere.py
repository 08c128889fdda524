"""The U.S. Standard Atmosphere 1976, shipped as a table, and the air density profile from it.

``skydome/data/us_standard_atmosphere_1976.csv`` holds temperature, pressure, density and
number density every 500 m of geometric altitude from 0 to 100 km (U.S. Standard Atmosphere,
1976, NOAA-S/T 76-1562; a U.S. Government work, public domain). Below 86 km the values come
from the standard's defining equations, from 86 to 100 km from its temperature equations and
its tabulated composition (Table VIII); ``tools/build_us_standard_atmosphere.py`` writes the
file and says how.

``air_density_profile()`` is the relative air density (1 at sea level) as a tabulated
:class:`~skydome.atmosphere.params.DensityProfile`, log-linear between the 500 m samples,
ready for ``AtmosphereParams.with_(rayleigh_density=...)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from importlib import resources

import numpy as np

from skydome.atmosphere.params import DensityProfile

#: The shipped table (see the module docstring and the file's header).
US_STANDARD_1976_FILE = "us_standard_atmosphere_1976.csv"
_COLUMNS = ("altitude_m", "temperature_K", "pressure_Pa", "density_kg_m3", "number_density_m3")


@dataclass(frozen=True)
class StandardAtmosphere:
    """A standard atmosphere sampled at increasing geometric altitudes (fresh float64 arrays)."""

    altitude_m: np.ndarray  #: geometric altitude above mean sea level, m
    temperature_K: np.ndarray  #: kinetic temperature, K
    pressure_Pa: np.ndarray  #: pressure, Pa
    density_kg_m3: np.ndarray  #: mass density, kg/m^3
    number_density_m3: np.ndarray  #: number density of air molecules, m^-3


@cache
def _read_table() -> np.ndarray:
    text = (resources.files("skydome") / "data" / US_STANDARD_1976_FILE).read_text()
    rows = [ln for ln in text.splitlines() if ln and not ln.startswith("#")]
    if tuple(rows[0].split(",")) != _COLUMNS:
        raise ValueError(f"{US_STANDARD_1976_FILE}: unexpected columns {rows[0]}")
    table = np.array([[float(v) for v in r.split(",")] for r in rows[1:]])
    table.setflags(write=False)
    return table


def us_standard_1976() -> StandardAtmosphere:
    """The U.S. Standard Atmosphere 1976 from 0 to 100 km every 500 m (201 samples)."""
    t = _read_table()
    return StandardAtmosphere(*(t[:, k].copy() for k in range(len(_COLUMNS))))


def air_density_profile() -> DensityProfile:
    """Relative air density of the U.S. Standard Atmosphere 1976: number density over its
    sea-level value (2.547e25 m^-3), tabulated every 500 m from 0 to 100 km.

    Number density, not mass density, because Rayleigh scattering is per molecule (the two
    differ by M / M0, under 0.04 % below 86 km and 2 % at 100 km). Above 100 km the profile
    continues the exponential of its last 500 m (see :meth:`DensityProfile.tabulated`).
    """
    t = _read_table()
    n = t[:, 4]
    return DensityProfile.tabulated(t[:, 0], n / n[0])
