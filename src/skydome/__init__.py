"""skydome: physically based skies in absolute units.

>>> from skydome import Sky
>>> frame = Sky("Valletta", "2018-03-01T19:00Z").render(look="moon", tonemap="filmic")

The public names live in :mod:`skydome.api` (documented there) and are loaded from it on
first use: ``import skydome`` costs nothing, so that the command line and the gazetteer
start without NumPy or OpenGL.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from skydome.version import __version__

if TYPE_CHECKING:  # what static tools see: every public name
    from skydome.api import *  # noqa: F403

__all__ = [  # noqa: F405  (the names of skydome.api)
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


def __getattr__(name: str):
    if name in __all__:
        from skydome import api  # the public face: NumPy, OpenGL and every layer

        return getattr(api, name)
    raise AttributeError(f"module 'skydome' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
