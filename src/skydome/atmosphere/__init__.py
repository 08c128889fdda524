"""Atmosphere: parameters, presets, lookup tables and float64 references.

Knobs on top of a preset: ``preset("earth", aod_550=0.1, angstrom=1.3, ozone_du=300,
albedo=0.2)``, or ``AtmosphereParams.with_knobs`` / ``with_aerosol`` / ``with_ozone`` /
``with_albedo``; each knob's valid range is in ``skydome.atmosphere.params``.
"""

from skydome.atmosphere.params import (
    ALBEDO_RANGE,
    ANGSTROM_RANGE,
    AOD_550_RANGE,
    DOBSON_UNIT_PER_M2,
    OZONE_DU_RANGE,
    SSA_RANGE,
    AtmosphereParams,
    DensityLayer,
    DensityProfile,
    Spectrum,
)
from skydome.atmosphere.presets import (
    HAZY_AEROSOL,
    PRESETS,
    desert,
    earth,
    earth_bruneton,
    earth_nishita,
    hazy,
    maritime,
    mars,
    preset,
    typical,
    urban,
)

__all__ = [
    "ALBEDO_RANGE",
    "ANGSTROM_RANGE",
    "AOD_550_RANGE",
    "DOBSON_UNIT_PER_M2",
    "HAZY_AEROSOL",
    "OZONE_DU_RANGE",
    "PRESETS",
    "SSA_RANGE",
    "AtmosphereParams",
    "DensityLayer",
    "DensityProfile",
    "Spectrum",
    "desert",
    "earth",
    "earth_bruneton",
    "earth_nishita",
    "hazy",
    "maritime",
    "mars",
    "preset",
    "typical",
    "urban",
]
