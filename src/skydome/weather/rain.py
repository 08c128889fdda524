"""Rain: from the rain rate to the drops' sizes, their fall speed and their extinction.

Drop size distributions (diameter D in mm, rain rate R in mm/h):

- **Marshall & Palmer** (1948, J. Meteor. 5, 165): N(D) = N0 exp(-Lambda D), N0 = 8000
  m^-3 mm^-1, Lambda = 4.1 R^-0.21 mm^-1. The default.
- **Best** (1950, Q. J. R. Meteor. Soc. 76, 16; seed 003 eq. 1): the fraction of the liquid
  water in drops smaller than D is F(D) = 1 - exp(-(D / a)^n) with a = 1.30 R^0.232 mm and
  n = 2.25, and the liquid water content W = 67 R^0.846 mg/m^3.

Drops of a millimetre are ~10^4 wavelengths across: their extinction efficiency is 2
(``skydome.physics.droplets``), so sigma_ext = 2 x (pi / 4) int D^2 N(D) dD. For
Marshall-Palmer that is pi N0 / Lambda^3 in closed form (1.55 /km at 10 mm/h); for Best,
3 W Gamma(1 - 1/n) / (rho_w a).

Fall speed: the fit of Atlas, Srivastava & Sekhon (1973, Rev. Geophys. 11, 1, eq. 17) to the
terminal velocities Gunn & Kinzer (1949, J. Meteor. 6, 243) measured in still air at sea
level: v(D) = 9.65 - 10.3 exp(-0.6 D) m/s (D in mm), within 2 % of their table from 0.5 to
5 mm.
"""

from __future__ import annotations

import math

import numpy as np

from skydome.errors import ParameterError, check_rates
from skydome.physics.droplets import LARGE_DROP_EXTINCTION_EFFICIENCY, WATER_DENSITY_KG_M3

#: Marshall-Palmer's intercept (m^-3 mm^-1).
MP_N0 = 8000.0
#: Best (1950): a = BEST_A R^BEST_P (mm), F(D) = 1 - exp(-(D/a)^BEST_N), W = BEST_C R^BEST_R
#: (mg/m^3).
BEST_A, BEST_P, BEST_N = 1.30, 0.232, 2.25
BEST_C, BEST_R = 67.0, 0.846
#: The drop size distributions by name.
DISTRIBUTIONS = ("marshall-palmer", "best")
#: Rain rates the model takes (mm/h): a trace to the heaviest hourly rates on record.
RAIN_RATE_RANGE = (0.0, 300.0)


def _rate(rain_mm_h) -> np.ndarray:
    return check_rates("rain rate", rain_mm_h, "mm/h")


def marshall_palmer_slope_per_mm(rain_mm_h) -> np.ndarray:
    """Marshall-Palmer's Lambda (1/mm) at rain rate ``rain_mm_h`` (mm/h)."""
    return 4.1 * np.power(_rate(rain_mm_h), -0.21)


def marshall_palmer(diameter_mm, rain_mm_h) -> np.ndarray:
    """Marshall-Palmer's number of drops per m^3 and per mm of diameter, N(D)."""
    lam = marshall_palmer_slope_per_mm(rain_mm_h)
    return MP_N0 * np.exp(-lam * np.asarray(diameter_mm, float))


def best_scale_mm(rain_mm_h) -> np.ndarray:
    """Best's a (mm): the diameter below which 1 - 1/e of the water falls."""
    return BEST_A * np.power(_rate(rain_mm_h), BEST_P)


def best_liquid_water_g_m3(rain_mm_h) -> np.ndarray:
    """Best's liquid water content of rain (g/m^3) at rain rate ``rain_mm_h`` (mm/h)."""
    return BEST_C * np.power(_rate(rain_mm_h), BEST_R) * 1e-3


def best_distribution(diameter_mm, rain_mm_h) -> np.ndarray:
    """Best's number of drops per m^3 and per mm of diameter: the water's distribution
    dF/dD times W over one drop's water."""
    d = np.asarray(diameter_mm, float)
    a = best_scale_mm(rain_mm_h)
    x = d / a
    dF_dD = BEST_N / a * np.power(x, BEST_N - 1.0) * np.exp(-np.power(x, BEST_N))
    drop_g = WATER_DENSITY_KG_M3 * 1e3 * math.pi / 6.0 * (d * 1e-3) ** 3
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(d > 0, best_liquid_water_g_m3(rain_mm_h) * dF_dD / drop_g, 0.0)


def rain_extinction_per_m(rain_mm_h, distribution: str = "marshall-palmer") -> np.ndarray:
    """Extinction coefficient of rain (1/m), extinction efficiency 2 (closed forms: module
    docstring). Zero without rain."""
    r = _rate(rain_mm_h)
    q = LARGE_DROP_EXTINCTION_EFFICIENCY
    with np.errstate(divide="ignore"):
        if distribution == "marshall-palmer":
            lam = marshall_palmer_slope_per_mm(np.maximum(r, 1e-30))
            beta = q / 2.0 * math.pi * MP_N0 / lam**3 * 1e-6  # mm^2 m^-3 -> 1/m
        elif distribution == "best":
            w_kg = best_liquid_water_g_m3(r) * 1e-3
            a_m = best_scale_mm(np.maximum(r, 1e-30)) * 1e-3
            beta = (
                q / 2.0 * 3.0 * w_kg * math.gamma(1.0 - 1.0 / BEST_N) / (WATER_DENSITY_KG_M3 * a_m)
            )
        else:
            raise ParameterError(
                f"drop size distribution {distribution!r} must be one of {', '.join(DISTRIBUTIONS)}"
            )
    return np.where(r > 0, beta, 0.0)


def fall_speed_m_s(diameter_mm) -> np.ndarray:
    """Terminal fall speed (m/s) of a raindrop of ``diameter_mm`` in still air at sea level
    (Atlas et al. 1973's fit to Gunn & Kinzer 1949; 0 for D <= 0.03 mm)."""
    d = np.asarray(diameter_mm, float)
    return np.maximum(9.65 - 10.3 * np.exp(-0.6 * d), 0.0)


def streak_length_m(diameter_mm, exposure_s: float, wind_m_s: float = 0.0) -> np.ndarray:
    """How long (m) a drop's streak is in an exposure of ``exposure_s`` (s): its path, down at
    its fall speed and across with the wind (m/s)."""
    v = fall_speed_m_s(diameter_mm)
    return np.hypot(v, float(wind_m_s)) * float(exposure_s)


def rain_rate_mm_h(distribution_per_m3_mm, diameters_mm) -> float:
    """The rain rate (mm/h) a drop size distribution N(D) (m^-3 mm^-1, at increasing
    ``diameters_mm``) carries at the drops' fall speeds: 6 pi 1e-4 int D^3 v(D) N(D) dD."""
    d = np.asarray(diameters_mm, float)
    integrand = d**3 * fall_speed_m_s(d) * np.asarray(distribution_per_m3_mm, float)
    return float(6.0 * math.pi * 1e-4 * np.trapezoid(integrand, d))
