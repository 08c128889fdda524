"""Frames of the atmosphere layer alone, drawn by the frame graph (the one render path), with
the lights given as directions and scales: what the physics tests compare with references.

``AirFrames(...).render(camera, w, h, sun_direction=..., ...)`` makes a SkyState of typed
lights (the Sun at the distance that gives ``sun_scale``; a second light, "the Moon", of
the solar spectrum's shape at ``light2_scale`` of the tables' Sun) and renders it with a
FrameGraph holding one AtmosphereLayer: no space layers, so the frame is the sky's own
light (the precomputed model draws no Sun disk; the single model draws its own).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from skydome.atmosphere.layer import AtmosphereLayer
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.core.cameras import check_direction
from skydome.core.frame import Frame
from skydome.core.lights import Light, SkyState
from skydome.physics.constants import AU_KM
from skydome.scene.graph import FrameGraph
from skydome.spectra import solar_luminance

SUN_RADIUS_RAD = 0.00465


class AirFrames:
    """One atmosphere layer in a frame graph of its own (see the module docstring)."""

    def __init__(
        self,
        atmosphere="earth",
        *,
        model: str = "precomputed",
        spectral: str = "accurate",
        orders: int = 4,
        config: PrecomputeConfig | None = None,
        sky_view: bool = True,
        samples: int = 16,
        jitter: bool = False,
        cache: bool = True,
        ctx=None,
        progress=None,
    ):
        config = config or PrecomputeConfig(wavelengths=spectral, orders=orders)
        self.layer = AtmosphereLayer(
            atmosphere, model=model, config=config, sky_view=sky_view, samples=samples,
            jitter=jitter, spectral=spectral, cache=cache, progress=progress,
        )  # fmt: skip
        self.graph = FrameGraph([self.layer], ctx=ctx)
        self.params = self.layer.params

    @property
    def sky(self):
        """The layer's model (PrecomputedSky or SingleScatteringSky)."""
        return self.layer.sky

    @property
    def tables(self):
        """The precomputed model's tables."""
        return self.layer.sky.tables

    @property
    def transmittance(self):
        """The single model's transmittance table."""
        return self.layer.sky.transmittance

    @property
    def view_samples(self) -> int:
        return self.layer.sky.view_samples

    @property
    def wavelengths_nm(self) -> np.ndarray:
        return self.layer.sky.wavelengths_nm

    def state(self, sun_direction, sun_scale=1.0, light2_direction=None, light2_scale=0.0):
        sun = check_direction("sun direction", sun_direction)
        distance = AU_KM / math.sqrt(float(sun_scale)) if sun_scale > 0 else AU_KM * 1e6
        sun_light = Light("sun", sun, sun, distance, SUN_RADIUS_RAD, 0.0)
        moon = None
        if light2_direction is not None and float(light2_scale) > 0:
            d = check_direction("light2 direction", light2_direction)
            lux = float(light2_scale) * solar_luminance(self.wavelengths_nm)
            lux *= self.params.solar_scale
            moon = Light("moon", d, d, 384_400.0, 0.0045, lux)
        return SkyState(sun=sun_light, moon=moon, pressure_hPa=0.0)

    def render(
        self,
        camera,
        width: int,
        height: int,
        *,
        sun_direction,
        altitude_m: float = 0.0,
        sun_scale: float = 1.0,
        light2_direction=None,
        light2_scale: float = 0.0,
        depth_m=None,
        shadow_length_m=None,
        directions: bool = False,
        supersample: int = 1,
    ) -> Frame:
        self.layer.output_directions = directions
        state = self.state(sun_direction, sun_scale, light2_direction, light2_scale)
        frame = self.graph.render(
            state, camera, width, height, altitude_m=altitude_m, depth_m=depth_m,
            shadow_length_m=shadow_length_m, supersample=supersample,
        )  # fmt: skip
        frame.info["sun_direction"] = state.sun.direction.tolist()
        return frame

    def release(self) -> None:
        self.graph.release()


@functools.cache
def single_frames(
    atmosphere: str = "earth", spectral: str = "fast", samples: int = 16, jitter: bool = False
) -> AirFrames:
    """The single-scattering model (kept for the session)."""
    return AirFrames(atmosphere, model="single", spectral=spectral, samples=samples, jitter=jitter)


@functools.cache
def precomputed_frames(
    atmosphere: str = "earth", spectral: str = "accurate", orders: int = 4, sky_view: bool = True
) -> AirFrames:
    """The precomputed model (kept for the session); ``sky_view=False``: every pixel looked up
    in the 4D tables (the same tables)."""
    return AirFrames(atmosphere, spectral=spectral, orders=orders, sky_view=sky_view)
