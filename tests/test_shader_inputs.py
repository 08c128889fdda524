"""Typed contracts: every pass takes frozen ShaderInputs dataclasses, held to the program when
it is compiled (a uniform the Python side would not set, or a field no shader declares, is an
error then) and when it draws (one instance of each input type, a value for every active
uniform)."""

from __future__ import annotations

import ast
import importlib
import pkgutil
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np
import pytest

import skydome
from skydome.errors import GLError
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs, declared_uniforms, library_uniforms

SOURCE = """
uniform vec4 u_glow;
uniform float u_gain;
out vec4 frag;
void main() { frag = u_glow * u_gain; }
"""


@dataclass(frozen=True)
class Glow(ShaderInputs):
    u_glow: tuple[float, float, float, float]
    u_gain: float


@dataclass(frozen=True)
class GlowOnly(ShaderInputs):
    u_glow: tuple[float, float, float, float]


@dataclass(frozen=True)
class Misspelt(ShaderInputs):
    u_glow: tuple[float, float, float, float]
    u_gian: float


@dataclass(frozen=True)
class Nested(ShaderInputs):
    glow: GlowOnly
    u_gain: float


def _draw(ctx, fpass, *inputs) -> np.ndarray:
    tex = ctx.texture((2, 2), 4, dtype="f4")
    fbo = ctx.framebuffer(color_attachments=[tex])
    try:
        fpass.draw(fbo, *inputs)
        return np.frombuffer(tex.read(), np.float32).reshape(2, 2, 4)
    finally:
        fbo.release()
        tex.release()


def test_a_uniform_no_input_gives_is_an_error_when_compiled(ctx):
    with pytest.raises(GLError, match="u_gain that none of its inputs"):
        FullscreenPass(ctx, "glow.glsl", inputs=(GlowOnly,), source=SOURCE)


def test_a_misspelt_field_is_an_error_when_compiled(ctx):
    with pytest.raises(GLError, match=r"Misspelt\.u_gian .*no shader declares"):
        FullscreenPass(ctx, "glow.glsl", inputs=(Misspelt, Glow), source=SOURCE)


def test_inputs_draw_and_nested_inputs_flatten(ctx):
    fpass = FullscreenPass(ctx, "glow.glsl", inputs=(Glow,), source=SOURCE)
    out = _draw(ctx, fpass, Glow((1.0, 2.0, 3.0, 4.0), 0.5))
    np.testing.assert_array_equal(out[0, 0], [0.5, 1.0, 1.5, 2.0])
    nested = FullscreenPass(ctx, "glow.glsl", inputs=(Nested,), source=SOURCE)
    assert Nested.uniform_names() == {"u_glow", "u_gain"}
    out = _draw(ctx, nested, Nested(GlowOnly((1.0, 1.0, 1.0, 1.0)), 3.0))
    np.testing.assert_array_equal(out[1, 1], [3.0] * 4)
    fpass.release()
    nested.release()


def test_a_draw_with_other_inputs_or_a_missing_value_is_an_error(ctx):
    fpass = FullscreenPass(ctx, "glow.glsl", inputs=(Glow,), source=SOURCE)
    with pytest.raises(GLError, match=r"draws with inputs \(Glow\), got \(GlowOnly\)"):
        _draw(ctx, fpass, GlowOnly((1.0, 1.0, 1.0, 1.0)))
    with pytest.raises(GLError, match=r"draws with inputs \(Glow\), got \(\)"):
        _draw(ctx, fpass)
    with pytest.raises(GLError, match="u_gain is active but has no value"):
        _draw(ctx, fpass, Glow((1.0, 1.0, 1.0, 1.0), None))
    fpass.release()


def test_declarations_are_read_several_to_a_line():
    text = "uniform int u_a, u_b[3], u_c;\nuniform highp vec2 u_d;\n// uniform float u_no;\n"
    assert declared_uniforms(text) == {"u_a", "u_b", "u_c", "u_d"}


def _all_inputs() -> list[type]:
    for module in pkgutil.walk_packages(skydome.__path__, "skydome."):
        importlib.import_module(module.name)
    found, todo = [], list(ShaderInputs.__subclasses__())
    while todo:
        kind = todo.pop()
        found.append(kind)
        todo.extend(kind.__subclasses__())
    return [k for k in found if k.__module__.startswith("skydome.")]


def test_every_input_field_of_the_package_is_a_uniform_of_its_shaders():
    kinds = _all_inputs()
    assert len(kinds) >= 30  # the package's passes, all typed
    declared = library_uniforms()
    for kind in kinds:
        names = {f.name for f in fields(kind) if f.name.startswith("u_")}
        assert names <= declared, (kind.__name__, sorted(names - declared))


def test_every_pass_of_the_package_declares_its_inputs():
    # A pass or a program built without ``inputs=`` would draw with nothing checked: every
    # call of FullscreenPass or ShaderProgram in the package names them.
    root = Path(skydome.__file__).parent
    for path in root.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Call):
                name = getattr(node.func, "id", getattr(node.func, "attr", ""))
                if name in ("FullscreenPass", "ShaderProgram"):
                    given = {k.arg for k in node.keywords}
                    assert "inputs" in given, f"{path.relative_to(root)}:{node.lineno}"
