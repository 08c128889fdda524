"""OpenGL contexts: headless through EGL (GPU or Mesa llvmpipe) or wrapping an existing one."""

from __future__ import annotations

import threading
from dataclasses import dataclass

from skydome.errors import GLError

_INSTALL_HINT = (
    "skydome needs OpenGL 3.3. On a machine without a GPU install Mesa's EGL and software "
    "rasterizer (Debian/Ubuntu: apt-get install libegl1 libgl1-mesa-dri); with a GPU, install "
    "its driver"
)

_SOFTWARE_RENDERERS = ("llvmpipe", "softpipe", "swrast", "software", "lavapipe", "swiftshader")


@dataclass(frozen=True)
class GLInfo:
    """What the OpenGL context runs on."""

    renderer: str
    vendor: str
    version: str
    version_code: int
    software: bool

    def describe(self) -> str:
        kind = "software rasterizer (CPU)" if self.software else "hardware (GPU)"
        return f"{self.renderer} | OpenGL {self.version} | {kind}"


def gl_info(ctx) -> GLInfo:
    """Describe a moderngl context: renderer, vendor, version and whether it is software."""
    info = ctx.info
    renderer = str(info.get("GL_RENDERER", "unknown"))
    return GLInfo(
        renderer=renderer,
        vendor=str(info.get("GL_VENDOR", "unknown")),
        version=str(info.get("GL_VERSION", "unknown")),
        version_code=int(ctx.version_code),
        software=any(s in renderer.lower() for s in _SOFTWARE_RENDERERS),
    )


def create_context(backend: str | None = "egl"):
    """Create a standalone (headless) moderngl context of OpenGL >= 3.3.

    ``backend="egl"`` works without a display, on a GPU or on Mesa llvmpipe. ``None`` lets
    moderngl pick its platform default. Raises GLError with an install hint on failure.
    """
    try:
        import moderngl
    except ImportError as exc:  # pragma: no cover - dependency is required
        raise GLError(f"moderngl is not installed ({exc}); pip install moderngl") from None
    errors = []
    for b in [backend] + ([None] if backend is not None else []):
        kwargs = {"standalone": True, "require": 330}
        if b is not None:
            kwargs["backend"] = b
        try:
            return moderngl.create_context(**kwargs)
        except Exception as exc:  # moderngl raises plain Exceptions for missing EGL/GL
            errors.append(f"{b or 'default'}: {str(exc).splitlines()[0] if str(exc) else exc!r}")
    raise GLError(f"cannot create an OpenGL 3.3 context ({'; '.join(errors)}). {_INSTALL_HINT}")


def wrap_context(require: int = 330):
    """Wrap the OpenGL context current in this thread (e.g. a viewer window's), whether
    EGL or GLX made it current (moderngl's loader tries EGL first, then GLX). The headless
    contexts stay as they are: moderngl's default context is left unchanged."""
    import moderngl

    try:
        from _moderngl import DefaultLoader

        store = moderngl._store
        before = store.default_context
        try:
            moderngl.init_context(DefaultLoader())
            ctx = store.default_context
        finally:
            store.default_context = before
    except Exception as exc:
        raise GLError(f"no current OpenGL context to wrap: {exc}") from None
    if ctx.version_code < require:
        raise GLError(
            f"the current OpenGL context has version {ctx.version_code}, skydome needs "
            f"{require}. {_INSTALL_HINT}"
        )
    return ctx


_shared = threading.local()


def shared_context():
    """A per-thread headless context, created on first use and reused afterwards."""
    ctx = getattr(_shared, "ctx", None)
    if ctx is None:
        ctx = create_context()
        _shared.ctx = ctx
    return ctx
