"""Typed services: what one layer offers the others through the frame graph.

A layer never imports another layer. The atmosphere layer offers its tables and lights as
an :class:`AirService`; the cloud layer the light of the cloudy sky as a
:class:`SkyLightService`; the cloud layer reads it (the sunlight and skylight at each cloud,
the aerial perspective in front of it) and offers the air its shadow as a
:class:`VolumeInputs` (the light shafts). The frame graph finds a service by its type
(``graph.service(AirService)``) among the layers that provide one (``Layer.services``).
"""

from __future__ import annotations

import dataclasses
from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

from skydome.gpu.inputs import ShaderInputs


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
    #: A solar eclipse's sky (``atmosphere/eclipse_sky.glsl``), None otherwise: then
    #: ``sun_scale`` is the eclipsed Sun's (for the clouds and the ground) and the sky passes
    #: weigh the uneclipsed one's light per direction.
    eclipse: EclipseSkyInputs | None = None

    @property
    def has_moon(self) -> bool:
        return self.moon_direction is not None and any(s > 0 for s in self.moon_scale)

    def inputs(self, camera_position_km, solar_scale: float) -> LightInputs:
        """The lights as shader inputs for a camera at ``camera_position_km`` (planet
        centred), scaled to the atmosphere's Sun (``solar_scale``): the tables are for the
        tabulated solar spectrum."""
        moon = self.has_moon
        return LightInputs(
            u_camera_position=tuple(float(v) for v in camera_position_km),
            u_sun_direction=tuple(float(v) for v in self.sun_direction),
            u_sun_scale=float(self.sun_scale) * solar_scale,
            u_light2_direction=tuple(self.moon_direction) if moon else (0.0, 0.0, 1.0),
            u_light2_scale=tuple(float(s) * solar_scale for s in self.moon_scale)
            if moon
            else (0.0,) * 4,
            **({} if self.eclipse is None else self.eclipse.scaled(solar_scale).values()),
        )


@dataclass(frozen=True)
class EclipseSkyInputs(ShaderInputs):
    """``atmosphere/eclipse_sky.glsl``: the Moon's centre from the camera (km, ENU) and
    radius (km), the Sun's angular radius (rad), the uneclipsed Sun's scale (relative to the
    tables' Sun at 1 au) and the air's extinction for the weights (Rayleigh 1/km and scale
    height km, aerosol 1/km and scale height km, at 550 nm) and the Rayleigh extinction of
    each output channel relative to 550 nm's."""

    u_eclipse_moon_km: tuple[float, float, float]
    u_eclipse_moon_radius_km: float
    u_eclipse_sun_radius: float
    u_eclipse_sky_scale: float
    u_eclipse_air: tuple[float, float, float, float]
    u_eclipse_channels: tuple[float, float, float, float] = (1.0, 1.0, 1.0, 1.0)

    def scaled(self, solar_scale: float) -> EclipseSkyInputs:
        """The same with the Sun's scale times ``solar_scale`` (the atmosphere's Sun)."""
        return dataclasses.replace(
            self, u_eclipse_sky_scale=self.u_eclipse_sky_scale * float(solar_scale)
        )


@dataclass(frozen=True)
class LightInputs(ShaderInputs):
    """The lights of the air's lookups for one camera: its planet-centred position (km),
    the Sun's airless direction and scale, the second light's (the Moon's, per channel)."""

    u_camera_position: tuple[float, float, float]
    u_sun_direction: tuple[float, float, float]
    u_sun_scale: float
    u_light2_direction: tuple[float, float, float]
    u_light2_scale: tuple[float, float, float, float]
    u_eclipse_moon_km: tuple[float, float, float] | None = None
    u_eclipse_moon_radius_km: float | None = None
    u_eclipse_sun_radius: float | None = None
    u_eclipse_sky_scale: float | None = None
    u_eclipse_air: tuple[float, float, float, float] | None = None
    u_eclipse_channels: tuple[float, float, float, float] | None = None


@dataclass(frozen=True)
class AerialInputs(ShaderInputs):
    """The aerial-perspective tables of the camera's height (``atmosphere/aerial_lookup.glsl``
    with ``sky_view_mapping.glsl``): the sky-view tables' size, the camera's radius (km), the
    tables' size, and the Sun's and the second light's tables (None where not drawn)."""

    u_sky_view_size: tuple[float, float]
    u_view_radius: float
    u_aerial_size: tuple[float, float, float]
    u_sun_aerial_scattering: object = None
    u_sun_aerial_single_mie: object = None
    u_light2_aerial_scattering: object = None
    u_light2_aerial_single_mie: object = None


@dataclass(frozen=True)
class LookupTables:
    """The air's lookup tables as a shader reads them (``atmosphere/precomputed_lookup.glsl``):
    the ``defines`` to compile with and the typed ``inputs`` to draw with (their type is the
    pass's input type)."""

    defines: dict
    inputs: ShaderInputs


class AirService(ABC):
    """The atmosphere as other layers see it.

    Its GLSL side is :attr:`GLSL`: the files a consumer's shader includes to read the
    lookups this service hands over (their uniforms and textures are :meth:`lookup`'s and
    :meth:`aerial_perspective`'s inputs). They are the only shader files a layer may include
    from another layer's folder (``tests/test_architecture.py``).
    """

    #: The service's GLSL interface (paths under ``skydome/shaders``).
    GLSL: tuple[str, ...] = (
        "atmosphere/precomputed_lookup.glsl",  # sky, transmittance, ground irradiance
        "atmosphere/aerial_lookup.glsl",  # the aerial-perspective tables
        "atmosphere/sky_view_mapping.glsl",  # the sky-view tables' directions
        "atmosphere/surface_radiance.glsl",  # the ground's light
    )

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
    def aerial_perspective(self, radius_km: float, lights: AirLights) -> AerialInputs | None:
        """The aerial-perspective tables of ``lights`` seen from ``radius_km``
        (``atmosphere/aerial_lookup.glsl``), or None above the air or without sky-view tables
        (look the 4D tables up instead)."""


class SkyLightService(ABC):
    """The light of the sky that is drawn (clouds and all) around the camera's ground: the
    cloud layer offers it (its probe); what lights things in the air near the camera, such
    as falling rain and snow."""

    @abstractmethod
    def ambient_radiance(self) -> tuple[float, float, float, float]:
        """The mean radiance (cd/m^2 per output channel) of the sky and the ground around
        the camera's ground."""


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
