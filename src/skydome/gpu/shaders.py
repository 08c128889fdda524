"""Shader library: GLSL files under ``skydome/shaders`` with ``#include`` and ``#define`` injection.

Drivers disagree on honouring source-string numbers in ``#line``, so each included file
instead gets its own block of line numbers (``#line FILE_INDEX*100000 + LINE``); compiler
messages such as ``0:100012(5): error`` (Mesa) or ``0(100012) : error`` (NVIDIA) are
mapped back to ``file.glsl:12``.
"""

from __future__ import annotations

import hashlib
import re
from functools import cache, lru_cache
from importlib import resources
from pathlib import Path

from skydome.errors import GLError

SHADER_DIR = Path(str(resources.files("skydome") / "shaders"))
VERSION_LINE = "#version 330 core"
_LINE_BLOCK = 100000
_INCLUDE = re.compile(r'^\s*#include\s+"([^"]+)"\s*$')


@cache
def sources_digest(folders: tuple[str, ...] | None = None) -> str:
    """SHA-256 (hex) of the shader files (of ``folders`` of the library, default all): part
    of the keys of cached GPU results, so that a change to the GLSL (a new table layout, a
    fixed integral) never reuses stale tables."""
    h = hashlib.sha256()
    paths = (
        SHADER_DIR.rglob("*.glsl")
        if folders is None
        else (p for f in folders for p in (SHADER_DIR / f).rglob("*.glsl"))
    )
    for path in sorted(paths):
        name = path.relative_to(SHADER_DIR).as_posix()
        h.update(name.encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def _read(name: str) -> str:
    path = SHADER_DIR / name
    if not path.is_file():
        raise GLError(f"shader file not found: {name} (looked in {SHADER_DIR})")
    return path.read_text()


class ShaderSource:
    """A fully expanded shader with the table that maps source-string numbers to files."""

    def __init__(self, text: str, files: list[str]):
        self.text = text
        self.files = tuple(files)

    def locate(self, message: str) -> str:
        """Rewrite driver messages 'S:L(C)' / 'S(L)' into 'file.glsl:line'."""

        def sub(m: re.Match) -> str:
            idx, line = divmod(int(m.group(2)), _LINE_BLOCK)
            name = self.files[idx] if idx < len(self.files) else f"<string {idx}>"
            return f"{name}:{line}"

        message = re.sub(r"\b(\d+):(\d+)\(\d+\)", sub, message)  # Mesa
        return re.sub(r"\b(\d+)\((\d+)\)", sub, message)  # NVIDIA / AMD


def expand(
    name: str, defines: dict[str, object] | None = None, source: str | None = None
) -> ShaderSource:
    """Expand shader ``name`` (or the given ``source`` text, labelled ``name``).

    Adds ``#version 330 core``, then one ``#define KEY VALUE`` per entry of ``defines``,
    then the file with its ``#include "x.glsl"`` lines replaced (each file once). A library
    file's expansion is kept per set of defines (a new sky's passes, ``Sky.at``'s, read and
    join no file again).
    """
    key = defines_key(defines) if source is None else None
    if key is not None:
        return _expand_file(name, key)
    return _expand(name, defines, source)


def defines_key(defines: dict[str, object] | None) -> tuple | None:
    """``defines`` as a hashable key of (name, type, value) triples (1, 1.0 and True are
    equal values but different GLSL), or None where a value cannot be a key."""
    key = tuple((k, type(v), v) for k, v in (defines or {}).items())
    try:
        hash(key)
    except TypeError:
        return None
    return key


@lru_cache(maxsize=512)
def _expand_file(name: str, defines: tuple) -> ShaderSource:
    """``_expand`` of a library file, ``defines`` as :func:`defines_key` gives them."""
    return _expand(name, {k: v for k, _, v in defines}, None)


def _expand(name: str, defines: dict[str, object] | None, source: str | None) -> ShaderSource:
    files: list[str] = ["<defines>"]
    seen: set[str] = set()
    out = [VERSION_LINE]
    for key, value in (defines or {}).items():
        if isinstance(value, bool):
            value = int(value)
        if isinstance(value, float):
            value = repr(value) if "e" not in repr(value) else f"{value:.9e}"
        out.append(f"#define {key} {value}")

    def emit(fname: str, text: str) -> None:
        seen.add(fname)
        files.append(fname)
        idx = len(files) - 1
        out.append(f"#line {idx * _LINE_BLOCK + 1}")
        for lineno, line in enumerate(text.splitlines(), start=1):
            if line.strip().startswith("#version"):
                out.append("")
                continue
            m = _INCLUDE.match(line)
            if m:
                inc = m.group(1)
                if inc not in seen:
                    emit(inc, _read(inc))
                out.append(f"#line {idx * _LINE_BLOCK + lineno + 1}")
            else:
                out.append(line)

    emit(name, source if source is not None else _read(name))
    return ShaderSource("\n".join(out) + "\n", files)


FULLSCREEN_VS = """#version 330 core
// Full-screen triangle; v_uv in [0,1]^2 over the viewport, no vertex buffer needed.
out vec2 v_uv;
void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    v_uv = p;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
"""

LAYERED_VS = """#version 330 core
out vec2 vs_uv;
void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    vs_uv = p;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
"""

# One triangle per instance, routed to layer gl_InstanceID + u_layer0 of a layered target.
LAYERED_GS = """#version 330 core
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec2 vs_uv[];
flat in int vs_instance[];
out vec2 v_uv;
flat out int v_layer;
uniform int u_layer0;
void main() {
    for (int i = 0; i < 3; ++i) {
        v_uv = vs_uv[i];
        v_layer = u_layer0 + vs_instance[i];
        gl_Layer = v_layer;
        gl_Position = gl_in[i].gl_Position;
        EmitVertex();
    }
    EndPrimitive();
}
"""

LAYERED_VS_INSTANCED = """#version 330 core
out vec2 vs_uv;
flat out int vs_instance;
void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    vs_uv = p;
    vs_instance = gl_InstanceID;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
"""


def build_program(
    ctx,
    fragment: str,
    defines: dict[str, object] | None = None,
    *,
    source: str | None = None,
    layered: bool = False,
    vertex: str | None = None,
):
    """Compile a full-screen fragment program from the shader library.

    ``fragment`` names a file under ``skydome/shaders`` (or labels ``source``). With
    ``layered=True`` a geometry shader routes instance i to layer ``u_layer0 + i`` and the
    fragment shader receives ``flat in int v_layer``. ``vertex`` names a vertex shader of
    the library (expanded with the same defines) for passes that draw geometry (point
    sources, lines) instead of the full-screen triangle. Compile errors raise GLError naming
    the file and line.
    """
    return compile_program(ctx, fragment, defines, source=source, layered=layered, vertex=vertex)[0]


def compile_program(
    ctx,
    fragment: str,
    defines: dict[str, object] | None = None,
    *,
    source: str | None = None,
    layered: bool = False,
    vertex: str | None = None,
) -> tuple[object, str]:
    """:func:`build_program`, and the expanded GLSL of its shaders (vertex and fragment, one
    text: what the typed inputs are held to)."""
    src = expand(fragment, defines, source)
    vsrc = expand(vertex, defines) if vertex is not None else None
    text = src.text if vsrc is None else vsrc.text + "\n" + src.text
    try:
        if vsrc is not None:
            try:
                return ctx.program(vertex_shader=vsrc.text, fragment_shader=src.text), text
            except Exception as exc:
                if "vertex" in str(exc).lower():
                    src = vsrc  # locate the error in the vertex shader's files
                raise
        if layered:
            program = ctx.program(
                vertex_shader=LAYERED_VS_INSTANCED,
                geometry_shader=LAYERED_GS,
                fragment_shader=src.text,
            )
            return program, text
        return ctx.program(vertex_shader=FULLSCREEN_VS, fragment_shader=src.text), text
    except Exception as exc:
        msg = src.locate(str(exc)).strip()
        lines = [
            ln for ln in msg.splitlines() if ln.strip() and "=" * 5 not in ln and "-" * 5 not in ln
        ]
        raise GLError(f"shader {fragment} failed to compile: {' | '.join(lines[:6])}") from None
