"""The natural and artificial glow of the night sky: airglow, zodiacal light, light pollution.

Layers (``skydome.night.glow_layer``): ``AirglowLayer`` and ``ZodiacalLightLayer`` (space
stage) and ``LightPollutionLayer`` (volume stage, after the atmosphere); the models with their
float64 formulas: ``skydome.night.airglow``, ``.zodiacal`` and ``.light_pollution``.
"""

from skydome.night.airglow import (
    luminance_to_mag,
    mag_to_luminance,
    s10_to_luminance,
    s10_to_mag,
    solar_cycle_factor,
    van_rhijn,
)
from skydome.night.glow_layer import (
    AirglowLayer,
    LightPollutionLayer,
    ZodiacalLightLayer,
    zenith_brightness,
)
from skydome.night.light_pollution import City, LightPollution, bortle_zenith_mag
from skydome.night.zodiacal import zodiacal_s10

__all__ = [
    "AirglowLayer",
    "City",
    "LightPollution",
    "LightPollutionLayer",
    "ZodiacalLightLayer",
    "bortle_zenith_mag",
    "luminance_to_mag",
    "mag_to_luminance",
    "s10_to_luminance",
    "s10_to_mag",
    "solar_cycle_factor",
    "van_rhijn",
    "zenith_brightness",
    "zodiacal_s10",
]
