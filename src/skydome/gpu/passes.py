"""Full-screen fragment passes: a compiled program, its empty vertex array, and a draw call."""

from __future__ import annotations

import moderngl
import numpy as np

from skydome.gpu.shaders import build_program


def set_uniforms(program, uniforms: dict[str, object]) -> None:
    """Set a program's uniforms by name; names the shader lacks (or the compiler removed)
    and vertex attributes are skipped, so passes can share one uniform dictionary.
    Vectors, matrices and arrays of floats go as raw float32 bytes in declared order (the
    compiler may shorten an array to the elements the shader can reach)."""
    for name, value in uniforms.items():
        member = program.get(name, None)
        if member is None or isinstance(member, moderngl.Attribute):
            continue
        if isinstance(value, (list, tuple, np.ndarray)) and np.size(value) > 1:
            n = member.array_length * member.dimension
            member.write(np.asarray(value, dtype="f4").ravel()[:n].tobytes())
        else:
            member.value = value


class FullscreenPass:
    """A fragment shader drawn over a whole framebuffer (or over layers of a layered one).

    ``textures`` maps sampler uniform names to textures; they are bound to consecutive
    units on each draw. Uniforms not used by the shader are ignored (the compiler may
    remove them), so passes can share one uniform dictionary.
    """

    def __init__(
        self,
        ctx,
        fragment: str,
        defines: dict[str, object] | None = None,
        *,
        source: str | None = None,
        layered: bool = False,
    ):
        self.ctx = ctx
        self.program = build_program(ctx, fragment, defines, source=source, layered=layered)
        self.vao = ctx.vertex_array(self.program, [])
        self.layered = layered

    def set_uniforms(self, uniforms: dict[str, object]) -> None:
        set_uniforms(self.program, uniforms)

    def draw(
        self,
        fbo,
        uniforms: dict[str, object] | None = None,
        textures: dict | None = None,
        layers: tuple[int, int] | None = None,
    ) -> None:
        """Draw into ``fbo``; for a layered pass ``layers=(first, count)``."""
        self.set_uniforms(uniforms or {})
        for unit, (name, tex) in enumerate((textures or {}).items()):
            member = self.program.get(name, None)
            if member is None:
                continue
            tex.use(location=unit)
            member.value = unit
        fbo.use()
        if self.layered:
            first, count = layers or (0, 1)
            self.program["u_layer0"].value = first
            self.vao.render(moderngl.TRIANGLES, vertices=3, instances=count)
        else:
            self.vao.render(moderngl.TRIANGLES, vertices=3)

    def release(self) -> None:
        self.vao.release()
        self.program.release()
