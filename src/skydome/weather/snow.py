"""Snow: from the snowfall rate (mm/h of melted water) to the flakes and their extinction.

- Flake sizes: Gunn & Marshall (1958, J. Meteor. 15, 452): in melted diameter D (mm),
  N(D) = N0 exp(-Lambda D) with N0 = 3.8e3 S^-0.87 m^-3 mm^-1 and Lambda = 2.55 S^-0.48
  mm^-1, S the snowfall rate in mm/h of water.
- A flake is an aggregate of crystals, mostly air: its size is its melted drop's times
  (rho_w / rho_flake)^(1/3). With :data:`FLAKE_DENSITY_KG_M3` (100 kg/m^3, a loose dry
  aggregate's) a flake is 2.15 times its drop.
- Its extinction efficiency is 2 (it is hundreds of wavelengths across), so
  sigma_ext = 2 (pi / 4) k^2 N0 int D^2 exp(-Lambda D) dD = pi k^2 N0 / Lambda^3.

The result, checked in the tests, sits within the spread of the observations: the chart of
visibility against snowfall intensity that Transport Canada's de-icing guidelines use in
daylight below -1 deg C (built on Rasmussen et al. 1999, J. Appl. Meteor. 38, 1542: heavy
snow, >= 2.5 mm/h, at visibilities below 3/8 mile; light, 0.4-1 mm/h, at 7/8 to 2 miles),
where Rasmussen et al. find the visibility for one rate spreads over a factor of 3 to 10
between storms.

Fall speed: unrimed aggregates fall at about 1 m/s whatever their size, v = 0.8 D^0.16 m/s
(D the flake's size in mm; Locatelli & Hobbs 1974, J. Geophys. Res. 79, 2185, aggregates of
unrimed radiating assemblages of dendrites).
"""

from __future__ import annotations

import math

import numpy as np

from skydome.errors import ParameterError, check_rates
from skydome.physics.droplets import LARGE_DROP_EXTINCTION_EFFICIENCY, WATER_DENSITY_KG_M3

#: The bulk density of a dry snowflake (kg/m^3): what turns a melted diameter into a flake's.
FLAKE_DENSITY_KG_M3 = 100.0
#: Snowfall rates the model takes (mm/h of water): to past the heaviest snowfalls.
SNOW_RATE_RANGE = (0.0, 50.0)


def _rate(snow_mm_h) -> np.ndarray:
    return check_rates("snow rate", snow_mm_h, "mm/h of water")


def gunn_marshall_parameters(snow_mm_h) -> tuple[np.ndarray, np.ndarray]:
    """Gunn & Marshall's (N0 m^-3 mm^-1, Lambda 1/mm) at ``snow_mm_h`` (mm/h of water;
    a rate of 0 is taken as 1e-30)."""
    s = np.maximum(_rate(snow_mm_h), 1e-30)
    return 3.8e3 * np.power(s, -0.87), 2.55 * np.power(s, -0.48)


def flake_size_ratio(flake_density_kg_m3: float = FLAKE_DENSITY_KG_M3) -> float:
    """A flake's size over its melted drop's: (rho_w / rho_flake)^(1/3)."""
    return (WATER_DENSITY_KG_M3 / flake_density_kg_m3) ** (1.0 / 3.0)


def gunn_marshall(melted_diameter_mm, snow_mm_h) -> np.ndarray:
    """Gunn & Marshall's flakes per m^3 and per mm of melted diameter, N(D)."""
    n0, lam = gunn_marshall_parameters(snow_mm_h)
    return n0 * np.exp(-lam * np.asarray(melted_diameter_mm, float))


def snow_extinction_per_m(
    snow_mm_h, flake_density_kg_m3: float = FLAKE_DENSITY_KG_M3
) -> np.ndarray:
    """Extinction coefficient (1/m) of falling snow at ``snow_mm_h`` (mm/h of water)."""
    s = _rate(snow_mm_h)
    n0, lam = gunn_marshall_parameters(s)
    k2 = flake_size_ratio(flake_density_kg_m3) ** 2
    beta = LARGE_DROP_EXTINCTION_EFFICIENCY / 2.0 * math.pi * k2 * n0 / lam**3 * 1e-6
    return np.where(s > 0, beta, 0.0)


def mean_flake_size_mm(snow_mm_h, flake_density_kg_m3: float = FLAKE_DENSITY_KG_M3):
    """The mean flake size (mm) of Gunn & Marshall's distribution: k / Lambda."""
    _, lam = gunn_marshall_parameters(snow_mm_h)
    return flake_size_ratio(flake_density_kg_m3) / lam


def flake_fall_speed_m_s(flake_size_mm) -> np.ndarray:
    """Fall speed (m/s) of an unrimed aggregate of ``flake_size_mm`` (Locatelli & Hobbs)."""
    d = np.asarray(flake_size_mm, float)
    if np.any(d < 0):
        raise ParameterError("a flake's size must be >= 0 mm")
    return 0.8 * np.power(d, 0.16)
