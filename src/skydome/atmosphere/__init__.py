"""Atmosphere: parameters, presets, lookup tables and float64 references."""

from skydome.atmosphere.params import AtmosphereParams, DensityLayer, DensityProfile, Spectrum
from skydome.atmosphere.presets import PRESETS, earth, earth_nishita, hazy, mars, preset

__all__ = [
    "PRESETS",
    "AtmosphereParams",
    "DensityLayer",
    "DensityProfile",
    "Spectrum",
    "earth",
    "earth_nishita",
    "hazy",
    "mars",
    "preset",
]
