"""OpenGL layer: contexts, the shader library and full-screen passes."""

from skydome.gpu.context import GLInfo, create_context, gl_info, shared_context, wrap_context
from skydome.gpu.passes import FullscreenPass
from skydome.gpu.shaders import build_program, expand

__all__ = [
    "GLInfo",
    "FullscreenPass",
    "build_program",
    "create_context",
    "expand",
    "gl_info",
    "shared_context",
    "wrap_context",
]
