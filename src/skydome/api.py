"""The public face of skydome: every name a user needs, imported here (``skydome.X`` is
``skydome.api.X``, loaded on first use so that the command line starts without NumPy).

skydome: physically based skies in absolute units.

>>> from skydome import Sky
>>> frame = Sky("Valletta", "2018-03-01T19:00Z").render(look="moon", tonemap="filmic")
>>> frame.luminance.max()          # cd/m^2

The names a user needs are here; the packages below hold the rest (``docs/architecture.md``
shows how they stand on one another):

- a sky: :class:`Sky` (a place and a time, or a Sun alone), described by a frozen
  :class:`SkyDescription`; its parts :class:`Clouds`, :class:`Weather`,
  :class:`AtmosphereParams` (presets: :func:`preset`), :class:`LightPollution`;
- cameras: :class:`PerspectiveCamera`, :class:`FisheyeCamera`, :class:`EquirectCamera`,
  :class:`CubemapCamera`, :class:`DirectionsCamera`; frames: :class:`Frame` (cd/m^2);
- places and times: :class:`Observer`, :func:`find_place`, :func:`to_time`;
- layers for a sky of your own: :class:`Layer`, :class:`AtmosphereLayer`,
  :class:`CloudLayer`, :class:`PrecipitationLayer` (falling rain and snow),
  :class:`CieSkyLayer` (a CIE standard general sky);
- output: :func:`tonemap`, :func:`write_outputs`;
- errors: :class:`SkydomeError` and its kinds.
"""

from skydome.astro import Observer, to_time
from skydome.astro.places import find_place
from skydome.atmosphere import PRESETS as ATMOSPHERES
from skydome.atmosphere import AtmosphereParams, preset
from skydome.atmosphere.cie_layer import CieSkyLayer
from skydome.atmosphere.layer import AtmosphereLayer
from skydome.clouds import CloudLayer, Clouds, WeatherMap
from skydome.core.cameras import (
    CubemapCamera,
    DirectionsCamera,
    EquirectCamera,
    FisheyeCamera,
    PerspectiveCamera,
    direction_from_angles,
)
from skydome.core.frame import Frame
from skydome.core.layer import Layer
from skydome.core.lights import SkyState
from skydome.description import SkyDescription
from skydome.display import auto_exposure, tonemap
from skydome.errors import CacheError, GLError, OutputError, ParameterError, SkydomeError
from skydome.io import write_outputs
from skydome.night import LightPollution
from skydome.sky import Sky
from skydome.version import __version__
from skydome.weather import Weather
from skydome.weather.particles import PrecipitationLayer

__all__ = [
    "ATMOSPHERES",
    "AtmosphereLayer",
    "AtmosphereParams",
    "CacheError",
    "CieSkyLayer",
    "CloudLayer",
    "Clouds",
    "CubemapCamera",
    "DirectionsCamera",
    "EquirectCamera",
    "FisheyeCamera",
    "Frame",
    "GLError",
    "Layer",
    "LightPollution",
    "Observer",
    "OutputError",
    "ParameterError",
    "PerspectiveCamera",
    "Sky",
    "SkyDescription",
    "SkyState",
    "SkydomeError",
    "PrecipitationLayer",
    "Weather",
    "WeatherMap",
    "__version__",
    "auto_exposure",
    "direction_from_angles",
    "find_place",
    "preset",
    "to_time",
    "tonemap",
    "write_outputs",
]
