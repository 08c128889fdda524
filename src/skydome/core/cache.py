"""The on-disk cache of precomputed tables, keyed by the inputs each product declares.

Each cached product (the atmosphere tables, the cloud noise) declares a :class:`CacheSpec`
next to its builder: a name, a version, the shader folders whose GLSL makes it and the
Python and data files whose code shapes it. Its key is the SHA-256 of the spec's name and
version, the cache and file format versions, the digest of the GLSL files of its shader
folders and the JSON of its parameters: nothing else (not the package version, not which
modules import which). The Python behind a product is not hashed at run time: the test
``tests/test_cache.py`` compares the SHA-256 of each spec's builder files with the manifest
``tests/data/cache_builders.json`` and fails when one changed while the version did not.

Files live in ``$SKYDOME_CACHE`` or, by default, ``$XDG_CACHE_HOME/skydome`` (else
``~/.cache/skydome``), named ``<name>-<first 32 hex digits of the key>.lut``. They are
written atomically; temporary files of writers that died are removed by the next load or
store. The folder is bounded: after each store the least recently used entries are removed
until it holds at most ``$SKYDOME_CACHE_MAX_MB`` (default 2048 MiB; a load counts as a use),
so that many cloud seeds or a long batch of atmospheres cannot fill a disk. A missing file is built silently; any fault while loading one (whatever it is: a
damaged file, a FIFO, a directory, arrays of the wrong shape) gives one CacheWarning, the
entry is removed and the product rebuilt and stored again.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
import shutil
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from skydome.errors import SkydomeWarning
from skydome.gpu.shaders import sources_digest
from skydome.io.atomic import remove_stale_temps
from skydome.io.lutfile import FORMAT_VERSION, read_lut_file, write_lut_file

#: Bump when the meaning of keys or of the cache's layout changes for every product.
CACHE_FORMAT_VERSION = 2

#: The installed package's root folder (``.../skydome``): builder files are relative to it.
PACKAGE_ROOT = Path(__file__).resolve().parents[1]

_SUFFIX = ".lut"
#: A table file's temporary copy unchanged for this long (s) is stale whoever wrote it: a
#: store writes its tens of MB in well under a second.
STALE_TEMP_S = 60.0
#: The cache folder's default bound (MiB): a dozen atmospheres and cloud noises.
DEFAULT_MAX_MB = 2048


class CacheWarning(SkydomeWarning):
    """A cached file could not be used and is being rebuilt."""


@dataclass(frozen=True)
class CacheSpec:
    """What one cached product depends on, besides its parameters.

    Attributes:
        name: the product's name in keys and the manifest (lower case, digits, hyphens).
        version: an integer >= 1; bump it whenever a change of the Python or data behind
            the product (its ``builder_files``) changes what it computes.
        shader_folders: folders of ``shaders/`` whose GLSL files (``*.glsl``, recursively)
            are hashed into the key: an edited shader never reuses stale tables.
        builder_files: files relative to the package root (``atmosphere/precompute.py``,
            ``data/...csv``) whose content shapes the product. Not hashed at run time; the
            manifest test makes an edit of one without a version bump fail.
    """

    name: str
    version: int
    shader_folders: tuple[str, ...] = ()
    builder_files: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not re.fullmatch(r"[a-z0-9]+(-[a-z0-9]+)*", self.name):
            raise ValueError(f"cache spec name {self.name!r}: use lower case, digits, hyphens")
        if type(self.version) is not int or self.version < 1:
            raise ValueError(f"cache spec {self.name}: version {self.version!r} is not >= 1")
        for field in ("shader_folders", "builder_files"):
            value = getattr(self, field)
            if not isinstance(value, tuple) or not all(isinstance(v, str) for v in value):
                raise ValueError(f"cache spec {self.name}: {field} must be a tuple of str")

    def key(self, params: Any) -> str:
        """SHA-256 (hex) of the spec, the format versions, the GLSL of ``shader_folders`` and
        ``params`` (JSON: dicts, lists, tuples, str, numbers, bool, None, NumPy values)."""
        blob = json.dumps(
            {
                "product": [self.name, self.version],
                "format": [CACHE_FORMAT_VERSION, FORMAT_VERSION],
                "shaders": sources_digest(tuple(sorted(self.shader_folders))),
                "params": params,
            },
            sort_keys=True,
            default=_json_value,
        )
        return hashlib.sha256(blob.encode()).hexdigest()

    def builder_digests(self, root: Path | None = None) -> dict[str, str]:
        """SHA-256 (hex) of each builder file by its relative path (for the manifest)."""
        root = root or PACKAGE_ROOT
        return {f: hashlib.sha256((root / f).read_bytes()).hexdigest() for f in self.builder_files}


def _json_value(value: Any) -> Any:
    if isinstance(value, np.ndarray | np.generic):
        return value.tolist()
    # Not repr(): a repr may hold an address or elide array elements, and keys must be exact.
    raise TypeError(f"a cache key parameter of type {type(value).__name__} is not JSON")


def cache_dir() -> Path:
    """The cache directory (created on demand)."""
    env = os.environ.get("SKYDOME_CACHE")
    if env:
        return Path(env).expanduser()
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "skydome"


def cache_max_bytes() -> int:
    """The cache folder's bound in bytes (``$SKYDOME_CACHE_MAX_MB``, default 2048 MiB)."""
    text = os.environ.get("SKYDOME_CACHE_MAX_MB", "").strip()
    try:
        max_mb = float(text) if text else DEFAULT_MAX_MB
    except ValueError:
        warnings.warn(
            f"SKYDOME_CACHE_MAX_MB={text!r} is not a number; using {DEFAULT_MAX_MB}",
            CacheWarning,
            stacklevel=2,
        )
        max_mb = DEFAULT_MAX_MB
    return max(0, int(max_mb * 2**20))


def prune(directory: str | os.PathLike, max_bytes: int, *, keep: Path | None = None) -> int:
    """Remove the least recently used cache entries (oldest modification time first) of
    ``directory`` until its entries total at most ``max_bytes``; ``keep`` is never removed.
    Returns the number of entries removed."""
    entries = []
    for path in Path(directory).glob(f"*{_SUFFIX}"):
        with contextlib.suppress(OSError):
            st = path.stat()
            entries.append((st.st_mtime, st.st_size, path))
    total = sum(size for _, size, _ in entries)
    removed = 0
    for _, size, path in sorted(entries, key=lambda e: e[0]):
        if total <= max_bytes:
            break
        if keep is not None and path == keep:
            continue
        with contextlib.suppress(FileNotFoundError):
            path.unlink()
            removed += 1
        total -= size
    return removed


def cache_path(key: str, name: str = "tables", directory: str | os.PathLike | None = None) -> Path:
    """Where the arrays of ``key`` are cached (``name`` made safe for a file name)."""
    safe = re.sub(r"[^A-Za-z0-9_.-]", "_", name).lstrip(".")
    return Path(directory or cache_dir()) / f"{safe}-{key[:32]}{_SUFFIX}"


def _reject(path: Path, exc: BaseException) -> None:
    """One CacheWarning for a cache entry that cannot be used, and the entry removed
    (whatever it is: a file, a link, a FIFO, a directory), so that it is rebuilt."""
    reason = str(exc) if str(path) in str(exc) else f"{path}: {type(exc).__name__}: {exc}"
    warnings.warn(f"rebuilding cached tables: {reason}", CacheWarning, stacklevel=3)
    with contextlib.suppress(OSError):
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path)
        else:
            path.unlink()


def try_load(
    key: str, *, name: str = "tables", directory: str | os.PathLike | None = None
) -> dict[str, np.ndarray] | None:
    """The cached arrays of ``key``, or None if absent; an entry that cannot be loaded, for
    any reason, warns once, is removed and gives None."""
    path = cache_path(key, name, directory)
    remove_stale_temps(path.parent, _SUFFIX, max_age_s=STALE_TEMP_S)
    if not os.path.lexists(path):
        return None
    try:
        arrays, _ = read_lut_file(path, key)
    except Exception as exc:  # noqa: BLE001 - any fault at all: never trusted, never raised
        _reject(path, exc)
        return None
    with contextlib.suppress(OSError):
        os.utime(path)  # a use: the bound removes the least recently used entries first
    return arrays


def store(
    key: str,
    arrays: dict[str, np.ndarray],
    *,
    name: str = "tables",
    meta: dict | None = None,
    directory: str | os.PathLike | None = None,
) -> Path | None:
    """Write arrays to the cache atomically; a failure only warns (returns None)."""
    path = cache_path(key, name, directory)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        remove_stale_temps(path.parent, _SUFFIX, max_age_s=STALE_TEMP_S)
        written = write_lut_file(path, key, arrays, meta)
        prune(path.parent, cache_max_bytes(), keep=written)
        return written
    except Exception as exc:  # noqa: BLE001 - a cache write failure must not fail a render
        warnings.warn(f"cannot write the table cache {path}: {exc}", CacheWarning, stacklevel=2)
        return None


def load_or_build(
    key: str,
    build: Callable[[], Any],
    *,
    name: str = "tables",
    meta: dict | None = None,
    directory: str | os.PathLike | None = None,
    decode: Callable[[dict[str, np.ndarray]], Any] | None = None,
    encode: Callable[[Any], dict[str, np.ndarray]] | None = None,
) -> tuple[Any, bool]:
    """The product of ``key``: ``decode(arrays)`` of the cached arrays if they load and
    decode, else ``build()``, stored as ``encode(product)``. Without ``decode``/``encode``
    the product is the dict of arrays itself.

    ``decode`` raises (anything) for arrays it cannot use (a wrong shape, a NaN): that is a
    fault of the entry like a damaged file: one CacheWarning, then a rebuild. Returns
    (product, loaded_from_cache). A cache that cannot be written (read-only directory) only
    costs a warning; the built product is still returned.
    """
    arrays = try_load(key, name=name, directory=directory)
    if arrays is not None:
        try:
            return (arrays if decode is None else decode(arrays)), True
        except Exception as exc:  # noqa: BLE001 - the same as a damaged file
            _reject(cache_path(key, name, directory), exc)
    product = build()
    store(
        key,
        product if encode is None else encode(product),
        name=name,
        meta=meta,
        directory=directory,
    )
    return product, False
