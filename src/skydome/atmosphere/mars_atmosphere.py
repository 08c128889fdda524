"""The Martian atmosphere from published profiles: CO2 gas, dust, and the dust's optics.

- **Gas.** ``skydome/data/mars_atmosphere_justus2005.csv``: density, pressure and temperature
  from 2.2 to 57.5 km above the areoid, a Mars-GRAM 2005 profile (the mean of 17 MGS TES limb
  soundings; Justus, Duvall & Keller 2005, Table 1). The ground is the areoid (mean radius
  3389.5 km): the table's lowest segment, log-linear, is continued down 2.17 km to it (583 Pa,
  0.0142 kg/m^3; Mars' mean surface pressure is about 610 Pa). Above 57.5 km the last
  segment's exponential goes on (``DensityProfile.tabulated``).
- **Rayleigh scattering** of CO2: Bodhaine et al.'s air cross-section (``rayleigh``) times
  :data:`CO2_TO_AIR_RAYLEIGH` = 2.5, times the number density. CO2's refractivity is 1.53
  times air's (4.49e-4 vs 2.93e-4 at 589 nm and STP) and its King factor 1.14 against 1.05
  (Sneep & Ubachs 2005, JQSRT 92, 293): 1.53^2 x 1.14 / 1.05 = 2.5.
- **Dust.** Conrath's (1975, Icarus 24, 36) profile: a mixing ratio q(p) = q0 exp(nu (1 - p0/p))
  with nu = :data:`CONRATH_NU`, so dust density ∝ rho_gas q; a visible optical depth of
  :data:`DUST_TAU_550` (a clear season: Lemmon et al. 2015 measured 0.3-1 at the MER sites
  outside dust storms). Optics from Mie theory (``skydome/data/mars_dust.csv``, built by
  ``tools/build_mars_dust.py``): single-scattering albedo 0.62 at 440 nm to 0.97 at 700 nm,
  extinction nearly grey, and a phase function per wavelength (``MiePhaseLobes``).
"""

from __future__ import annotations

from functools import cache

import numpy as np

from skydome.atmosphere.params import DensityProfile, Spectrum
from skydome.atmosphere.phase import MiePhaseLobes
from skydome.atmosphere.rayleigh import rayleigh_scattering_per_m
from skydome.io.packaged import read_packaged_csv

MARS_PROFILE_FILE = "mars_atmosphere_justus2005.csv"
MARS_DUST_FILE = "mars_dust.csv"
#: Mars' volumetric mean radius (m; NASA Mars fact sheet).
MARS_RADIUS_M = 3_389_500.0
#: Boltzmann's constant, J/K (SI 2019, exact).
BOLTZMANN_J_PER_K = 1.380649e-23
#: CO2's Rayleigh cross-section over air's (see the module docstring).
CO2_TO_AIR_RAYLEIGH = 2.5
#: Conrath's nu: 0.003 (Mars-GRAM's default) to 0.03 in the literature; 0.01 keeps dust mixed
#: to about 30 km, as limb soundings show outside dust storms.
CONRATH_NU = 0.01
#: Vertical dust optical depth at 550 nm.
DUST_TAU_550 = 0.5


@cache
def _profile() -> dict:
    t = read_packaged_csv(
        MARS_PROFILE_FILE, ("height_km", "temperature_K", "pressure_Pa", "density_kg_m3")
    )
    h = t["height_km"] * 1000.0

    # Continue the lowest segment (log-linear) down to the areoid.
    def down(v):
        return v[0] * (v[0] / v[1]) ** (h[0] / (h[1] - h[0]))

    return {
        # the number density at the table's lowest level, n = p / (k T)
        "n_first_m3": float(t["pressure_Pa"][0] / (BOLTZMANN_J_PER_K * t["temperature_K"][0])),
        "altitude_m": np.concatenate([[0.0], h]),
        "pressure_Pa": np.concatenate([[down(t["pressure_Pa"])], t["pressure_Pa"]]),
        "density_kg_m3": np.concatenate([[down(t["density_kg_m3"])], t["density_kg_m3"]]),
    }


def mars_profile() -> dict[str, np.ndarray]:
    """The gas profile from the areoid up (fresh arrays): ``altitude_m``, ``pressure_Pa``,
    ``density_kg_m3`` (the table, plus its extrapolation to 0 km first)."""
    return {k: v.copy() for k, v in _profile().items() if k != "n_first_m3"}


def mars_ground_number_density_m3() -> float:
    """Number density of the gas at the areoid, m^-3: p / (k T) at the table's lowest level,
    scaled by the density's extrapolation down to the areoid (1.99e23 m^-3, 1/128 of
    Earth's sea level)."""
    p = _profile()
    return p["n_first_m3"] * float(p["density_kg_m3"][0] / p["density_kg_m3"][1])


#: The grid the profiles are tabulated on (m): every 500 m to the top of the ``mars`` preset,
#: so that the GPU's table holds the profile exactly (atmosphere.uniforms.profile_table_grid).
GRID_STEP_M = 500.0
TOP_M = 120_000.0


def _on_grid(relative_density: np.ndarray) -> DensityProfile:
    """A profile through the table's levels (log-linear between them), resampled every
    GRID_STEP_M from the areoid to TOP_M."""
    exact = DensityProfile.tabulated(_profile()["altitude_m"], relative_density)
    grid = np.arange(0.0, TOP_M + 0.5 * GRID_STEP_M, GRID_STEP_M)
    return DensityProfile.tabulated(grid, exact.density(grid))


def mars_gas_density() -> DensityProfile:
    """Relative gas density (1 at the areoid), tabulated every 500 m."""
    p = _profile()
    return _on_grid(p["density_kg_m3"] / p["density_kg_m3"][0])


def mars_dust_density(conrath_nu: float = CONRATH_NU) -> DensityProfile:
    """Relative dust density (1 at the areoid): gas density times Conrath's mixing ratio
    exp(nu (1 - p0 / p)), tabulated every 500 m."""
    p = _profile()
    rho = p["density_kg_m3"] / p["density_kg_m3"][0]
    q = np.exp(conrath_nu * (1.0 - p["pressure_Pa"][0] / p["pressure_Pa"]))
    return _on_grid(rho * q)


def mars_rayleigh_scattering(wavelengths_nm) -> np.ndarray:
    """CO2 Rayleigh scattering coefficient at the areoid (m^-1)."""
    n0 = mars_ground_number_density_m3()
    return CO2_TO_AIR_RAYLEIGH * rayleigh_scattering_per_m(wavelengths_nm, n0)


@cache
def _dust() -> dict:
    return read_packaged_csv(MARS_DUST_FILE)


def mars_dust_spectra(
    dust_column_m: float, tau_550: float = DUST_TAU_550
) -> tuple[Spectrum, Spectrum]:
    """(extinction, scattering) of the dust at the areoid (m^-1) for a profile whose column
    (∫ relative density dh) is ``dust_column_m``: tau_550 / column at 550 nm, shaped by the
    Mie extinction cross-section, times the single-scattering albedo."""
    d = _dust()
    wl = d["wavelength_nm"]
    rel_550 = float(np.interp(550.0, wl, d["c_ext_rel"]))
    ext = tau_550 / dust_column_m * d["c_ext_rel"] / rel_550
    return Spectrum.sampled(wl, ext), Spectrum.sampled(wl, ext * d["ssa"])


def mars_dust_phase() -> MiePhaseLobes:
    """The dust's phase function per wavelength (Henyey-Greenstein lobes fitted to Mie)."""
    d = _dust()
    names = [k for k in d if k.startswith("hg_")]
    w = np.stack([d[k] for k in names], axis=1)
    return MiePhaseLobes(
        lobe_g=tuple(float(k[3:]) for k in names),
        wavelengths_nm=tuple(d["wavelength_nm"]),
        weights=tuple(map(tuple, w / w.sum(axis=1, keepdims=True))),
    )
