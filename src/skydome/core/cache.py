"""The on-disk cache of precomputed tables: keyed by a hash of every input that changes them.

Files live in ``$SKYDOME_CACHE`` or, by default, ``$XDG_CACHE_HOME/skydome`` (else
``~/.cache/skydome``). They are written atomically and validated on load; a missing,
truncated, corrupt or mismatched file is rebuilt, with a warning for the last three.
"""

from __future__ import annotations

import ast
import hashlib
import json
import os
import warnings
from collections.abc import Callable
from functools import cache
from pathlib import Path

import numpy as np

from skydome.errors import CacheError, SkydomeWarning
from skydome.io.lutfile import read_lut_file, write_lut_file

#: Bump when the meaning of cached tables changes (shaders, layout).
CACHE_FORMAT_VERSION = 1


class CacheWarning(SkydomeWarning):
    """A cached file could not be used and is being rebuilt."""


def cache_dir() -> Path:
    """The cache directory (created on demand)."""
    env = os.environ.get("SKYDOME_CACHE")
    if env:
        return Path(env).expanduser()
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "skydome"


def cache_key(*parts: object) -> str:
    """SHA-256 (hex) of the JSON of ``parts`` plus the package and cache format versions."""
    import skydome

    blob = json.dumps(
        [skydome.__version__, CACHE_FORMAT_VERSION, *parts], sort_keys=True, default=repr
    )
    return hashlib.sha256(blob.encode()).hexdigest()


#: The installed package's root folder (``.../skydome``).
PACKAGE_ROOT = Path(__file__).resolve().parents[1]


def _module_file(module: str, root: Path) -> Path | None:
    """The source file of a ``skydome.*`` module or package under ``root``, if it exists."""
    parts = module.split(".")[1:]
    for path in (root.joinpath(*parts).with_suffix(".py"), root.joinpath(*parts, "__init__.py")):
        if parts and path.is_file():
            return path
    return (root / "__init__.py") if not parts else None


def _imported_modules(path: Path) -> set[str]:
    """Every ``skydome.*`` module that a source file imports, at any depth (function-level
    imports too), and for ``from skydome.x import y`` also ``skydome.x.y`` (y may be a
    submodule)."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names.update(a.name for a in node.names if a.name.split(".")[0] == "skydome")
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if node.module.split(".")[0] == "skydome":
                names.add(node.module)
                names.update(f"{node.module}.{a.name}" for a in node.names)
    return names


def code_files(module: str, root: Path | None = None) -> list[Path]:
    """The source files of ``module`` and of every skydome module it imports, transitively,
    plus the package data files (``data/``) whose names appear in that source: all the Python
    code and data that can shape what the module computes."""
    root = root or PACKAGE_ROOT
    seen: dict[Path, None] = {}
    todo = [module]
    while todo:
        name = todo.pop()
        # A package's modules are imported through its __init__; each parent package too.
        parts = name.split(".")
        todo.extend(".".join(parts[:i]) for i in range(1, len(parts)))
        path = _module_file(name, root)
        if path is None or path in seen:
            continue
        seen[path] = None
        todo.extend(_imported_modules(path))
    text = "\n".join(p.read_text() for p in seen)
    data = [p for p in sorted((root / "data").glob("*")) if p.is_file() and p.name in text]
    return sorted(seen) + data


@cache
def code_digest(module: str, root: Path | None = None) -> str:
    """SHA-256 (hex) of the files of ``code_files(module)``: a cache key part that changes
    whenever an installation's Python code or data behind a cached result is edited."""
    root = root or PACKAGE_ROOT
    h = hashlib.sha256()
    for path in code_files(module, root):
        h.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def cache_path(key: str, name: str = "tables", directory: Path | None = None) -> Path:
    """Where the tables of ``key`` are cached."""
    return (directory or cache_dir()) / f"{name}-{key[:32]}.lut"


def try_load(
    key: str, *, name: str = "tables", directory: Path | None = None
) -> dict[str, np.ndarray] | None:
    """The cached arrays of ``key``, or None if absent; a damaged file warns and gives None."""
    path = cache_path(key, name, directory)
    if not path.exists():
        return None
    try:
        arrays, _ = read_lut_file(path, key)
        return arrays
    except CacheError as exc:
        warnings.warn(f"rebuilding cached tables: {exc}", CacheWarning, stacklevel=2)
        return None


def store(
    key: str,
    arrays: dict[str, np.ndarray],
    *,
    name: str = "tables",
    meta: dict | None = None,
    directory: Path | None = None,
) -> Path | None:
    """Write arrays to the cache atomically; a failure only warns (returns None)."""
    path = cache_path(key, name, directory)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        return write_lut_file(path, key, arrays, meta)
    except Exception as exc:  # noqa: BLE001 - a cache write failure must not fail a render
        warnings.warn(f"cannot write the table cache {path}: {exc}", CacheWarning, stacklevel=2)
        return None


def load_or_build(
    key: str,
    build: Callable[[], dict[str, np.ndarray]],
    *,
    name: str = "tables",
    meta: dict | None = None,
    directory: Path | None = None,
) -> tuple[dict[str, np.ndarray], bool]:
    """Arrays for ``key``: loaded from the cache if valid, else built and stored.

    Returns (arrays, loaded_from_cache). A cache that cannot be written (read-only
    directory) only costs a warning; the built arrays are still returned.
    """
    arrays = try_load(key, name=name, directory=directory)
    if arrays is not None:
        return arrays, True
    arrays = build()
    store(key, arrays, name=name, meta=meta, directory=directory)
    return arrays, False
