"""The command line: outputs, messages and exit status for bad input."""

import os
import warnings

import numpy as np
import pytest
from PIL import Image

from skydome.io import read_exr
from tests.cli_helpers import run_cli


def run(*args, cwd=None, env=None):
    # In this process (the console script's own entry point): a subprocess per case costs
    # seconds of Python and NumPy start-up. test_cli.py keeps a few real subprocesses.
    return run_cli(*args, cwd=cwd, env=env)


def test_info():
    res = run("info")
    assert res.returncode == 0, res.stderr
    assert (
        "OpenGL renderer" in res.stdout
        and "software" in res.stdout
        and "skydome 0.1.0" in res.stdout
    )


def test_render_png_and_exr(tmp_path):
    png, exr = tmp_path / "sky.png", tmp_path / "sky.exr"
    res = run(
        "render",
        "--sun-elevation",
        "20",
        "--size",
        "96x48",
        "--spectral",
        "fast",
        "-o",
        str(png),
        "-o",
        str(exr),
    )
    assert res.returncode == 0, res.stderr
    assert str(png) in res.stdout and "ms" in res.stdout
    img = np.asarray(Image.open(png))
    assert img.shape == (48, 96, 3) and img.std() > 5  # an image, not a flat frame
    data, header = read_exr(exr)
    assert data.shape == (48, 96, 4) and np.all(np.isfinite(data))
    # Absolute units: a clear daytime sky is hundreds to tens of thousands of cd/m^2.
    lum = data[:24, :, :3] @ np.array([0.2126, 0.7152, 0.0722])
    assert 100 < np.median(lum) < 50_000


def test_render_supersample(tmp_path):
    # n x n rays a pixel, their mean: the frame at the asked size, the same sky (the mean
    # luminance of a clear sky is smooth at this scale: within 1 %); a bad n writes nothing.
    one, two = tmp_path / "one.npy", tmp_path / "two.npy"
    common = ("render", "--sun-elevation", "20", "--size", "48x24", "--spectral", "fast")
    assert run(*common, "-o", str(one)).returncode == 0
    res = run(*common, "--supersample", "2", "-o", str(two))
    assert res.returncode == 0, res.stderr
    a, b = np.load(one), np.load(two)
    assert b.shape == (24, 48, 4)
    assert b[..., :3].mean() == pytest.approx(a[..., :3].mean(), rel=0.01)
    bad = tmp_path / "bad.png"
    res = run(*common, "--supersample", "5", "-o", str(bad))
    assert res.returncode == 2 and not bad.exists()
    assert res.stderr.strip().count("\n") == 0 and "--supersample 5" in res.stderr


def test_equirect_and_cubemap_sizes(tmp_path):
    out = tmp_path / "env.npy"
    assert (
        run(
            "render",
            "--camera",
            "equirect",
            "--size",
            "64x32",
            "--spectral",
            "fast",
            "-o",
            str(out),
        ).returncode
        == 0
    )
    assert np.load(out).shape == (32, 64, 4)
    assert (
        run(
            "render", "--camera", "cubemap", "--size", "16x16", "--spectral", "fast", "-o", str(out)
        ).returncode
        == 0
    )
    assert np.load(out).shape == (16, 96, 4)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--sun-elevation", "95"], "--sun-elevation"),
        (["--atmosphere", "venus"], "unknown atmosphere preset"),
        (["--size", "0x10"], "--size"),
        (["--size", "100000x100000"], "--size"),
        (["--size", "big"], "--size"),
        (["--camera", "pinhole"], "unknown camera"),
        (["--tonemap", "magic"], "unknown tone map"),
        (["--exposure", "bright"], "--exposure"),
        (["-o", "OUT/x.tif"], "extension"),
        (["-o", "/nonexistent_dir_xyz/x.png"], "does not exist"),
    ],
)
def test_bad_input_one_line_exit_2_nothing_written(tmp_path, args, message):
    args = [a.replace("OUT", str(tmp_path)) for a in args]
    if "-o" not in args:
        args += ["-o", str(tmp_path / "sky.png")]
    res = run("render", *args, cwd=tmp_path)
    assert res.returncode == 2
    lines = [ln for ln in res.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and message in lines[0], res.stderr
    assert "Traceback" not in res.stderr
    assert list(tmp_path.iterdir()) == []


def only_error_line(res) -> str:
    """The one stderr line of a refused command (exit status 2, no traceback)."""
    lines = [ln for ln in res.stderr.splitlines() if ln.strip()]
    assert res.returncode == 2 and len(lines) == 1, res.stderr
    assert lines[0].startswith("skydome: error: ")
    return lines[0]


@pytest.mark.parametrize(
    "args, flag, shown",
    [
        # Unknown names: the flag, the value and the choices as plain words (the presets in
        # their PRESETS order: the measured Earths, then the seeds' two Earths and Mars).
        (
            ["--atmosphere", "nope"],
            "--atmosphere",
            "earth, typical, hazy, urban, maritime, desert, earth_bruneton, earth_nishita, mars",
        ),
        (["--camera", "nope"], "--camera", "perspective, fisheye, equirect, cubemap"),
        (["--tonemap", "nope"], "--tonemap", "filmic"),
        (["--spectral", "nope"], "--spectral", "fast, accurate"),
        (["--model", "nope"], "--model", "precomputed, single"),
        # Out-of-range numbers: the flag (not the library's fov_deg), the range in words.
        (["--size", "0x0"], "--size", "1 to 16384 pixels"),
        (["--fov", "500"], "--fov", "0.01 to 179 deg"),
        (["--pitch", "100"], "--pitch", "-90 to 90 deg"),
        (["--yaw", "1000"], "--yaw", "-360 to 360 deg"),
        (["--roll", "-999"], "--roll", "-360 to 360 deg"),
        (["--altitude", "-5"], "--altitude", "0 to 1e+08 m"),
        (["--orders", "0"], "--orders", "1 to 20"),
        (["--model", "single", "--samples", "0"], "--samples", "1 to 4096"),
        (["--exposure", "bright"], "--exposure", "auto or an EV100 number"),
        # --samples does not apply to the precomputed model: refused, not ignored.
        (["--samples", "64"], "--samples", "only to --model single"),
        (["--model", "precomputed", "--samples", "16"], "--samples", "--model single"),
        # Usage errors too are one line.
        (["--fov", "wide"], "--fov", "render --help"),
        (["--no-such-flag"], "--no-such-flag", "render --help"),
    ],
)
def test_errors_name_the_flag_in_plain_words(tmp_path, args, flag, shown):
    res = run("render", *args, "-o", str(tmp_path / "sky.png"), cwd=tmp_path)
    line = only_error_line(res)
    assert flag in line and shown in line, line
    if "help" not in shown:  # (Click's own usage messages quote the option)
        # No Python syntax: no ['a', 'b'] lists, no quoted values, no [lo, hi] intervals.
        assert not any(ch in line for ch in "[]'\""), line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "args, flag",
    [
        (["precompute", "--atmosphere", "nope"], "--atmosphere"),
        (["precompute", "--spectral", "nope"], "--spectral"),
        (["precompute", "--orders", "21"], "--orders"),
        (["illuminance", "--sun-elevation", "10", "--atmosphere", "nope"], "--atmosphere"),
    ],
)
def test_other_commands_name_the_flag(tmp_path, args, flag):
    line = only_error_line(run(*args, cwd=tmp_path))
    assert flag in line and not any(ch in line for ch in "[]'"), line
    assert list(tmp_path.iterdir()) == []


def test_version():
    import skydome

    res = run("--version")
    assert res.returncode == 0 and res.stdout.strip() == f"skydome {skydome.__version__}"
    assert res.stderr == ""


def test_help_says_where_samples_apply():
    res = run("render", "--help")
    assert res.returncode == 0
    text = " ".join(res.stdout.replace("│", " ").split())
    assert "--samples" in text and "--model single only" in text


def test_samples_with_the_single_model_renders(tmp_path):
    out = tmp_path / "s.npy"
    res = run(
        "render", "--model", "single", "--samples", "8", "--size", "8x4", "--spectral", "fast",
        "-o", str(out),
    )  # fmt: skip
    assert res.returncode == 0, res.stderr
    frame = np.load(out)
    # A daytime sky in cd/m^2 (as in test_render_png_and_exr): hundreds to tens of thousands.
    assert frame.shape == (4, 8, 4) and 100 < np.median(frame[:2, :, 1]) < 50_000


def test_hdr_and_jpg_outputs(tmp_path):
    hdr, jpg, exr = tmp_path / "sky.hdr", tmp_path / "sky.jpg", tmp_path / "sky.exr"
    res = run(
        "render", "--size", "32x16", "--spectral", "fast",
        "-o", str(hdr), "-o", str(jpg), "-o", str(exr),
    )  # fmt: skip
    assert res.returncode == 0, res.stderr
    from skydome.io import read_hdr

    rgb, header = read_hdr(hdr)
    data, _ = read_exr(exr)
    # The same frame: RGBE keeps every channel within 1/256 of the pixel's largest one.
    err = np.abs(rgb - np.maximum(data[..., :3], 0)).max(axis=-1)
    assert np.all(err <= (2.0**-8 + 2.0**-20) * data[..., :3].max(axis=-1))
    assert '"tonemap":"filmic"' in header["SKYDOME_SETTINGS"]
    with Image.open(jpg) as im:
        assert im.format == "JPEG" and im.size == (32, 16) and np.asarray(im).std() > 2


def test_cache_warning_is_one_line(tmp_path):
    """A damaged cache file is rebuilt with one 'skydome: warning:' line, no source line."""
    env = {**os.environ, "SKYDOME_CACHE": str(tmp_path / "cache")}
    args = ("precompute", "--spectral", "fast", "--orders", "1")
    first = run(*args, env=env)
    assert first.returncode == 0 and first.stderr == "", first.stderr
    (path,) = (tmp_path / "cache").glob("*.lut")
    path.write_bytes(path.read_bytes()[:100])  # truncated, as in test_cache.py
    res = run(*args, env=env)
    assert res.returncode == 0, res.stderr
    lines = res.stderr.splitlines()
    assert len(lines) == 1, res.stderr
    assert lines[0].startswith("skydome: warning: rebuilding cached tables: ")
    assert str(path) in lines[0] and "CacheWarning" not in lines[0]
    assert "computed" in res.stdout  # and it was rebuilt


def test_only_skydome_warnings_are_shown_as_one_line(capsys):
    from skydome.cli.main import show_warning
    from skydome.errors import SkydomeWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (the import below must not warn)
        from skydome.core.cache import CacheWarning
    assert issubclass(CacheWarning, SkydomeWarning)
    show_warning(CacheWarning("rebuilding\ncached tables"), CacheWarning, "/x/mod.py", 7)
    assert capsys.readouterr().err == "skydome: warning: rebuilding cached tables\n"
    for category in (UserWarning, RuntimeWarning, DeprecationWarning):
        show_warning(category("from another library"), category, "/x/mod.py", 7)
    assert capsys.readouterr().err == ""


def test_warnings_while_a_command_runs(monkeypatch):
    """Through the CLI: NumPy's RuntimeWarning, Pillow's and any other library's warning
    print nothing; skydome's own warning prints one line; the command succeeds."""
    from PIL import Image

    import skydome.astro.places as places
    from skydome.errors import SkydomeWarning

    search = places.search

    def noisy_search(query, limit):
        with np.errstate(divide="warn", invalid="warn"):
            np.log(np.zeros(3)) - np.log(np.zeros(3))  # divide by zero, invalid value
        warnings.warn("Image size exceeds limit", Image.DecompressionBombWarning, stacklevel=1)
        warnings.warn("some library\nsays this", UserWarning, stacklevel=1)
        warnings.warn("a skydome warning\non two lines", SkydomeWarning, stacklevel=1)
        return search(query, limit)

    monkeypatch.setattr(places, "search", noisy_search)
    with warnings.catch_warnings():
        warnings.simplefilter("always")  # shown every time, not once per place
        res = run("places", "paranal")
    assert res.returncode == 0 and "Paranal" in res.stdout
    assert res.stderr == "skydome: warning: a skydome warning on two lines\n"


@pytest.mark.parametrize(
    ("target", "needles"),
    [
        ("tables.txt", ["extension '.txt'", "valid: .lut"]),
        ("missing/tables.lut", ["does not exist"]),
        ("dir.lut", ["it is a directory"]),
        ("fifo.lut", ["it is a FIFO (named pipe), not a regular file"]),
        ("/sys/tables.lut", ["not writable"]),  # not even root can create files in sysfs
    ],
)
def test_precompute_checks_its_output_before_it_computes(tmp_path, target, needles):
    import time

    (tmp_path / "dir.lut").mkdir()
    os.mkfifo(tmp_path / "fifo.lut")
    cache = tmp_path / "cache"
    env = {**os.environ, "SKYDOME_CACHE": str(cache)}
    out = target if target.startswith("/") else str(tmp_path / target)
    t0 = time.perf_counter()
    res = run("precompute", "--spectral", "fast", "--orders", "1", "-o", out, env=env)
    seconds = time.perf_counter() - t0
    lines = res.stderr.splitlines()
    assert res.returncode == 2 and len(lines) == 1, res.stderr
    assert lines[0].startswith("skydome: error: cannot write")
    for needle in needles:
        assert needle in lines[0], lines[0]
    assert not cache.exists() or not list(cache.iterdir())  # nothing was computed
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dir.lut", "fifo.lut"]
    assert seconds < 1.0, seconds  # (the tables take seconds)


def test_a_real_process(tmp_path):
    # The in-process runner above calls the same entry point; this checks the process itself:
    # `python -m skydome` exits 0 for --version and 2 with one stderr line for bad input.
    from tests.cli_helpers import run_process

    def proc(*args):
        return run_process(*args, cwd=tmp_path, timeout=300)

    ok = proc("--version")
    assert ok.returncode == 0 and ok.stdout.strip() == "skydome 0.1.0"
    bad = proc("render", "--fov", "500", "-o", "sky.png")
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "--fov" in bad.stderr
    assert not list(tmp_path.iterdir())
