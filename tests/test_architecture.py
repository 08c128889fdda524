"""The layout is the architecture: the package's parts (``tests/data/architecture.json``, a
copy of ``../shared/architecture.json``) and the imports that must never exist between them,
held against every import of the package (function-level ones included); floors that import
only downwards; no import cycle between packages; function-level imports only where a
dependency is optional or heavy (the command line starts without NumPy)."""

from __future__ import annotations

import ast
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from skydome.core.services import AirService

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "skydome"
ARCHITECTURE = json.loads((Path(__file__).parent / "data" / "architecture.json").read_text())

#: The floors, lowest first: a package imports only from its own floor's packages where the
#: architecture allows it, and from lower floors. The public face (sky.py, description.py,
#: api.py, the package root) stands under the front ends.
FLOORS = {
    "Base": 0,
    "Astro": 1,
    "Atmosphere": 2,
    "Celestial": 2,
    "Night": 2,
    "Clouds": 2,
    "Scene": 3,
    "Display": 3,
    "Top": 4,
    "Fronts": 5,
    "Reference": 6,  # oracles for the tests: may use anything, used by nothing in production
}
#: Within the base: its own floors (core over gpu, io, physics, spectra, errors).
BASE_FLOORS = {"errors": 0, "version": 0, "spectra": 1, "physics": 2, "gpu": 2, "io": 2, "core": 3}


def _part(rel: str) -> str:
    if rel == "__main__.py":  # `python -m skydome`: the command line
        return "Fronts"
    for name, part in ARCHITECTURE["parts"].items():
        for prefix in part["is"]:
            p = prefix.removeprefix("src/skydome/")
            if rel == p or (p.endswith("/") and rel.startswith(p)):
                return name
    return "Top"


def _module_file(module: str) -> str | None:
    """The file (relative to the package) of a ``skydome.*`` module."""
    parts = module.split(".")[1:]
    for path in (
        PACKAGE.joinpath(*parts).with_suffix(".py"),
        PACKAGE.joinpath(*parts, "__init__.py"),
    ):
        if parts and path.is_file():
            return path.relative_to(PACKAGE).as_posix()
    return "__init__.py" if not parts else None


def _imports(path: Path):
    """(target file, line, function-level) of every skydome import of a source file."""
    tree = ast.parse(path.read_text(), str(path))
    in_function = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            in_function |= {id(sub) for sub in ast.walk(node) if sub is not node}
    for node in ast.walk(tree):
        names = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        for name in names:
            if name.split(".")[0] != "skydome":
                continue
            target = _module_file(name)
            if target is not None:
                yield target, node.lineno, id(node) in in_function


def _edges():
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).as_posix()
        for target, line, lazy in _imports(path):
            if target != rel:
                yield rel, target, line, lazy


EDGES = list(_edges())


@pytest.mark.parametrize("never", ARCHITECTURE["never"], ids=lambda n: f"{n[0]}->{n[1]}")
def test_no_import_the_architecture_forbids(never):
    src, dst, why = never
    found = [
        f"{a}:{line} imports {b}" for a, b, line, _ in EDGES if _part(a) == src and _part(b) == dst
    ]
    assert not found, f"{why}: {found}"


def test_imports_run_down_the_floors():
    up = []
    for a, b, line, _ in EDGES:
        pa, pb = _part(a), _part(b)
        if pa == pb == "Base":
            fa, fb = (BASE_FLOORS[x.split("/")[0].removesuffix(".py")] for x in (a, b))
            if fb > fa:
                up.append(f"{a}:{line} -> {b}")
        elif pa != pb and FLOORS[pb] > FLOORS[pa] and pa != "Reference":
            up.append(f"{a}:{line} -> {b}")
        elif pa != pb and FLOORS[pa] == FLOORS[pb] and (pa, pb) != ("Scene", "Display"):
            up.append(f"{a}:{line} -> {b} (same floor)")
    assert not up, up


def test_no_import_cycle_between_packages():
    graph: dict[str, set[str]] = {}
    for a, b, _, _ in EDGES:
        pa, pb = a.split("/")[0], b.split("/")[0]
        if pa != pb and "/" in a and "/" in b:
            graph.setdefault(pa, set()).add(pb)

    def reaches(start: str, goal: str, seen: set) -> bool:
        for nxt in graph.get(start, ()):
            if nxt == goal or (nxt not in seen and reaches(nxt, goal, seen | {nxt})):
                return True
        return False

    cycles = sorted(p for p in graph if reaches(p, p, {p}))
    assert not cycles, cycles


def test_function_level_imports_only_at_the_front_ends():
    # The command line imports what pulls NumPy and OpenGL inside its commands (it starts
    # without them: `skydome --version` in 0.1 s), the package root loads its public face on
    # first use, the viewer its optional window libraries (glfw, imgui), the gazetteer
    # (`skydome places`: no NumPy) its Observer when one is asked for; the library imports at
    # the top.
    allowed = ("cli/", "viewer/", "__init__.py", "astro/places.py")
    lazy = [f"{a}:{line} -> {b}" for a, b, line, is_lazy in EDGES if is_lazy]
    assert all(x.startswith(allowed) for x in lazy), [x for x in lazy if not x.startswith(allowed)]


def test_the_package_root_forwards_exactly_the_public_face():
    # `skydome/__init__.py` lists the public names without importing them (the command line
    # starts without NumPy) and forwards each, on first use, to `skydome.api`: the two lists
    # are one list, and every name resolves to the same object. Run in a fresh interpreter:
    # importing the root must not import NumPy.
    code = (
        "import sys, skydome, skydome.api as api\n"
        "assert skydome.__all__ == api.__all__, set(skydome.__all__) ^ set(api.__all__)\n"
        "assert all(getattr(skydome, n) is getattr(api, n) for n in api.__all__)\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
    bare = "import sys, skydome; assert 'numpy' not in sys.modules, 'numpy imported'"
    subprocess.run([sys.executable, "-c", bare], check=True)


SHADERS = PACKAGE / "shaders"
_INCLUDE = re.compile(r'^\s*#include\s+"([^"]+)"', re.M)
#: Shader folders of the base floor: any shader may include them.
SHARED_SHADER_FOLDERS = {"common"}


def test_shaders_include_only_their_own_folder_common_and_service_interfaces():
    # The import rules hold for GLSL too: a layer's shader includes its own folder's files,
    # `common/`, and, from another layer, only the GLSL interface a typed service declares
    # (the air's lookups, AirService.GLSL): never another layer's internals.
    allowed_across = set(AirService.GLSL)
    wrong = []
    for path in sorted(SHADERS.rglob("*.glsl")):
        folder = path.relative_to(SHADERS).parts[0]
        for target in _INCLUDE.findall(path.read_text()):
            other = target.split("/")[0]
            if other in (folder, *SHARED_SHADER_FOLDERS) or target in allowed_across:
                continue
            wrong.append(f"{path.relative_to(SHADERS)} includes {target}")
    assert not wrong, wrong
    for target in allowed_across:
        assert (SHADERS / target).is_file(), target
