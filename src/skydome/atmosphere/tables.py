"""Precomputed tables of an atmosphere, loaded from the disk cache or computed and stored."""

from __future__ import annotations

import weakref
from collections.abc import Callable

from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.precompute import PrecomputedAtmosphere, precompute
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.core.cache import CacheSpec, load_or_build

#: What the tables depend on besides the parameters and the config. They are made by
#: shaders/atmosphere/ with includes from shaders/common/ only (night-sky, celestial and
#: display shaders do not invalidate them). The Python and data behind them: this module, the
#: precomputation and its table encoding (precompute.py), the config and its wavelength grids
#: (precompute_config.py, spectra/grids.py), the transmittance pass (transmittance.py), the
#: uniforms and defines given to the shaders (inputs.py), the parameters' derived values and
#: phase lobes (params.py, phase.py), the spectral-to-RGB conversion (spectra/colour.py,
#: spectra/tables.py, spectra/__init__.py) and the CIE, solar and surface tables it reads. Bump
#: ``version`` when an edit of one of them changes the tables (tests/test_cache.py checks).
TABLES_CACHE = CacheSpec(
    name="atmosphere-tables",
    version=6,
    shader_folders=("atmosphere", "common"),
    builder_files=(
        "atmosphere/tables.py",
        "atmosphere/precompute.py",
        "atmosphere/precompute_config.py",
        "atmosphere/transmittance.py",
        "atmosphere/inputs.py",
        "physics/constants.py",
        "physics/droplets.py",
        "physics/geometry.py",
        "physics/packing.py",
        "physics/phase.py",
        "atmosphere/params.py",
        "atmosphere/phase.py",
        "spectra/__init__.py",
        "spectra/colour.py",
        "spectra/grids.py",
        "spectra/tables.py",
        "data/cie1931_2deg_cmf_5nm.csv",
        "data/cie_luminous_efficiency_5nm.csv",
        "data/solar_ozone_10nm.csv",
        "data/surface_albedo_igbp.csv",
    ),
)


def tables_key(params: AtmosphereParams, config: PrecomputeConfig) -> str:
    """Cache key of the tables: every parameter and config field (``TABLES_CACHE`` adds the
    shader sources and the version of the code behind them)."""
    return TABLES_CACHE.key({"atmosphere": params.to_dict(), "config": config.key()})


def load_tables(
    ctx,
    params: AtmosphereParams,
    config: PrecomputeConfig | None = None,
    *,
    cache: bool = True,
    progress: Callable[[str, float], None] | None = None,
) -> tuple[PrecomputedAtmosphere, bool]:
    """The precomputed tables of ``params``: from the disk cache when valid, else computed
    (and stored). Returns (tables, loaded_from_cache). A cache file that cannot be used
    (damaged, or holding arrays that do not fit) is rebuilt with one CacheWarning."""
    config = config or PrecomputeConfig()

    def build() -> PrecomputedAtmosphere:
        return precompute(ctx, params, config, progress=progress)

    if not cache:
        return build(), False
    return load_or_build(
        tables_key(params, config),
        build,
        name=f"sky-{params.name}",
        meta={"atmosphere": params.name},
        decode=lambda arrays: PrecomputedAtmosphere.from_arrays(ctx, params, config, arrays),
        encode=PrecomputedAtmosphere.to_arrays,
    )


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
