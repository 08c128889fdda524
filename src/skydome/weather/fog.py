"""Fog and mist: a layer of water droplets at the ground.

A fog is droplets of a few to some tens of micrometres: extinction efficiency 2 (they are 10-
100 wavelengths across), sigma_ext = 3 LWC / (2 rho_w r_eff) (``skydome.physics.droplets``),
grey over the visible. The default droplets are those of the clouds' Mie phase function
(effective radius 10 um, ``skydome.clouds.phase``), the size of mature radiation and
advection fogs' droplets (Pruppacher & Klett 1997, table 2.2: fog droplets 1-40 um, mean
radius ~ 10 um). WMO's words: fog below 1 km of visibility, mist from 1 km up (WMO-No. 8,
2018, vol. I ch. 14).

Check against the world: Kunkel (1984, J. Climate Appl. Meteor. 23, 34) fitted sigma_ext =
144.7 LWC^0.88 /km (LWC in g/m^3) to droplet spectra measured in advection fogs; the tests
hold the droplet formula to it.
"""

from __future__ import annotations

import numpy as np

from skydome.errors import ParameterError
from skydome.physics.droplets import droplet_extinction_per_m, extinction_for_visibility_per_m

#: Effective radius of fog droplets (m), the clouds' droplets'.
FOG_DROPLET_RADIUS_M = 10e-6
#: Effective radii (um) the fog knob takes.
FOG_DROPLET_RANGE_UM = (1.0, 50.0)
#: Below this visibility (km) the WMO calls it fog; above, mist.
FOG_VISIBILITY_KM = 1.0


def kunkel_extinction_per_m(liquid_water_g_m3) -> np.ndarray:
    """Kunkel's (1984) fitted fog extinction (1/m): 144.7 LWC^0.88 /km."""
    return 144.7 * np.power(np.asarray(liquid_water_g_m3, float), 0.88) * 1e-3


def fog_liquid_water_g_m3(visibility_km, droplet_radius_m: float = FOG_DROPLET_RADIUS_M):
    """The liquid water (g/m^3) of a fog of droplets of ``droplet_radius_m`` (m) with the
    visibility ``visibility_km`` (km) from its droplets alone."""
    v = np.asarray(visibility_km, float)
    if np.any(~np.isfinite(v)) or np.any(v <= 0):
        raise ParameterError(f"fog visibility must be > 0 km, got {visibility_km!r}")
    per_gram = droplet_extinction_per_m(1.0, droplet_radius_m)
    return extinction_for_visibility_per_m(v) / per_gram
