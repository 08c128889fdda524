"""Precomputed tables of an atmosphere, loaded from the disk cache or computed and stored."""

from __future__ import annotations

import warnings
import weakref
from collections.abc import Callable

from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.precompute import PrecomputedAtmosphere, precompute
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.core.cache import CacheWarning, cache_key, code_digest, store, try_load
from skydome.errors import CacheError


def tables_key(params: AtmosphereParams, config: PrecomputeConfig) -> str:
    """Cache key of the tables: every parameter, every config field, the package version, the
    shader sources, and the Python code and data files that shape the tables (this module and
    all it imports: the precomputation, the ln L interpolation, the spectral conversion and
    its CIE tables, the table file encoding)."""
    from skydome.gpu.shaders import sources_digest

    return cache_key(
        "precomputed",
        params.to_dict(),
        config.key(),
        # The tables are made by shaders/atmosphere/ with includes from shaders/common/ only:
        # night-sky, celestial and display shaders do not invalidate them.
        sources_digest(("atmosphere", "common")),
        code_digest("skydome.atmosphere.tables"),
    )


def load_tables(
    ctx,
    params: AtmosphereParams,
    config: PrecomputeConfig | None = None,
    *,
    cache: bool = True,
    progress: Callable[[str, float], None] | None = None,
) -> tuple[PrecomputedAtmosphere, bool]:
    """The precomputed tables of ``params``: from the disk cache when valid, else computed
    (and stored). Returns (tables, loaded_from_cache). A damaged or mismatched cache file is
    rebuilt with a CacheWarning."""
    config = config or PrecomputeConfig()
    key = tables_key(params, config)
    name = f"sky-{params.name}"
    if cache:
        arrays = try_load(key, name=name)
        if arrays is not None:
            try:
                return PrecomputedAtmosphere.from_arrays(ctx, params, config, arrays), True
            except CacheError as exc:
                warnings.warn(f"rebuilding cached tables: {exc}", CacheWarning, stacklevel=2)
    tables = precompute(ctx, params, config, progress=progress)
    if cache:
        store(key, tables.to_arrays(), name=name, meta={"atmosphere": params.name})
    return tables, False


#: Tables in GPU memory by (context, key): renderers of the same atmosphere and configuration
#: share one set (about 25 MB at the defaults) for as long as any of them holds it.
_IN_MEMORY: weakref.WeakValueDictionary = weakref.WeakValueDictionary()


def _release_textures(textures: list) -> None:
    for tex in textures:
        tex.release()


def shared_tables(
    ctx,
    params: AtmosphereParams,
    config: PrecomputeConfig | None = None,
    *,
    progress: Callable[[str, float], None] | None = None,
) -> tuple[PrecomputedAtmosphere, bool]:
    """The tables of ``params`` and ``config`` on ``ctx``: the set already in GPU memory for
    another holder if there is one, else :func:`load_tables` (disk cache or precomputation).
    Returns (tables, not_computed_now). Their textures are released when the last holder
    drops them (a renderer that is released or garbage collected)."""
    config = config or PrecomputeConfig()
    key = (id(ctx), tables_key(params, config))
    tables = _IN_MEMORY.get(key)
    if tables is not None and tables.ctx is ctx:
        return tables, True
    tables, loaded = load_tables(ctx, params, config, progress=progress)
    _IN_MEMORY[key] = tables
    # The finalizer holds the textures, not the tables (which would then never be collected).
    weakref.finalize(tables, _release_textures, tables.gl_textures()).atexit = False
    return tables, loaded
