"""Texture helpers shared by the precomputation and the renderers."""

from __future__ import annotations


def release_unbound(obj) -> None:
    """Release a GL object; a framebuffer that is the context's bound one is unbound first
    (the default framebuffer bound instead). moderngl rebinds its bound framebuffer after
    it makes another one: bound to a deleted name, that rebind is GL_INVALID_OPERATION, a
    flag the next ``ctx.error`` (a viewer's check of its context) would report."""
    ctx = getattr(obj, "ctx", None)
    if ctx is not None and ctx.fbo is obj:
        (ctx.screen or ctx.detect_framebuffer(0)).use()
    obj.release()


def release_all(*objects) -> None:
    """Release GL objects (None skipped), framebuffers unbound first (:func:`release_unbound`)."""
    for obj in objects:
        if obj is not None:
            release_unbound(obj)


def linear_clamped(tex, ctx):
    """Set ``tex`` (2D, array or 3D) to linear filtering with clamped edges; returns it."""
    tex.filter = (ctx.LINEAR, ctx.LINEAR)
    tex.repeat_x = tex.repeat_y = False
    if hasattr(tex, "repeat_z"):
        tex.repeat_z = False
    return tex


def copy_array_to_3d(ctx, array, volume) -> None:
    """Copy a texture array (rendered layer by layer) into a 3D texture of the same size and
    format, through a GPU buffer (no trip through host memory on a GPU): 3D textures filter
    across layers, which texture arrays do not."""
    w, h, d = array.size
    bytes_per_component = int(array.dtype[-1])  # moderngl dtypes: "f1", "f2", "f4", "u2", ...
    buffer = ctx.buffer(reserve=w * h * d * array.components * bytes_per_component)
    try:
        array.read_into(buffer)
        volume.write(buffer)
    finally:
        buffer.release()


class FloatTargets:
    """RGBA32F render targets (bilinear, clamped to their edges), one per (role, size), kept
    for reuse between frames: a post pass's intermediate images."""

    def __init__(self, ctx):
        self.ctx = ctx
        self._targets: dict[tuple, tuple] = {}

    def get(self, role: str, size: tuple[int, int]):
        """(texture, framebuffer) of ``role`` at ``size`` (made the first time)."""
        key = (role, tuple(size))
        if key not in self._targets:
            tex = linear_clamped(self.ctx.texture(size, 4, dtype="f4"), self.ctx)
            self._targets[key] = (tex, self.ctx.framebuffer(color_attachments=[tex]))
        return self._targets[key]

    def release(self) -> None:
        """Free every target (framebuffers unbound first)."""
        for tex, fbo in self._targets.values():
            release_all(fbo, tex)
        self._targets.clear()
