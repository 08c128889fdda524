"""The machinery of tests/test_glsl_twins.py: find the ``// twin:`` annotations of the shader
library, build the inputs they describe, run a GLSL function on them and call its twin.

An annotation is one line right above a GLSL function (descriptive comments go above it):

    // twin: skydome.physics.phase.henyey_greenstein(nu, g) nu=-1..1 g=-0.95..0.95

- the dotted name of the Python twin (a module, then attributes);
- its arguments: Python expressions over the GLSL function's ``in`` parameters, the uniforms
  and defines the annotation sets, ``np`` and ``math``;
- ``name=spec`` items. For an ``in`` parameter: ``lo..hi`` (a grid of floats, or every
  integer for an int), a number (fixed), ``unit`` (unit vectors spread over the sphere),
  ``lo..hi`` for a vector (points uniform in the box) or ``unit*lo..hi`` (unit vectors times
  lengths). Any other ``UPPER_CASE`` name is a ``#define``, any other name a float uniform.

The GLSL function's return value and ``out`` parameters (at most 4 floats in all; a bool is
0 or 1) are compared, in that order, with the twin's result (a value or a tuple of them,
flattened the same way). Where the twin's units, argument order or an instance differ from
the shader's, the test's ``SETUPS`` call the twin themselves (the annotation's arguments then
say what the call means) and may give inputs, uniform arrays, textures and a tolerance.

A file with its own ``main`` (a pass) is included with that ``main`` renamed, so the
functions of a pass can be checked too; the harness writes to an output at location 0.
"""

from __future__ import annotations

import dataclasses
import importlib
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.shaders import SHADER_DIR

#: Components of the GLSL types the harness passes in and out.
TYPE_SIZE = {"float": 1, "int": 1, "bool": 1, "vec2": 2, "vec3": 3, "vec4": 4}
#: Points per case (a 64 x 64 float texture).
POINTS = 4096
WIDTH = 64

_ANNOTATION = re.compile(r"^\s*//\s*twin:\s*(?P<body>.+?)\s*$")
_SIGNATURE = re.compile(r"^\s*(?P<ret>\w+)\s+(?P<name>\w+)\s*\((?P<params>[^)]*)\)\s*\{", re.S)
_PARAM = re.compile(r"^(?:(?P<q>in|out|inout)\s+)?(?:const\s+)?(?P<type>\w+)\s+(?P<name>\w+)$")
_MAIN = re.compile(r"^\s*void\s+main\s*\(", re.M)


@dataclass(frozen=True)
class Param:
    qualifier: str  # "in" or "out"
    type: str
    name: str


@dataclass
class Twin:
    """One annotation: where it is, the GLSL function under it, and what it says."""

    file: str  # relative to the shader library
    line: int
    function: str
    returns: str
    params: list[Param]
    target: str  # dotted name of the Python twin
    args: str  # the twin's arguments, Python expressions
    specs: dict[str, str] = field(default_factory=dict)

    @property
    def key(self) -> str:
        return f"{self.file}:{self.function}"

    @property
    def inputs(self) -> list[Param]:
        return [p for p in self.params if p.qualifier == "in"]

    @property
    def outputs(self) -> list[tuple[str, str]]:
        """(type, name) of the values written back: the return value, then the out params."""
        out = [] if self.returns == "void" else [(self.returns, "")]
        return out + [(p.type, p.name) for p in self.params if p.qualifier == "out"]

    def defines(self) -> dict[str, str]:
        names = {p.name for p in self.params}
        return {k: v for k, v in self.specs.items() if k not in names and k.isupper()}

    def uniforms(self) -> dict[str, float]:
        names = {p.name for p in self.params}
        return {k: float(v) for k, v in self.specs.items() if k not in names and not k.isupper()}


def _split_call(body: str) -> tuple[str, str, str]:
    """``dotted(args) rest`` -> (dotted, args, rest), parentheses balanced."""
    start = body.index("(")
    depth = 0
    for i, ch in enumerate(body[start:], start):
        depth += {"(": 1, ")": -1}.get(ch, 0)
        if depth == 0:
            return body[:start].strip(), body[start + 1 : i], body[i + 1 :].strip()
    raise ValueError(f"unbalanced parentheses in {body!r}")


def _parse_params(text: str, where: str) -> list[Param]:
    params = []
    for raw in filter(None, (p.strip() for p in text.replace("\n", " ").split(","))):
        m = _PARAM.match(" ".join(raw.split()))
        if m is None or m["type"] not in TYPE_SIZE or m["q"] == "inout":
            raise ValueError(f"{where}: the harness cannot pass parameter {raw!r}")
        params.append(Param(m["q"] or "in", m["type"], m["name"]))
    return params


def parse_file(path: Path) -> list[Twin]:
    """The annotations of one shader file."""
    rel = path.relative_to(SHADER_DIR).as_posix()
    lines = path.read_text().splitlines()
    twins = []
    for i, line in enumerate(lines):
        m = _ANNOTATION.match(line)
        if m is None:
            continue
        j = i + 1
        while j < len(lines) and _ANNOTATION.match(lines[j]):
            j += 1  # several annotations above one function: one case each
        sig = _SIGNATURE.match("\n".join(lines[j : j + 6]))
        where = f"{rel}:{i + 1}"
        if sig is None:
            raise ValueError(f"{where}: a twin annotation must sit right above a function")
        target, args, rest = _split_call(m["body"])
        specs = dict(item.split("=", 1) for item in rest.split())
        twins.append(
            Twin(
                file=rel,
                line=i + 1,
                function=sig["name"],
                returns=sig["ret"],
                params=_parse_params(sig["params"], where),
                target=target,
                args=args,
                specs=specs,
            )
        )
    return twins


def find_twins() -> list[Twin]:
    """Every annotation of the shader library, in file order."""
    return [t for path in sorted(SHADER_DIR.rglob("*.glsl")) for t in parse_file(path)]


def resolve(dotted: str):
    """The Python object of a dotted name: the longest importable module, then attributes."""
    parts = dotted.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        for attr in parts[k:]:
            obj = getattr(obj, attr)
        return obj
    raise ImportError(f"no module in {dotted!r}")


# ---------------------------------------------------------------------------------- inputs


def fibonacci_sphere(n: int) -> np.ndarray:
    """n unit vectors spread evenly over the sphere (a Fibonacci lattice), (n, 3)."""
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    phi = math.pi * (3.0 - math.sqrt(5.0)) * i
    s = np.sqrt(1.0 - z * z)
    return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=-1)


def _range(spec: str) -> tuple[float, float]:
    lo, hi = spec.split("..")
    return float(lo), float(hi)


def _axis(spec: str, type_: str, n: int, rng) -> np.ndarray:
    """n values (n, components) of one varying parameter."""
    if spec == "unit":
        return fibonacci_sphere(n)
    if spec.startswith("unit*"):
        return fibonacci_sphere(n) * (rng.uniform(*_range(spec[5:]), n))[:, None]
    lo, hi = _range(spec)
    if type_ == "int":
        return np.arange(lo, hi + 1)[:, None]
    if TYPE_SIZE[type_] == 1:
        return np.linspace(lo, hi, n)[:, None]
    return rng.uniform(lo, hi, (n, TYPE_SIZE[type_]))


def make_inputs(twin: Twin, points: int = POINTS) -> dict[str, np.ndarray]:
    """Inputs of every ``in`` parameter from the annotation, float32-rounded, (M, components):
    the full grid over the parameters that vary (a vector parameter is one axis), every
    integer of an int range, about ``points`` in all."""
    fixed, varying = {}, []
    for p in twin.inputs:
        spec = twin.specs.get(p.name)
        if spec is None:
            raise ValueError(f"{twin.key}: the annotation gives no values for {p.name!r}")
        if spec == "unit" or ".." in spec:
            varying.append((p, spec))
        else:
            fixed[p.name] = np.full(TYPE_SIZE[p.type], float(spec))
    n_int = math.prod(int(np.ptp(_range(s))) + 1 for p, s in varying if p.type == "int")
    n_other = sum(p.type != "int" for p, _ in varying)
    n = int((points / n_int) ** (1.0 / max(n_other, 1)) + 1e-9)
    rng = np.random.default_rng(0)
    axes = [_axis(spec, p.type, n, rng) for p, spec in varying]
    index = np.meshgrid(*[np.arange(len(a)) for a in axes], indexing="ij")
    count = index[0].size if axes else 1
    out = {p.name: a[i.ravel()] for (p, _), a, i in zip(varying, axes, index, strict=True)}
    out.update({k: np.broadcast_to(v, (count, len(v))) for k, v in fixed.items()})
    return {k: np.asarray(v, np.float32).astype(np.float64) for k, v in out.items()}


# ---------------------------------------------------------------------------------- the GPU


def shader_source(twin: Twin) -> str:
    """A fragment shader that includes the twin's file and calls its function per pixel."""
    has_main = _MAIN.search((SHADER_DIR / twin.file).read_text()) is not None
    lines = ["#define main twin_pass_main"] if has_main else []  # the pass's own main
    lines += [f'#include "{twin.file}"', "#undef main" if has_main else ""]
    lines += [f"uniform sampler2D twin_in_{k};" for k in range(len(twin.inputs))]
    lines += ["layout(location = 0) out vec4 twin_out;", "void main() {"]
    lines.append("    ivec2 twin_p = ivec2(gl_FragCoord.xy);")
    call = []
    inputs = {p.name: k for k, p in enumerate(twin.inputs)}  # input k: texture twin_in_k
    for p in twin.params:
        k = inputs.get(p.name)
        if p.qualifier == "out":
            lines.append(f"    {p.type} twin_{p.name};")
        elif p.type in ("int", "bool"):
            fetch = f"texelFetch(twin_in_{k}, twin_p, 0).x"
            value = f"int(floor({fetch} + 0.5))" if p.type == "int" else f"({fetch} > 0.5)"
            lines.append(f"    {p.type} twin_{p.name} = {value};")
        else:
            n = TYPE_SIZE[p.type]
            lines.append(
                f"    {p.type} twin_{p.name} = {p.type}(texelFetch(twin_in_{k}, twin_p, 0)"
                f".{'xyzw'[:n]});"
            )
        call.append(f"twin_{p.name}")
    result = f"{twin.function}({', '.join(call)})"
    parts = []
    if twin.returns != "void":
        lines.append(f"    {twin.returns} twin_result = {result};")
        parts.append("twin_result")
    else:
        lines.append(f"    {result};")
    parts += [f"twin_{p.name}" for p in twin.params if p.qualifier == "out"]
    floats = [
        f"float({v})" if t == "bool" else v for (t, _), v in zip(twin.outputs, parts, strict=True)
    ]
    size = sum(TYPE_SIZE[t] for t, _ in twin.outputs)
    if size > 4:
        raise ValueError(f"{twin.key}: more than 4 output components")
    lines.append(f"    twin_out = vec4({', '.join(floats + ['0.0'] * (4 - size))});")
    lines.append("}")
    return "\n".join(lines) + "\n"


def _input_texture(ctx, values: np.ndarray, height: int):
    data = np.zeros((height * WIDTH, 4), np.float32)
    v = values.reshape(len(values), -1)
    data[: len(v), : v.shape[1]] = v
    return ctx.texture((WIDTH, height), 4, data.tobytes(), dtype="f4")


def typed_inputs(values: dict) -> type[ShaderInputs]:
    """A ShaderInputs type whose fields are ``values``' uniform names: the harness's inputs,
    held to the program's active uniforms like any pass's."""
    fields = [(name, object) for name in sorted(values)]
    return dataclasses.make_dataclass("TwinInputs", fields, bases=(ShaderInputs,), frozen=True)


def run_gpu(ctx, twin: Twin, inputs, defines, uniforms, textures) -> np.ndarray:
    """The function's outputs (M, components) on the GPU, float32."""
    count = len(next(iter(inputs.values()))) if inputs else 1
    height = -(-count // WIDTH)
    made = [_input_texture(ctx, inputs[p.name], height) for p in twin.inputs]
    for tex in made:
        tex.filter = (ctx.NEAREST, ctx.NEAREST)
    bound = {f"twin_in_{k}": tex for k, tex in enumerate(made)}
    values = {k: v for k, v in {**uniforms, **bound, **textures}.items() if v is not None}
    kind = typed_inputs(values)
    fpass = FullscreenPass(
        ctx, f"twin:{twin.key}", defines, inputs=(kind,), source=shader_source(twin)
    )
    out = ctx.texture((WIDTH, height), 4, dtype="f4")
    fbo = ctx.framebuffer(color_attachments=[out])
    try:
        fpass.draw(fbo, kind(**values))
        data = np.frombuffer(out.read(), np.float32).reshape(-1, 4)[:count]
    finally:
        fbo.release()
        out.release()
        for tex in made:
            tex.release()
        fpass.release()
    size = sum(TYPE_SIZE[t] for t, _ in twin.outputs)
    return data[:, :size].astype(np.float64)


def flatten(result, count: int) -> np.ndarray:
    """The twin's result as (M, components) float64: a value or a tuple of values, each (),
    (M,) or (M, k); bools as 0/1."""
    parts = result if isinstance(result, tuple) else (result,)
    cols = []
    for part in parts:
        a = np.asarray(part, dtype=np.float64)
        if a.ndim <= 1:
            cols.append(np.broadcast_to(a, (count,))[:, None])
        else:
            cols.append(a.reshape(count, -1))
    return np.concatenate(cols, axis=1)


def environment(twin: Twin, inputs, uniforms, defines) -> dict[str, object]:
    """Names the twin's arguments may use: the inputs ((M,) for a scalar, (M, k) for a vector;
    one value, a number or a (k,) vector, where it is the same at every point), the uniforms
    (float32-rounded, as the GPU sees them) and the defines, numpy and math."""
    env: dict[str, object] = {"np": np, "math": math}
    for k, v in uniforms.items():
        a = np.asarray(v)
        env[k] = a.astype(np.float32).astype(np.float64) if a.dtype.kind == "f" else v
    env.update({k: _number(v) for k, v in defines.items()})
    types = {p.name: p.type for p in twin.inputs}
    for name, v in inputs.items():
        if np.all(v == v[0]):  # the same at every point: one value
            v = v[0]
        if v.ndim >= 1 and v.shape[-1] == 1:
            v = v[..., 0]
        if types.get(name) == "int":
            v = int(v) if np.ndim(v) == 0 else v.astype(np.int64)
        env[name] = v
    return env


def _number(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return v
