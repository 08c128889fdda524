"""Volumetric clouds: what they are (:class:`Clouds`, presets), the droplets' phase function
(:mod:`skydome.clouds.phase`), noise textures and weather maps (:mod:`skydome.clouds.noise`,
:mod:`skydome.clouds.weather`), and the cloud layer of the scene (:mod:`skydome.clouds.layer`).

The float64 references they are checked against live in :mod:`skydome.reference.clouds_mc`
(Monte Carlo) and :mod:`skydome.reference.cloud_slab` (the light model's twin).
"""

from skydome.clouds.layer import CloudLayer
from skydome.clouds.params import PRESETS, Clouds
from skydome.clouds.weather import AnimatedWeather, WeatherMap

__all__ = ["PRESETS", "AnimatedWeather", "CloudLayer", "Clouds", "WeatherMap"]
