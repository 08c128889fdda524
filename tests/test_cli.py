"""The command line: outputs, messages and exit status for bad input."""

import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from skydome.io import read_exr


def run(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "skydome", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=300,
    )


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
        (["-o", "OUT/x.jpg"], "extension"),
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
