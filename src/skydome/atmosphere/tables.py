"""Precomputed tables of an atmosphere, loaded from the disk cache or computed and stored."""

from __future__ import annotations

import warnings
from collections.abc import Callable

from skydome.atmosphere.cache import CacheWarning, cache_key, code_digest, store, try_load
from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.precompute import PrecomputedAtmosphere, precompute
from skydome.atmosphere.precompute_config import PrecomputeConfig
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
        sources_digest(),
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
