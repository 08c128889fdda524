"""The on-disk cache of precomputed tables: keyed by a hash of every input that changes them.

Files live in ``$SKYDOME_CACHE`` or, by default, ``$XDG_CACHE_HOME/skydome`` (else
``~/.cache/skydome``). They are written atomically and validated on load; a missing,
truncated, corrupt or mismatched file is rebuilt, with a warning for the last three.
"""

from __future__ import annotations

import hashlib
import json
import os
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

from skydome.errors import CacheError
from skydome.io.lutfile import read_lut_file, write_lut_file

#: Bump when the meaning of cached tables changes (shaders, layout).
CACHE_FORMAT_VERSION = 1


class CacheWarning(UserWarning):
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
