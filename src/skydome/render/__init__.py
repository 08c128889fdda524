"""Rendering: cameras, frames and sky renderers."""

from skydome.render.api import MODELS, get_renderer, render_sky
from skydome.render.cameras import (
    CAMERAS,
    Camera,
    CubemapCamera,
    DirectionsCamera,
    EquirectCamera,
    FisheyeCamera,
    PerspectiveCamera,
    direction_from_angles,
    make_camera,
)
from skydome.render.frame import Frame

__all__ = [
    "CAMERAS",
    "MODELS",
    "Camera",
    "CubemapCamera",
    "DirectionsCamera",
    "EquirectCamera",
    "FisheyeCamera",
    "Frame",
    "PerspectiveCamera",
    "direction_from_angles",
    "get_renderer",
    "make_camera",
    "render_sky",
]
