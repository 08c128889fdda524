"""Water drops large beside the wavelength: their extinction, and Koschmieder's visibility.

- A drop much larger than the wavelength removes light from twice its geometric cross-section
  (the extinction paradox: extinction efficiency Q_ext -> 2; van de Hulst 1957, "Light
  Scattering by Small Particles", sec. 8.22). Half of it is diffraction into a peak of a
  degree or two around the forward direction.
- So a population of drops of liquid water content LWC and effective radius r_eff (the ratio
  of the third to the second moment of the radii) has the extinction coefficient
  sigma_ext = 3 LWC / (2 rho_w r_eff) (Stephens 1978, J. Atmos. Sci. 35, 2123, eq. 10).
- The meteorological optical range (visibility) is the distance at which a collimated beam
  keeps 2 % of its light, i.e. a black object's contrast against the horizon sky falls to 2 %:
  V = -ln(0.02) / sigma_ext = 3.912 / sigma_ext at 550 nm (Koschmieder 1924; WMO-No. 8,
  2018, vol. I ch. 9).
"""

from __future__ import annotations

import numpy as np

#: -ln(0.02): Koschmieder's constant of the meteorological optical range (2 % contrast).
KOSCHMIEDER = 3.912
#: Extinction efficiency of drops much larger than the wavelength (van de Hulst).
LARGE_DROP_EXTINCTION_EFFICIENCY = 2.0
WATER_DENSITY_KG_M3 = 1000.0


def droplet_extinction_per_m(liquid_water_g_m3, effective_radius_m):
    """Extinction coefficient (1/m) of drops holding ``liquid_water_g_m3`` (g/m^3) of water
    with effective radius ``effective_radius_m`` (m): 3 LWC / (2 rho_w r_eff)."""
    lwc_kg_m3 = np.asarray(liquid_water_g_m3, float) * 1e-3
    return 3.0 * lwc_kg_m3 / (2.0 * WATER_DENSITY_KG_M3 * np.asarray(effective_radius_m, float))


def visibility_km(extinction_per_m):
    """Koschmieder's visibility (km) for an extinction coefficient at 550 nm (1/m)."""
    return KOSCHMIEDER / (np.asarray(extinction_per_m, float) * 1e3)


def extinction_for_visibility_per_m(visibility_km_):
    """The extinction coefficient at 550 nm (1/m) of a visibility (km)."""
    return KOSCHMIEDER / (np.asarray(visibility_km_, float) * 1e3)
