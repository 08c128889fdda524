"""The table cache: the LUT file format, its validation, keys from declared inputs, the
builder manifest, rebuilds of damaged entries (one warning, never a NaN, a traceback or a
hang) and temporary files of writers that died."""

from __future__ import annotations

import ast
import contextlib
import gc
import json
import os
import signal
import struct
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import skydome
from skydome.atmosphere import earth, preset
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.atmosphere.tables import TABLES_CACHE, load_tables, tables_key
from skydome.core.cache import (
    PACKAGE_ROOT,
    CacheSpec,
    CacheWarning,
    cache_dir,
    cache_max_bytes,
    cache_path,
    load_or_build,
    store,
    try_load,
)
from skydome.errors import CacheError
from skydome.io.lutfile import MAGIC, read_lut_file, write_lut_file
from tests.conftest import TINY_TABLES
from tests.tools_module import load_tool

ROOT = Path(__file__).resolve().parents[1]


def arrays():
    rng = np.random.default_rng(0)
    return {"a": rng.random((4, 5, 6)).astype(np.float32), "b": rng.random(7).astype(np.float16)}


def header_length(data: bytes) -> int:
    """Bytes of magic, length and JSON header at the start of a LUT file."""
    return len(MAGIC) + 8 + struct.unpack_from("<Q", data, len(MAGIC))[0]


@contextlib.contextmanager
def deadline(seconds: int):
    """Fail instead of hanging (a FIFO opened for reading waits for a writer forever)."""

    def expire(*_):
        raise TimeoutError(f"still running after {seconds} s")

    old = signal.signal(signal.SIGALRM, expire)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


@contextlib.contextmanager
def one_cache_warning():
    """Exactly one CacheWarning (and no other warning) inside the block."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield caught
    assert [w.category for w in caught] == [CacheWarning], [str(w.message) for w in caught]


# --------------------------------------------------------------------------- file format


def test_round_trip(tmp_path):
    p = write_lut_file(tmp_path / "t.lut", "k1", arrays(), {"note": "x"})
    got, meta = read_lut_file(p, "k1")
    for name, a in arrays().items():
        assert got[name].dtype == a.dtype and np.array_equal(got[name], a)
    assert meta == {"note": "x"}
    assert p.read_bytes()[: len(MAGIC)] == b"SKYDOMELUT\x00\x02"


@pytest.mark.parametrize(
    "damage", ["truncate", "flip", "garbage", "key", "empty", "trailing", "old-format"]
)
def test_damaged_files_are_rejected(tmp_path, damage):
    p = write_lut_file(tmp_path / "t.lut", "k1", arrays())
    data = bytearray(p.read_bytes())
    if damage == "truncate":
        p.write_bytes(data[: len(data) // 2])
    elif damage == "flip":
        data[-40] ^= 0xFF
        p.write_bytes(bytes(data))
    elif damage == "garbage":
        p.write_bytes(b"not a lut file at all")
    elif damage == "empty":
        p.write_bytes(b"")
    elif damage == "trailing":
        p.write_bytes(bytes(data) + b"\0")
    elif damage == "old-format":
        data[len(MAGIC) - 1] = 1
        p.write_bytes(bytes(data))
    with pytest.raises(CacheError):
        read_lut_file(p, "other" if damage == "key" else "k1")


def test_header_is_checked_even_when_the_checksum_holds(tmp_path):
    # A writer's bug (an offset off by one, an array past the payload) is caught by the
    # cross-checks, not only damage on disk: rewrite the header, then re-sign the file.
    import hashlib

    p = write_lut_file(tmp_path / "t.lut", "k1", arrays())
    data = p.read_bytes()
    n = header_length(data)
    header = json.loads(data[len(MAGIC) + 8 : n])
    for edit in ("offset", "shape", "dtype", "gap"):
        h = json.loads(json.dumps(header))
        e = h["arrays"][1]
        if edit == "offset":
            e["offset"] += 1
        elif edit == "shape":
            e["shape"] = [8]
        elif edit == "dtype":
            e["dtype"] = "object"
        else:
            h["arrays"] = h["arrays"][:1]
        blob = json.dumps(h).encode()
        body = MAGIC + struct.pack("<Q", len(blob)) + blob + data[n:-32]
        p.write_bytes(body + hashlib.sha256(body).digest())
        with pytest.raises(CacheError):
            read_lut_file(p, "k1")


@pytest.mark.parametrize("kind", ["fifo", "dev-zero", "directory", "link-to-file"])
def test_only_regular_files_are_read(tmp_path, kind):
    p = tmp_path / "t.lut"
    if kind == "fifo":
        os.mkfifo(p)
    elif kind == "dev-zero":
        p.symlink_to("/dev/zero")
    elif kind == "directory":
        p.mkdir()
    else:
        p.symlink_to(write_lut_file(tmp_path / "real.lut", "k1", arrays()))
    with deadline(5), pytest.raises(CacheError, match="not a table file"):
        read_lut_file(p, "k1")


# --------------------------------------------------------------------------- load_or_build


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
    with one_cache_warning() as caught:
        a, loaded = load_or_build("key-1", build, directory=tmp_path)
    assert "rebuilding" in str(caught[0].message) and str(path) in str(caught[0].message)
    assert not loaded and len(calls) == 2
    assert np.array_equal(a["a"], arrays()["a"])
    path.unlink()  # deleted: rebuilt silently
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _, loaded = load_or_build("key-1", build, directory=tmp_path)
    assert not loaded and len(calls) == 3
    # No temporary files are left behind.
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]


def test_arrays_a_product_cannot_use_are_rebuilt_once(tmp_path):
    # A sound file whose arrays the product rejects (decode raises: a wrong shape, a NaN) is
    # a fault of the entry like a damaged file: one warning, rebuilt, stored again.
    def decode(a):
        if a["a"].shape != (4, 5, 6):
            raise ValueError("wrong shape")
        return a

    store("key-2", {"a": np.zeros((2, 2), np.float32)}, directory=tmp_path)
    with one_cache_warning():
        got, loaded = load_or_build("key-2", arrays, directory=tmp_path, decode=decode)
    assert not loaded and got["a"].shape == (4, 5, 6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _, loaded = load_or_build("key-2", arrays, directory=tmp_path, decode=decode)
    assert loaded


# --------------------------------------------------------------------------- keys


def test_key_changes_with_every_declared_input(monkeypatch):
    spec = CacheSpec("demo", 1, ("common",), ())
    params = {"p": earth().to_dict(), "orders": 4}
    k = spec.key(params)
    assert k == CacheSpec("demo", 1, ("common",)).key({"orders": 4, "p": earth().to_dict()})
    assert k != spec.key({"p": earth().with_(mie_g=0.7).to_dict(), "orders": 4})
    assert k != spec.key({**params, "orders": 5})
    assert k != CacheSpec("demo", 2, ("common",)).key(params)
    assert k != CacheSpec("other", 1, ("common",)).key(params)
    assert k != CacheSpec("demo", 1, ("common", "clouds")).key(params)
    assert k == CacheSpec("demo", 1, ("common",), ("atmosphere/params.py",)).key(params)
    # Not the package version: a release that changes no table keeps the user's cache.
    monkeypatch.setattr(skydome, "__version__", "99.0")
    assert spec.key(params) == k
    # NumPy values are exact JSON; anything else is refused (a repr could elide or vary).
    assert spec.key({"x": np.float32(0.5), "y": np.arange(3)}) == spec.key(
        {"x": 0.5, "y": [0, 1, 2]}
    )
    with pytest.raises(TypeError, match="not JSON"):
        spec.key({"x": object()})


def test_cache_dir_from_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("SKYDOME_CACHE", str(tmp_path / "c"))
    assert cache_dir() == tmp_path / "c"
    monkeypatch.delenv("SKYDOME_CACHE")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "x"))
    assert cache_dir() == tmp_path / "x" / "skydome"


def test_cache_is_bounded_least_recently_used_first(tmp_path, monkeypatch):
    # Four entries of ~1 MiB each under a 2.5 MiB bound: a store removes the least recently
    # used (a load counts as a use), never the entry it has just written.
    entry = {"a": np.zeros(2**18, np.float32)}  # 1 MiB
    monkeypatch.setenv("SKYDOME_CACHE_MAX_MB", "2.5")
    for i, key in enumerate(("k1", "k2")):
        store(key, entry, directory=tmp_path)
        os.utime(cache_path(key, directory=tmp_path), (1000 + i, 1000 + i))
    assert try_load("k1", directory=tmp_path) is not None  # k1 now the most recently used
    store("k3", entry, directory=tmp_path)
    assert not cache_path("k2", directory=tmp_path).exists()
    assert cache_path("k1", directory=tmp_path).exists()
    assert cache_path("k3", directory=tmp_path).exists()
    # A bound below one entry keeps just the entry written.
    monkeypatch.setenv("SKYDOME_CACHE_MAX_MB", "0.5")
    store("k4", entry, directory=tmp_path)
    assert sorted(p.name for p in tmp_path.glob("*.lut")) == [
        cache_path("k4", directory=tmp_path).name
    ]


def test_cache_bound_from_environment(monkeypatch):
    monkeypatch.delenv("SKYDOME_CACHE_MAX_MB", raising=False)
    assert cache_max_bytes() == 2048 * 2**20
    monkeypatch.setenv("SKYDOME_CACHE_MAX_MB", "100")
    assert cache_max_bytes() == 100 * 2**20
    monkeypatch.setenv("SKYDOME_CACHE_MAX_MB", "lots")
    with pytest.warns(CacheWarning, match="SKYDOME_CACHE_MAX_MB"):
        assert cache_max_bytes() == 2048 * 2**20


def test_cache_file_names_stay_in_the_cache(tmp_path):
    assert cache_path("ab" * 32, "sky-../../x y", tmp_path).parent == tmp_path


def test_table_key_follows_the_shader_sources(tmp_path, monkeypatch):
    # Tables made by different GLSL must never be mistaken for each other: editing any shader
    # (here one appended comment) changes the key.
    import shutil

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


def test_core_computes_no_key_from_imports():
    # Keys come from declared inputs: no module of core/ walks imports or loads modules.
    for path in (PACKAGE_ROOT / "core").glob("*.py"):
        tree = ast.parse(path.read_text())
        names = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
        names |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
        assert not names & {"ast", "importlib", "importlib.util", "pkgutil"}, path.name


# --------------------------------------------------------------------------- the manifest


def manifest_tool():
    return load_tool("cache_manifest")


def test_builder_manifest_is_current():
    # Each cached product's builder files (Python and data) are recorded with its version in
    # tests/data/cache_builders.json. An edit of one that keeps the version fails here, with
    # the instruction to bump the version (so that users' cached results are rebuilt) and
    # refresh the manifest with `python tools/cache_manifest.py`.
    tool = manifest_tool()
    specs = tool.declared_specs()
    assert {"atmosphere-tables", "cloud-noise"} <= specs.keys()
    recorded = json.loads(tool.MANIFEST.read_text())
    problems = tool.problems(recorded, specs)
    assert not problems, "\n".join(problems)


def test_manifest_check_asks_for_a_version_bump():
    tool = manifest_tool()
    specs = {"demo": ("skydome.demo", CacheSpec("demo", 3, (), ("atmosphere/params.py",)))}
    current = tool.manifest(specs)
    assert tool.problems(current, specs) == []
    edited = json.loads(json.dumps(current))
    edited["demo"]["files"]["atmosphere/params.py"] = "0" * 64  # the file was edited since
    (msg,) = tool.problems(edited, specs)
    assert "atmosphere/params.py changed" in msg and "still version 3" in msg
    assert "bump its version in src/skydome/demo.py" in msg
    assert "python tools/cache_manifest.py" in msg
    edited["demo"]["version"] = 2  # bumped, manifest not refreshed
    (msg,) = tool.problems(edited, specs)
    assert "out of date" in msg and "python tools/cache_manifest.py" in msg
    edited["demo"]["version"] = 4
    (msg,) = tool.problems(edited, specs)
    assert "versions only go up" in msg
    (msg,) = tool.problems({}, specs)
    assert "not in the manifest" in msg


#: Modules a builder imports that do not shape what it computes: error messages, the GL
#: plumbing (contexts, the full-screen pass, #include expansion, texture helpers: they run
#: what the shaders say, and a change there that altered numbers would alter every frame,
#: which the render tests see), and the cache and its file format (whose own version is in
#: every key). Everything else a builder imports must be one of its builder files.
PLUMBING = {
    "errors.py",
    "core/cache.py",
    "io/atomic.py",
    "io/lutfile.py",
    "gpu/__init__.py",
    "gpu/context.py",
    "gpu/inputs.py",
    "gpu/passes.py",
    "gpu/shaders.py",
    "gpu/textures.py",
}


def _imports(path: Path) -> set[str]:
    """The skydome modules a source file imports (any depth, function-level too); for
    ``from skydome.x import y`` also ``skydome.x.y`` (y may be a submodule)."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names if a.name.startswith("skydome.")}
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("skydome."):
            out |= {node.module} | {f"{node.module}.{a.name}" for a in node.names}
    return out


def _module_path(module: str) -> str | None:
    parts = module.split(".")[1:]
    for rel in ("/".join(parts) + ".py", "/".join([*parts, "__init__.py"])):
        if (PACKAGE_ROOT / rel).is_file():
            return rel
    return None


def test_builders_declare_the_code_and_data_they_depend_on():
    # Every module reachable by imports from the module that declares a spec (not through the
    # parents' __init__: `skydome/__init__` would pull in the whole package) is one of its
    # builder files or plumbing (above); every data file a builder file names is declared;
    # every declared file and shader folder exists.
    for name, (module, spec) in manifest_tool().declared_specs().items():
        files = set(spec.builder_files)
        reached, todo = set(), [module]
        while todo:
            rel = _module_path(todo.pop())
            if rel is not None and rel not in reached:
                reached.add(rel)
                todo.extend(_imports(PACKAGE_ROOT / rel))
        assert reached - PLUMBING <= files, (
            f"{name}: undeclared {sorted(reached - PLUMBING - files)}"
        )
        text = "\n".join((PACKAGE_ROOT / f).read_text() for f in files if f.endswith(".py"))
        named = {f"data/{p.name}" for p in (PACKAGE_ROOT / "data").iterdir() if p.name in text}
        assert named <= files, f"{name}: undeclared data {sorted(named - files)}"
        assert all((PACKAGE_ROOT / f).is_file() for f in files), name
        assert all((PACKAGE_ROOT / "shaders" / d).is_dir() for d in spec.shader_folders), name
    # The ones the tables must have (the list): the precomputation and its encoding,
    # the config, the transmittance pass, the shaders' uniforms, the parameters, the spectral
    # conversion and its CIE and solar data.
    assert {
        "atmosphere/tables.py",
        "atmosphere/precompute.py",
        "atmosphere/precompute_config.py",
        "atmosphere/transmittance.py",
        "atmosphere/inputs.py",
        "atmosphere/params.py",
        "spectra/colour.py",
        "data/cie1931_2deg_cmf_5nm.csv",
        "data/solar_ozone_10nm.csv",
    } <= set(TABLES_CACHE.builder_files)


# --------------------------------------------------------------------------- damaged entries


@pytest.fixture(scope="module")
def tiny(ctx, tmp_path_factory):
    """TINY_TABLES of `earth`: the cache file's bytes and the fresh tables' arrays."""
    directory = tmp_path_factory.mktemp("tiny-cache")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("SKYDOME_CACHE", str(directory))
        tables, loaded = load_tables(ctx, preset("earth"), TINY_TABLES)
    assert not loaded
    (path,) = directory.glob("*.lut")
    out = {"bytes": path.read_bytes(), "arrays": tables.to_arrays(), "name": path.name}
    tables.release()
    return out


def test_every_header_byte_is_checked(ctx, tiny, tmp_path, monkeypatch):
    # One byte of the header changed, every byte in turn (magic, length, JSON: offsets,
    # shapes, dtypes, the key) and every byte of the checksum: the load warns once, the
    # tables are rebuilt (here by a stand-in that counts calls and returns fresh tables: the
    # real precomputation is checked below) and stored again, byte for byte as before.
    from skydome.atmosphere import tables as tables_module
    from skydome.io import atomic

    monkeypatch.setenv("SKYDOME_CACHE", str(tmp_path))
    fresh = tables_module.PrecomputedAtmosphere.from_arrays(
        ctx, preset("earth"), TINY_TABLES, tiny["arrays"]
    )
    built = []
    monkeypatch.setattr(tables_module, "precompute", lambda *a, **k: built.append(1) or fresh)
    monkeypatch.setattr(atomic, "_fsync", lambda path: None)  # 790 flushes to disk: not tested
    data, path = tiny["bytes"], tmp_path / tiny["name"]
    positions = [*range(header_length(data)), *range(len(data) - 32, len(data))]
    path.write_bytes(data)
    t0 = time.perf_counter()
    for i in positions:
        with open(path, "r+b") as f:  # the file is whole again after each rebuild
            f.seek(i)
            f.write(bytes([data[i] ^ (0x20 if 0x21 <= data[i] <= 0x7E else 0xFF)]))
        with one_cache_warning():
            _, loaded = load_tables(ctx, preset("earth"), TINY_TABLES)
        assert not loaded and len(built) == 1, i
        built.clear()
        assert path.read_bytes() == data, f"byte {i}: not rebuilt as before"
    per_byte = (time.perf_counter() - t0) / len(positions)
    print(f"{len(positions)} bytes, {per_byte * 1e3:.1f} ms each")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _, loaded = load_tables(ctx, preset("earth"), TINY_TABLES)
    assert loaded
    fresh.release()


@pytest.mark.parametrize("field", ["magic", "length", "offset", "shape", "dtype", "key"])
def test_header_damage_rebuilds_equal_tables(ctx, tiny, tmp_path, monkeypatch, field):
    monkeypatch.setenv("SKYDOME_CACHE", str(tmp_path))
    data = bytearray(tiny["bytes"])
    n = header_length(data)
    header = bytes(data[:n])
    i = {
        "magic": 3,
        "length": len(MAGIC),
        "offset": header.index(b'"offset": 12288') + len('"offset": 1'),  # 12288 -> 13288
        "shape": header.index(b'"shape": [8, 32') + len('"shape": ['),  # 8 -> 9
        "dtype": header.index(b'"float16"') + len('"float'),  # float16 -> float26
        "key": header.index(b'"key": "') + 10,
    }[field]
    data[i] = data[i] + 1 if field != "length" else data[i] ^ 0x01
    (tmp_path / tiny["name"]).write_bytes(bytes(data))
    with one_cache_warning():
        tables, loaded = load_tables(ctx, preset("earth"), TINY_TABLES)
    assert not loaded
    for name, a in tiny["arrays"].items():
        assert np.array_equal(tables.to_arrays()[name], a), name
    assert (tmp_path / tiny["name"]).read_bytes() == tiny["bytes"]
    tables.release()


def test_damaged_header_through_the_sky(tiny, tmp_path, monkeypatch):
    # The user's path: the offset of `scattering` one higher in the header (which gave frames
    # half NaN before the header was checksummed) is rebuilt with one warning, and the frame
    # equals the one of fresh tables, finite.
    import weakref

    from skydome.atmosphere import tables as tables_module

    monkeypatch.setenv("SKYDOME_CACHE", str(tmp_path))
    # Tables other tests hold in memory must not stand in for the disk.
    monkeypatch.setattr(tables_module, "_IN_MEMORY", weakref.WeakValueDictionary())

    def frame():
        with skydome.Sky(sun_elevation_deg=10, config=TINY_TABLES) as sky:
            out = sky.render(skydome.PerspectiveCamera(), 64, 32, exposure=None).data
        gc.collect()  # the tables leave memory with their last holder: the next Sky loads
        return out

    fresh = frame()  # computed and stored
    path = tmp_path / tiny["name"]
    assert path.read_bytes() == tiny["bytes"]
    data = bytearray(tiny["bytes"])
    data[data.index(b'"offset": 12288') + len('"offset": 1')] += 1
    path.write_bytes(bytes(data))
    with one_cache_warning():
        again = frame()
    assert np.all(np.isfinite(again)) and np.array_equal(again, fresh)
    assert path.read_bytes() == tiny["bytes"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.array_equal(frame(), fresh)  # now loaded, silently


@pytest.mark.parametrize(
    "kind", ["fifo", "dev-zero", "directory", "full-directory", "empty", "truncated"]
)
def test_what_is_not_a_cache_file_is_replaced(ctx, tiny, tmp_path, monkeypatch, kind):
    # Whatever stands at the cache file's path: one warning, the entry replaced by rebuilt
    # tables, no more than 2 s beyond a plain build, never a hang.
    monkeypatch.setenv("SKYDOME_CACHE", str(tmp_path))
    path = tmp_path / tiny["name"]
    t0 = time.perf_counter()
    tables, _ = load_tables(ctx, preset("earth"), TINY_TABLES)  # a plain build (no file)
    plain = time.perf_counter() - t0
    tables.release()
    path.unlink()
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "dev-zero":
        path.symlink_to("/dev/zero")
    elif kind == "directory":
        path.mkdir()
    elif kind == "full-directory":
        path.mkdir()
        (path / "x").write_bytes(b"x")
    elif kind == "empty":
        path.write_bytes(b"")
    else:
        path.write_bytes(tiny["bytes"][: len(tiny["bytes"]) // 3])
    t0 = time.perf_counter()
    with deadline(60), one_cache_warning():
        tables, loaded = load_tables(ctx, preset("earth"), TINY_TABLES)
    extra = time.perf_counter() - t0 - plain
    print(f"{kind}: {extra * 1e3:+.0f} ms beyond a plain build of {plain * 1e3:.0f} ms")
    assert not loaded and extra < 2.0
    assert path.is_file() and not path.is_symlink() and path.read_bytes() == tiny["bytes"]
    for name, a in tiny["arrays"].items():
        assert np.array_equal(tables.to_arrays()[name], a), name
    tables.release()


def test_cloud_noise_of_the_wrong_layout_is_rebuilt(ctx, tmp_path, monkeypatch):
    # The other cached product: a sound file of its key holding arrays of the wrong shape.
    from skydome.clouds.noise import cloud_noise, noise_key

    monkeypatch.setenv("SKYDOME_CACHE", str(tmp_path))
    sizes = {"shape_size": 8, "detail_size": 4, "curl_size": 4}
    store(noise_key(7, 8, 4, 4), {"shape": np.zeros(3, np.float32)}, name="cloud-noise")
    with one_cache_warning():
        noise = cloud_noise(ctx, 7, **sizes)
    assert not noise.from_cache
    noise.release()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        again = cloud_noise(ctx, 7, **sizes)
    assert again.from_cache
    again.release()


def test_cli_warns_in_one_line_and_rebuilds(tmp_path):
    # A real process on a FIFO in place of the default tables: one warning line, a frame.
    cache = tmp_path / "cache"
    cache.mkdir()
    os.mkfifo(cache_path(tables_key(preset("earth"), PrecomputeConfig()), "sky-earth", cache))
    env = {**os.environ, "SKYDOME_CACHE": str(cache)}
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src"), env.get("PYTHONPATH", "")])
    cmd = [sys.executable, "-m", "skydome", "render", "--sun-elevation", "10", "--size", "32x16"]
    res = subprocess.run(
        [*cmd, "-o", "out.png"], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300
    )
    assert res.returncode == 0, res.stderr
    lines = res.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("skydome: warning: rebuilding cached tables: ")
    assert "FIFO" in lines[0] and "Traceback" not in res.stderr
    assert (tmp_path / "out.png").stat().st_size > 0
    (lut,) = cache.iterdir()
    assert lut.is_file() and read_lut_file(lut)[0]


# --------------------------------------------------------------------------- interrupted writes


def test_a_killed_writer_leaves_nothing_the_next_run_keeps(tmp_path):
    # A process killed in the middle of a store (after writing, before the rename) leaves its
    # temporary file; the next load removes it, as its writer is gone.
    script = (
        "import os, signal, numpy as np\n"
        "import skydome.io.atomic as atomic\n"
        "from skydome.core.cache import store\n"
        "atomic._fsync = lambda p: os.kill(os.getpid(), signal.SIGKILL)\n"
        f"store('key-3', {{'a': np.zeros(1000, np.float32)}}, directory={str(tmp_path)!r})\n"
    )
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    res = subprocess.run([sys.executable, "-c", script], env=env, timeout=120)
    assert res.returncode == -signal.SIGKILL
    (left,) = tmp_path.iterdir()
    assert left.name.startswith(".tables-key-3") and ".tmp.lut" in left.name
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert try_load("key-3", directory=tmp_path) is None  # nothing usable, no warning
    assert not list(tmp_path.iterdir())


def test_stale_temporary_files_are_removed(tmp_path):
    # Removed: a writer that died, or one silent for over a minute. Kept: a live writer's,
    # and any file that is not a cache temporary file.
    me = os.getpid()
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True
    )
    dead_pid = int(dead.stdout)
    names = {
        "dead": f".sky-earth-ab.skydome-{dead_pid}-0123abcd.tmp.lut",
        "old": f".sky-earth-ab.skydome-{me}-0123abce.tmp.lut",
        "live": f".sky-earth-ab.skydome-{me}-0123abcf.tmp.lut",
        "png": f".frame.skydome-{dead_pid}-0123abcd.tmp.png",
        "other": "notes.txt",
    }
    for n in names.values():
        (tmp_path / n).write_bytes(b"x")
    hour_ago = time.time() - 3600
    os.utime(tmp_path / names["old"], (hour_ago, hour_ago))
    store("key-4", arrays(), directory=tmp_path)
    left = {p.name for p in tmp_path.iterdir()}
    assert left == {names["live"], names["png"], names["other"], cache_path("key-4").name}
