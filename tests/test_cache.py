"""LUT file format and cache: validation, atomic writes, rebuild on damage, keys."""

import numpy as np
import pytest

from skydome.atmosphere import earth
from skydome.core.cache import CacheWarning, cache_dir, cache_key, load_or_build
from skydome.errors import CacheError
from skydome.io.lutfile import read_lut_file, write_lut_file


def arrays():
    rng = np.random.default_rng(0)
    return {"a": rng.random((4, 5, 6)).astype(np.float32), "b": rng.random(7).astype(np.float16)}


def test_round_trip(tmp_path):
    p = write_lut_file(tmp_path / "t.lut", "k1", arrays(), {"note": "x"})
    got, meta = read_lut_file(p, "k1")
    for name, a in arrays().items():
        assert got[name].dtype == a.dtype and np.array_equal(got[name], a)
    assert meta == {"note": "x"}


@pytest.mark.parametrize("damage", ["truncate", "flip", "garbage", "key"])
def test_damaged_files_are_rejected(tmp_path, damage):
    p = write_lut_file(tmp_path / "t.lut", "k1", arrays())
    data = bytearray(p.read_bytes())
    if damage == "truncate":
        p.write_bytes(data[: len(data) // 2])
    elif damage == "flip":
        data[-3] ^= 0xFF
        p.write_bytes(bytes(data))
    elif damage == "garbage":
        p.write_bytes(b"not a lut file at all")
    with pytest.raises(CacheError):
        read_lut_file(p, "other" if damage == "key" else "k1")


def test_load_or_build_rebuilds_damaged_and_reuses_valid(tmp_path):
    calls = []

    def build():
        calls.append(1)
        return arrays()

    a, loaded = load_or_build("key-1", build, directory=tmp_path)
    assert not loaded and len(calls) == 1
    a, loaded = load_or_build("key-1", build, directory=tmp_path)
    assert loaded and len(calls) == 1  # second call loads
    (path,) = tmp_path.glob("*.lut")
    path.write_bytes(path.read_bytes()[:100])  # truncate
    with pytest.warns(CacheWarning, match="rebuilding"):
        a, loaded = load_or_build("key-1", build, directory=tmp_path)
    assert not loaded and len(calls) == 2
    assert np.array_equal(a["a"], arrays()["a"])
    path.unlink()  # deleted: rebuilt silently
    _, loaded = load_or_build("key-1", build, directory=tmp_path)
    assert not loaded and len(calls) == 3
    # No temporary files are left behind.
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]


def test_key_changes_with_every_parameter():
    p = earth()
    k = cache_key(p.to_dict(), {"orders": 4})
    assert k == cache_key(earth().to_dict(), {"orders": 4})
    assert k != cache_key(p.with_(mie_g=0.7).to_dict(), {"orders": 4})
    assert k != cache_key(p.to_dict(), {"orders": 5})


def test_cache_dir_from_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("SKYDOME_CACHE", str(tmp_path / "c"))
    assert cache_dir() == tmp_path / "c"
    monkeypatch.delenv("SKYDOME_CACHE")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "x"))
    assert cache_dir() == tmp_path / "x" / "skydome"


def test_table_key_follows_the_shader_sources(tmp_path, monkeypatch):
    # Tables made by different GLSL must never be mistaken for each other: editing any shader
    # (here one appended comment) changes the key.
    import shutil

    from skydome.atmosphere.precompute_config import PrecomputeConfig
    from skydome.atmosphere.tables import tables_key
    from skydome.gpu import shaders

    before = tables_key(earth(), PrecomputeConfig())
    copy = tmp_path / "shaders"
    shutil.copytree(shaders.SHADER_DIR, copy)
    with open(copy / "atmosphere/precompute_ray.glsl", "a") as f:
        f.write("// edited\n")
    monkeypatch.setattr(shaders, "SHADER_DIR", copy)
    shaders.sources_digest.cache_clear()
    try:
        assert tables_key(earth(), PrecomputeConfig()) != before
    finally:
        monkeypatch.undo()
        shaders.sources_digest.cache_clear()
    assert tables_key(earth(), PrecomputeConfig()) == before


def test_table_code_files_cover_what_shapes_the_tables():
    # The files behind the key are found from the imports, so a new module cannot be missed;
    # these are the ones the issue names: the ln L interpolation (precompute.py), the
    # conversion matrix (spectra) with its CIE data, and the table file encoding (lutfile.py).
    from skydome.core.cache import PACKAGE_ROOT, code_files

    names = {
        p.relative_to(PACKAGE_ROOT).as_posix() for p in code_files("skydome.atmosphere.tables")
    }
    assert {
        "atmosphere/precompute.py",
        "atmosphere/precompute_config.py",
        "spectra/colour.py",
        "data/cie1931_2deg_cmf_5nm.csv",
        "data/solar_ozone_10nm.csv",
        "io/lutfile.py",
    } <= names
    # Not the astronomy, the renderers or the tests' oracles: editing them keeps the tables.
    assert not any(n.startswith(("astro/", "render/", "cli/")) for n in names)
    assert "reference/ms.py" not in names


@pytest.mark.parametrize(
    "edited", ["atmosphere/precompute.py", "spectra/colour.py", "data/cie1931_2deg_cmf_5nm.csv"]
)
def test_table_key_follows_the_python_code_and_data(tmp_path, monkeypatch, edited):
    # An edited installation (the ln L interpolation, the spectral conversion, its CIE data)
    # must never reuse tables made by the old code: one appended byte changes the key.
    import shutil

    from skydome.atmosphere import cache, tables
    from skydome.atmosphere.precompute_config import PrecomputeConfig

    before = tables.tables_key(earth(), PrecomputeConfig())
    copy = tmp_path / "skydome"
    shutil.copytree(cache.PACKAGE_ROOT, copy, ignore=shutil.ignore_patterns("__pycache__"))
    with open(copy / edited, "a") as f:
        f.write("\n")
    monkeypatch.setattr(cache, "PACKAGE_ROOT", copy)
    cache.code_digest.cache_clear()
    try:
        assert tables.tables_key(earth(), PrecomputeConfig()) != before
    finally:
        monkeypatch.undo()
        cache.code_digest.cache_clear()
    assert tables.tables_key(earth(), PrecomputeConfig()) == before
