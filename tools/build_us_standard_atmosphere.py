"""Build ``src/skydome/data/us_standard_atmosphere_1976.csv``: the U.S. Standard Atmosphere
1976 every 500 m of geometric altitude from 0 to 100 km.

Source: U.S. Standard Atmosphere, 1976, NOAA-S/T 76-1562 (NOAA, NASA and USAF; U.S.
Government Printing Office, Washington, D.C., 1976), a work of the U.S. Government and in
the public domain. Section and table numbers below are the standard's.

Below 86 km the standard is defined by equations, evaluated here in float64:

* geopotential altitude H = r0 Z / (r0 + Z), r0 = 6 356 766 m (eq. 18);
* the molecular-scale temperature T_M is linear in H in seven layers with bases at 0, 11,
  20, 32, 47, 51 and 71 km' and gradients -6.5, 0, +1.0, +2.8, 0, -2.8, -2.0 K/km' from
  T_M = 288.15 K at sea level, up to 84.852 km' (86 km geometric) (Table 4, eq. 23);
* hydrostatic pressure from P0 = 101 325 Pa: P = P_b [T_Mb / T_M]^(g0' M0 / (R* L_M)) in a
  layer with gradient L_M, P = P_b exp(-g0' M0 (H - H_b) / (R* T_Mb)) in an isothermal one
  (eqs. 33a, 33b), g0' = 9.80665 m^2 s^-2 m'^-1, M0 = 28.9644 kg/kmol, R* = 8314.32 J/(kmol K);
* density rho = P M0 / (R* T_M) (eq. 42); kinetic temperature T = T_M M / M0 with the ratio
  M / M0 of Table 8 (1 below 80 km, 0.999579 at 86 km), number density n = N_A P / (R* T)
  (eq. 41), N_A = 6.022169e26 /kmol.

From 86 to 100 km the standard integrates diffusion equations for each gas (section 1.3);
this script does not repeat that. It takes the kinetic temperature from the standard's
defining equations for that region (T = 186.8673 K to 91 km, then the ellipse
T = 263.1905 - 76.3232 sqrt(1 - ((Z - 91 km) / -19.9429 km)^2) K, eqs. 27-29) and the
composition from the standard's tabulated number densities of N2, O, O2, Ar and He at 86,
90, 95 and 100 km (Table VIII; ln n of each gas is interpolated linearly in Z between them),
which give the mean molecular weight M(Z). Between those altitudes the pressure has the
shape of hydrostatic equilibrium, dP/dZ = -P M g / (R* T) with g = g0 (r0 / (r0 + Z))^2,
integrated from the 86 km pressure above, times a factor interpolated log-linearly in Z that
makes P = n k T with the tabulated total n at 90, 95 and 100 km (the gases' diffusive
separation, which the mean-molecular-weight hydrostatic equation leaves out, puts the plain
integral 0.1 % below the table at 90 and 95 km and 0.85 % above it at 100 km). So the table
holds the standard's Table I values at 86, 90, 95 and 100 km (pressure 0.37338, 0.18359,
0.075966, 0.032011 Pa; density 6.958e-6, 3.416e-6, 1.393e-6, 5.604e-7 kg/m^3) to their
printed digits, and smooth values between them.

Usage: python tools/build_us_standard_atmosphere.py
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

OUT = (
    Path(__file__).resolve().parents[1]
    / "src"
    / "skydome"
    / "data"
    / "us_standard_atmosphere_1976.csv"
)
STEP_M = 500.0
TOP_M = 100_000.0

# Constants of the standard (Table 2).
G0 = 9.80665  # m/s^2 (and m^2 s^-2 m'^-1 for geopotential)
R0_M = 6_356_766.0  # effective Earth radius of the geopotential, m
R_STAR = 8314.32  # J / (kmol K)
M0 = 28.9644  # kg/kmol, sea-level mean molecular weight
N_A = 6.022169e26  # 1/kmol
P0 = 101_325.0  # Pa
T0 = 288.15  # K

# Layers below 86 km (Table 4): base geopotential altitude (m'), gradient (K/m').
LAYER_BASE_M = (0.0, 11_000.0, 20_000.0, 32_000.0, 47_000.0, 51_000.0, 71_000.0)
LAYER_GRADIENT = (-6.5e-3, 0.0, 1.0e-3, 2.8e-3, 0.0, -2.8e-3, -2.0e-3)
H_86_KM = 84_852.0  # m', the geopotential altitude of Z = 86 km (to 1 m)

# M / M0 between 80 and 86 km every 0.5 km (Table 8); 1 below.
MW_RATIO_Z_M = np.arange(80_000.0, 86_001.0, 500.0)
MW_RATIO = np.array(
    [1.0, 0.999996, 0.999989, 0.999971, 0.999941, 0.999909, 0.999870, 0.999829, 0.999786,
     0.999741, 0.999694, 0.999641, 0.999579]
)  # fmt: skip

# Number densities (m^-3) at 86, 90, 95, 100 km (Table VIII; 86 km: the boundary values of
# section 1.3.3), molecular weights (kg/kmol, Table 3).
SPECIES_Z_M = np.array([86_000.0, 90_000.0, 95_000.0, 100_000.0])
SPECIES = {
    "N2": (28.0134, [1.129794e20, 5.547e19, 2.268e19, 9.210e18]),
    "O": (15.9994, [8.6e16, 2.443e17, 4.365e17, 4.298e17]),
    "O2": (31.9988, [3.030898e19, 1.479e19, 5.83e18, 2.151e18]),
    "Ar": (39.948, [1.3514e18, 6.574e17, 2.583e17, 9.501e16]),
    "He": (4.0026, [7.5817e14, 3.976e14, 1.973e14, 1.133e14]),
}


def geopotential_m(z_m: np.ndarray) -> np.ndarray:
    """Geopotential altitude (m') of geometric altitude ``z_m`` (eq. 18)."""
    return R0_M * z_m / (R0_M + z_m)


def layer_bases() -> tuple[np.ndarray, np.ndarray]:
    """Molecular-scale temperature (K) and pressure (Pa) at each layer base (Table 4)."""
    t_b, p_b = [T0], [P0]
    for i in range(len(LAYER_BASE_M) - 1):
        dh = LAYER_BASE_M[i + 1] - LAYER_BASE_M[i]
        t_next, p_next = _layer(t_b[i], p_b[i], LAYER_GRADIENT[i], dh)
        t_b.append(t_next)
        p_b.append(p_next)
    return np.array(t_b), np.array(p_b)


def _layer(t_b: float, p_b: float, gradient: float, dh_m: float) -> tuple[float, float]:
    """T_M (K) and P (Pa) at dh_m geopotential metres above a base (eqs. 23, 33a, 33b)."""
    t = t_b + gradient * dh_m
    if gradient == 0.0:
        return t, p_b * math.exp(-G0 * M0 * dh_m / (R_STAR * t_b))
    return t, p_b * (t_b / t) ** (G0 * M0 / (R_STAR * gradient))


def lower_atmosphere(z_m: np.ndarray) -> dict[str, np.ndarray]:
    """T (kinetic, K), P (Pa), rho (kg/m^3), n (m^-3) at geometric altitudes <= 86 km."""
    t_b, p_b = layer_bases()
    h = geopotential_m(z_m)
    layer = np.clip(np.searchsorted(LAYER_BASE_M, h, side="right") - 1, 0, len(LAYER_BASE_M) - 1)
    t_m = np.empty_like(z_m)
    p = np.empty_like(z_m)
    for k, (hk, layer_k) in enumerate(zip(h, layer, strict=True)):
        t_m[k], p[k] = _layer(
            t_b[layer_k], p_b[layer_k], LAYER_GRADIENT[layer_k], hk - LAYER_BASE_M[layer_k]
        )
    ratio = np.interp(z_m, MW_RATIO_Z_M, MW_RATIO, left=1.0)
    t = t_m * ratio
    return {
        "temperature_K": t,
        "pressure_Pa": p,
        "density_kg_m3": p * M0 / (R_STAR * t_m),
        "number_density_m3": N_A * p / (R_STAR * t),
    }


def upper_temperature_k(z_m: np.ndarray) -> np.ndarray:
    """Kinetic temperature (K) from 86 to 110 km (eqs. 27-29)."""
    z_km = np.asarray(z_m) / 1e3
    ellipse = 263.1905 - 76.3232 * np.sqrt(np.maximum(1.0 - ((z_km - 91.0) / -19.9429) ** 2, 0.0))
    return np.where(z_km <= 91.0, 186.8673, ellipse)


def mean_molecular_weight(z_m: np.ndarray) -> np.ndarray:
    """M (kg/kmol) from 86 to 100 km: the Table VIII composition, ln n interpolated in Z."""
    num = np.zeros_like(z_m)
    den = np.zeros_like(z_m)
    for weight, n in SPECIES.values():
        n_z = np.exp(np.interp(z_m, SPECIES_Z_M, np.log(n)))
        num += weight * n_z
        den += n_z
    return num / den


def tabulated_pressure_pa(z_m: np.ndarray) -> np.ndarray:
    """P = n k T (Pa) with the total number density of Table VIII at its altitudes."""
    n = sum(np.asarray(v[1]) for v in SPECIES.values())
    return n * R_STAR / N_A * upper_temperature_k(z_m)


def upper_atmosphere(z_m: np.ndarray, p_86: float) -> dict[str, np.ndarray]:
    """T, P, rho, n at geometric altitudes from 86 to 100 km: hydrostatic integration (10 m
    steps, trapezoidal in ln P), matched to the Table VIII totals at 90, 95 and 100 km."""
    fine = np.arange(86_000.0, z_m.max() + 10.0, 10.0)
    m = mean_molecular_weight(fine)
    t = upper_temperature_k(fine)
    g = G0 * (R0_M / (R0_M + fine)) ** 2
    rate = m * g / (R_STAR * t)  # -d ln P / dZ, 1/m
    ln_p = math.log(p_86) - np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * 10.0)])
    # The correction is 0 at 86 km, where p_86 is the lower atmosphere's (continuity).
    ln_fix = np.log(tabulated_pressure_pa(SPECIES_Z_M)) - np.interp(SPECIES_Z_M, fine, ln_p)
    ln_fix[0] = 0.0
    p = np.exp(np.interp(z_m, fine, ln_p) + np.interp(z_m, SPECIES_Z_M, ln_fix))
    t_z = upper_temperature_k(z_m)
    m_z = mean_molecular_weight(z_m)
    return {
        "temperature_K": t_z,
        "pressure_Pa": p,
        "density_kg_m3": p * m_z / (R_STAR * t_z),
        "number_density_m3": N_A * p / (R_STAR * t_z),
    }


def build() -> dict[str, np.ndarray]:
    """The table's columns at 0, 500, ..., 100 000 m."""
    z = np.arange(0.0, TOP_M + 1.0, STEP_M)
    low = z <= 86_000.0
    lower = lower_atmosphere(z[low])
    p_86 = float(lower["pressure_Pa"][-1])
    upper = upper_atmosphere(z[~low], p_86)
    columns = {"altitude_m": z}
    for key in lower:
        columns[key] = np.concatenate([lower[key], upper[key]])
    return columns


HEADER = """\
# U.S. Standard Atmosphere, 1976 (NOAA-S/T 76-1562; NOAA, NASA, USAF; U.S. Government
# Printing Office, 1976; public domain). Geometric altitude every 500 m, 0-100 km.
# Below 86 km: the standard's defining equations (layers of Table 4, hydrostatic pressure,
# rho = P M0 / (R* T_M), n = N_A P / (R* T), M/M0 of Table 8). 86-100 km: the standard's
# temperature equations and the composition of its Table VIII, pressure by hydrostatic
# equilibrium. Built by tools/build_us_standard_atmosphere.py.
"""


def main() -> None:
    cols = build()
    lines = [HEADER.rstrip("\n"), ",".join(cols)]
    for row in zip(*cols.values(), strict=True):
        z, rest = row[0], row[1:]
        lines.append(f"{z:.1f}," + ",".join(f"{v:.7g}" for v in rest))
    OUT.write_text("\n".join(lines) + "\n")
    print(f"wrote {OUT} ({len(cols['altitude_m'])} rows)")


if __name__ == "__main__":
    main()
