"""Compiled programs held to their typed inputs, and full-screen passes.

A :class:`ShaderProgram` is a program of the shader library compiled with its input types
(``skydome.gpu.inputs``): checked against the program when it is compiled, and given
exactly one instance of each when it draws. A :class:`FullscreenPass` draws one over a whole
framebuffer (or over layers of a layered one) with the full-screen triangle.
"""

from __future__ import annotations

import moderngl
import numpy as np

from skydome.gpu.inputs import ShaderInputs, active_uniforms, check_program, check_values
from skydome.gpu.shaders import compile_program

_TEXTURES = (moderngl.Texture, moderngl.Texture3D, moderngl.TextureArray, moderngl.TextureCube)


class ShaderProgram:
    """A program of the shader library and the types of its inputs.

    Args:
        ctx: the moderngl context.
        fragment: a file under ``skydome/shaders`` (or the label of ``source``).
        defines: ``#define`` lines put before the source.
        inputs: the ShaderInputs types the program takes (checked now: see
            ``skydome.gpu.inputs``).
        source: GLSL text instead of the file (tests' small programs).
        layered: route instance i to layer ``u_layer0 + i`` of a layered target.
        vertex: a vertex shader of the library, for programs that draw geometry.
    """

    def __init__(
        self,
        ctx,
        fragment: str,
        defines: dict[str, object] | None = None,
        *,
        inputs: tuple[type[ShaderInputs], ...],
        source: str | None = None,
        layered: bool = False,
        vertex: str | None = None,
    ):
        self.ctx = ctx
        self.name = fragment
        self.program, text = compile_program(
            ctx, fragment, defines, source=source, layered=layered, vertex=vertex
        )
        self.inputs = tuple(inputs)
        try:
            check_program(fragment, self.program, text, self.inputs)
        except Exception:
            self.program.release()
            raise
        self.active = active_uniforms(self.program)

    def apply(self, *given: ShaderInputs, first_unit: int = 0) -> None:
        """Set the uniforms of ``given`` (one instance of each input type) and bind their
        textures to consecutive units from ``first_unit``."""
        values = check_values(self.name, self.active, self.inputs, given)
        unit = first_unit
        for name, value in values.items():
            if name not in self.active or value is None:
                continue
            member = self.program[name]
            if isinstance(value, _TEXTURES):
                value.use(location=unit)
                member.value = unit
                unit += 1
            elif isinstance(value, (list, tuple, np.ndarray)) and np.size(value) > 1:
                # Vectors, matrices and arrays go as raw float32 bytes in declared order (the
                # compiler may shorten an array to the elements the shader can reach).
                n = member.array_length * member.dimension
                member.write(np.asarray(value, dtype="f4").ravel()[:n].tobytes())
            else:
                member.value = value

    def release(self) -> None:
        self.program.release()


class FullscreenPass:
    """A fragment shader drawn over a whole framebuffer (or over layers of a layered one);
    its inputs are typed (:class:`ShaderProgram`)."""

    def __init__(
        self,
        ctx,
        fragment: str,
        defines: dict[str, object] | None = None,
        *,
        inputs: tuple[type[ShaderInputs], ...],
        source: str | None = None,
        layered: bool = False,
    ):
        self.ctx = ctx
        self.shader = ShaderProgram(
            ctx, fragment, defines, inputs=inputs, source=source, layered=layered
        )
        self.program = self.shader.program
        self.vao = ctx.vertex_array(self.program, [])
        self.layered = layered

    def draw(self, fbo, *inputs: ShaderInputs, layers: tuple[int, int] | None = None) -> None:
        """Draw into ``fbo`` with ``inputs`` (one instance of each of the pass's input
        types); for a layered pass ``layers=(first, count)``."""
        self.shader.apply(*inputs)
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
