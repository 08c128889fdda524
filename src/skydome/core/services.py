"""Typed services: what one layer offers the others through the frame graph.

A layer never imports another layer. The atmosphere layer offers its tables and lights as
an :class:`AirService`; the cloud layer reads it (the sunlight and skylight at each cloud,
the aerial perspective in front of it) and offers the air its shadow as a
:class:`VolumeInputs` (the light shafts). The frame graph finds a service by its type
(``graph.service(AirService)``) among the layers that provide one (``Layer.services``).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class AirLights:
    """The lights as the air's tables see them at one instant.

    ``sun_direction``: the Sun's airless direction (unit ENU; the tables' light paths are
    straight); ``sun_scale``: its irradiance relative to the tables' Sun at 1 au;
    ``moon_direction`` (None without a Moon) and ``moon_scale``: the Moon's, per output
    channel (its colour relative to sunlight's).
    """

    sun_direction: tuple[float, float, float]
    sun_scale: float
    moon_direction: tuple[float, float, float] | None = None
    moon_scale: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)

    @property
    def has_moon(self) -> bool:
        return self.moon_direction is not None and any(s > 0 for s in self.moon_scale)


@dataclass(frozen=True)
class LookupTables:
    """The air's lookup tables as a shader reads them (``atmosphere/precomputed_lookup.glsl``):
    the ``defines`` to compile with, the ``uniforms`` and the ``textures`` (sampler name ->
    texture) to draw with."""

    defines: dict
    uniforms: dict
    textures: dict


class AirService(ABC):
    """The atmosphere as other layers see it."""

    #: Radii (m) of the ground and of the top of the air.
    bottom_radius_m: float
    top_radius_m: float
    #: The Sun's irradiance relative to the tabulated solar spectrum (1 for the Earth).
    solar_scale: float

    @abstractmethod
    def lights(self) -> AirLights:
        """The lights of the last update."""

    @abstractmethod
    def lookup(self) -> LookupTables:
        """The tables, for a shader that looks the sky, the transmittance and the ground's
        light up."""

    @abstractmethod
    def ground_albedo(self) -> float:
        """The ground's mean albedo (0..1)."""

    @abstractmethod
    def camera_position_km(self, altitude_m: float) -> tuple[float, float, float]:
        """The planet-centred position (km, ENU axes) of a camera ``altitude_m`` above the
        ground."""

    @abstractmethod
    def aerial_perspective(self, radius_km: float, lights: AirLights) -> tuple[dict, dict] | None:
        """(uniforms, textures) of the aerial-perspective tables of ``lights`` seen from
        ``radius_km`` (``atmosphere/aerial_lookup.glsl``), or None above the air (look the
        4D tables up instead)."""


@dataclass
class VolumeInputs:
    """Per-pixel inputs one volume layer gives the others for a tile: ``shadow_map``, the
    length (km) of each view ray's air in an occluder's shadow (the clouds', for the air's
    light shafts), or None."""

    shadow_map: object = None

    def merge(self, other: VolumeInputs) -> VolumeInputs:
        return VolumeInputs(
            shadow_map=other.shadow_map if other.shadow_map is not None else self.shadow_map
        )


def channel_scales(value) -> tuple[float, float, float, float]:
    """A scale per output channel from a number or 4 numbers."""
    v = np.broadcast_to(np.asarray(value, dtype=np.float64), (4,))
    return tuple(float(s) for s in v)
