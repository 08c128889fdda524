"""The scene: the lights of an instant and the frame graph that draws a sky's layers.

- :mod:`~skydome.scene.state`: :func:`state_at`, :func:`state_series` and
  :func:`abstract_state` make a :class:`~skydome.core.lights.SkyState`;
- :class:`~skydome.scene.graph.FrameGraph`: draws the layers in physical order, then the
  post passes; it knows layers only through ``skydome.core.layer.Layer``.

The front door over both is :class:`skydome.Sky`. See ``docs/architecture.md``.
"""

from skydome.core.lights import Light, MoonView, SkyState
from skydome.scene.graph import FrameGraph, TileInputs
from skydome.scene.state import abstract_state, state_at, state_series

__all__ = [
    "FrameGraph",
    "Light",
    "MoonView",
    "SkyState",
    "TileInputs",
    "abstract_state",
    "state_at",
    "state_series",
]
