"""Weather: fog, mist, rain and snow, and the visibility they make (NumPy only).

- :mod:`~skydome.weather.params`: :class:`Weather`, a preset and its knobs;
- :mod:`~skydome.weather.rain`: drop size distributions (Marshall-Palmer, Best), fall speed
  (Gunn-Kinzer), extinction;
- :mod:`~skydome.weather.snow`: flake sizes (Gunn-Marshall), extinction, fall speed;
- :mod:`~skydome.weather.fog`: fog droplets' water and extinction;
- :mod:`~skydome.weather.humidity`: the aerosol's hygroscopic growth.

The weather is drawn by the layers it feeds (``skydome.description`` joins them): the air's
aerosol (visibility, humidity) and the clouds' layer of droplets and precipitation at the
ground.
"""

from skydome.weather.params import PRESETS, Weather

__all__ = ["PRESETS", "Weather"]
