"""Compiled programs held to their typed inputs, and full-screen passes.

A :class:`ShaderProgram` is a program of the shader library compiled with its input types
(``skydome.gpu.inputs``): checked against the program when it is compiled, and given
exactly one instance of each when it draws. A :class:`FullscreenPass` draws one over a whole
framebuffer (or over layers of a layered one) with the full-screen triangle.

Equal programs on one context are one GL program, counted: every holder of a
:class:`ShaderProgram` made with the same shader, defines and inputs shares it, and the last
to release it frees it. A program holds no state between draws that a holder relies on
(each draw sets every active uniform and binds its textures: ``check_values``), and a new
program costs a CPU rasterizer its shader's compilation at the first draw (llvmpipe: a
few milliseconds each; a sky's ``Sky.at`` copy at night draws with a dozen).
"""

from __future__ import annotations

import threading
import weakref

import moderngl
import numpy as np

from skydome.gpu.inputs import ShaderInputs, active_uniforms, check_program, check_values
from skydome.gpu.shaders import compile_program, defines_key

_TEXTURES = (moderngl.Texture, moderngl.Texture3D, moderngl.TextureArray, moderngl.TextureCube)

# context -> {key: _Shared}: the programs alive on each context.
_PROGRAMS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
_LOCK = threading.Lock()


class _Shared:
    """One compiled and checked program and the count of its holders."""

    def __init__(self, program, active: frozenset[str]):
        self.program = program
        self.active = active
        self.refs = 0


def _key(fragment, defines, source, layered, vertex, inputs) -> tuple | None:
    """What makes two programs equal, or None where a define's value cannot be a key."""
    typed = defines_key(defines)
    return None if typed is None else (fragment, typed, source, layered, vertex, inputs)


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
        self.inputs = tuple(inputs)
        key = _key(fragment, defines, source, layered, vertex, self.inputs)
        with _LOCK:
            programs = _PROGRAMS.setdefault(ctx, {})
            shared = programs.get(key) if key is not None else None
            if shared is None:
                program, text = compile_program(
                    ctx, fragment, defines, source=source, layered=layered, vertex=vertex
                )
                try:
                    check_program(fragment, program, text, self.inputs)
                except Exception:
                    program.release()
                    raise
                shared = _Shared(program, active_uniforms(program))
                if key is not None:
                    programs[key] = shared
            shared.refs += 1
        self._shared: _Shared | None = shared
        self._key = key
        self.program = shared.program
        self.active = shared.active

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
                # compiler may shorten an array to the elements the shader can reach); an
                # array given fewer elements is filled with zeros, so that nothing of an
                # earlier draw (another holder's: the programs are shared) stays in it.
                n = member.array_length * member.dimension
                flat = np.asarray(value, dtype="f4").ravel()[:n]
                if flat.size < n:
                    flat = np.concatenate([flat, np.zeros(n - flat.size, dtype="f4")])
                member.write(flat.tobytes())
            else:
                member.value = value

    def release(self) -> None:
        """This holder's share: the program is freed with its last holder (twice is
        harmless)."""
        with _LOCK:
            shared, self._shared = self._shared, None
            if shared is None:
                return
            shared.refs -= 1
            if shared.refs > 0:
                return
            programs = _PROGRAMS.get(self.ctx)
            if programs is not None and programs.get(self._key) is shared:
                del programs[self._key]
        shared.program.release()


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
        self.shader.release()
