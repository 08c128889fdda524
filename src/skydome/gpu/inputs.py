"""Typed inputs of shader passes, checked against the program when it is compiled.

A pass's inputs are frozen dataclasses, subclasses of :class:`ShaderInputs`, whose field
names are the GLSL uniform names (a field holding a texture is a sampler; None: not given,
for a uniform an ``#ifdef`` leaves out). A pass declares the input types it takes
(``FullscreenPass(ctx, shader, defines, inputs=(CameraInputs, SunInputs))``); when its
program is compiled:

- every active uniform of the program must be a field of one of them: a uniform the Python
  side would not set (a silent zero) is an error at build time;
- every field of them must be a uniform some shader of the library declares (in any
  ``#ifdef`` branch; or the program's own source): a misspelt field is an error at build
  time. (An input type may serve several shaders and hold uniforms one of them lacks.)

and when it draws it takes exactly those types' instances, so a value cannot be missing
either (an active uniform whose field is None is an error too).
"""

from __future__ import annotations

import dataclasses
import re
import sys
import typing
from functools import cache

import moderngl

from skydome.errors import GLError
from skydome.gpu.shaders import SHADER_DIR

#: Uniforms the pass machinery sets itself (the layered passes' first layer).
INTERNAL_UNIFORMS = frozenset({"u_layer0"})
_DECLARATION = re.compile(r"^\s*uniform\s+(?:(?:lowp|mediump|highp)\s+)?\w+\s+([^;]+);", re.M)
_NAME = re.compile(r"(\w+)\s*(?:\[[^\]]*\])?\s*(?:,|$)")


@dataclasses.dataclass(frozen=True)
class ShaderInputs:
    """Base class of a pass's inputs (see the module docstring): subclass it as a frozen
    dataclass; a field may itself be a ShaderInputs, whose fields are flattened in."""

    @classmethod
    def uniform_names(cls) -> frozenset[str]:
        """The GLSL uniforms this type gives (nested inputs' included)."""
        return _names(cls)

    def values(self) -> dict[str, object]:
        """Uniform name -> value (textures included; nested inputs flattened)."""
        out: dict[str, object] = {}
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if isinstance(value, ShaderInputs):
                out.update(value.values())
            else:
                out[f.name] = value
        return out


@cache
def _names(cls) -> frozenset[str]:
    names: set[str] = set()
    hints = {f.name: f.type for f in dataclasses.fields(cls)}
    for f in dataclasses.fields(cls):
        nested = _nested_type(cls, f.name, hints[f.name])
        if nested is not None:
            names |= nested.uniform_names()
        else:
            names.add(f.name)
    return frozenset(names)


def _nested_type(cls, name: str, annotation) -> type | None:
    """The ShaderInputs type of a field, if it is one (annotations may be strings)."""

    if isinstance(annotation, str):
        module = sys.modules[cls.__module__]
        try:
            annotation = typing.get_type_hints(cls, vars(module))[name]
        except Exception:  # noqa: BLE001 - a forward reference to a non-inputs type
            return None
    if isinstance(annotation, type) and issubclass(annotation, ShaderInputs):
        return annotation
    return None


def declared_uniforms(source: str) -> frozenset[str]:
    """The uniforms a GLSL source declares (in any ``#ifdef`` branch; several to a line)."""
    names: set[str] = set()
    for names_text in _DECLARATION.findall(source):
        names |= set(_NAME.findall(names_text.strip()))
    return frozenset(names)


@cache
def library_uniforms() -> frozenset[str]:
    """Every uniform a file of the shader library declares."""

    names: set[str] = set()
    for path in SHADER_DIR.rglob("*.glsl"):
        names |= declared_uniforms(path.read_text())
    return frozenset(names)


def active_uniforms(program) -> frozenset[str]:
    """The uniforms the compiler kept in a moderngl program (samplers included)."""

    return frozenset(
        name
        for name in program
        if isinstance(program[name], moderngl.Uniform) and name not in INTERNAL_UNIFORMS
    )


def check_program(shader: str, program, source: str, inputs: tuple[type, ...]) -> None:
    """Hold a compiled program to its input types (see the module docstring); GLError
    naming the shader and the uniform or field otherwise."""
    given: dict[str, type] = {}
    for kind in inputs:
        if not (isinstance(kind, type) and issubclass(kind, ShaderInputs)):
            raise GLError(f"shader {shader}: its inputs must be ShaderInputs types, got {kind!r}")
        for name in kind.uniform_names():
            given.setdefault(name, kind)
    names = ", ".join(k.__name__ for k in inputs) or "none"
    missing = sorted(active_uniforms(program) - set(given))
    if missing:
        raise GLError(
            f"shader {shader} uses uniform {missing[0]} that none of its inputs ({names}) "
            f"gives{f' (and {len(missing) - 1} more)' if len(missing) > 1 else ''}"
        )
    declared = declared_uniforms(source) | library_uniforms()
    unknown = sorted(set(given) - declared)
    if unknown:
        raise GLError(
            f"shader {shader}: {given[unknown[0]].__name__}.{unknown[0]} is a uniform no "
            "shader declares (misspelt?)"
        )


def check_values(
    shader: str, active: frozenset[str], inputs: tuple[type, ...], given: tuple
) -> dict:
    """The uniforms' values of a draw: exactly one instance of each declared input type,
    and a value for every ``active`` uniform."""
    kinds = tuple(type(g) for g in given)
    if len(kinds) != len(inputs) or set(kinds) != set(inputs):
        want = ", ".join(k.__name__ for k in inputs)
        got = ", ".join(k.__name__ for k in kinds)
        raise GLError(f"shader {shader} draws with inputs ({want}), got ({got})")
    values: dict[str, object] = {}
    for g in given:
        values.update(g.values())
    for name in active:
        if values.get(name) is None:
            raise GLError(f"shader {shader}: uniform {name} is active but has no value")
    return values
