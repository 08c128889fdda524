"""The scene: a Sky is a place, a time and layers drawn by one frame graph.

- :class:`~skydome.scene.sky.Sky`: the front door (also ``skydome.Sky``);
- :class:`~skydome.scene.state.SkyState`: the lights for one instant;
- :class:`~skydome.scene.layer.Layer`: what every layer implements;
- :class:`~skydome.scene.graph.FrameGraph`: draws the layers in physical order.

See ``docs/architecture.md``.
"""

from skydome.scene.graph import FrameGraph
from skydome.scene.layer import DrawContext, Layer, SpectralBasis
from skydome.scene.sky import LOOKS, Sky
from skydome.scene.state import Light, MoonView, SkyState

__all__ = [
    "LOOKS",
    "DrawContext",
    "FrameGraph",
    "Layer",
    "Light",
    "MoonView",
    "Sky",
    "SkyState",
    "SpectralBasis",
]
