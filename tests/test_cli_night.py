"""``skydome render`` at night: --bortle, --night-vision, --overlay; bad values get one line,
exit status 2 and nothing written."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from tests.cli_helpers import run_cli

DARK = ["--lat", "28.7606", "--lon", "-17.8816", "--elevation", "2396"]
NIGHT = [*DARK, "--time", "2019-04-05T01:04Z", "--look", "zenith", "--size", "64x64"]


def test_render_reports_the_night_glow_and_bortle_brightens_the_zenith(tmp_path):
    dark, lit = tmp_path / "dark.npy", tmp_path / "lit.npy"
    r1 = run_cli("render", *NIGHT, "-o", dark)
    r2 = run_cli("render", *NIGHT, "--bortle", "8", "-o", lit)
    assert r1.returncode == 0 and r2.returncode == 0, (r1.stderr, r2.stderr)
    assert "night glow at the zenith" in r1.stdout and "airglow 22.38" in r1.stdout
    assert "light_pollution" in r2.stdout and "light_pollution" not in r1.stdout
    # Bortle 8 (18.0-18.4 mag/arcsec^2) against a natural 21.8: ~20x brighter at the zenith.
    ratio = np.median(np.load(lit)[..., 1]) / np.median(np.load(dark)[..., 1])
    assert 15 < ratio < 35


def test_night_vision_and_overlays_change_the_png_only(tmp_path):
    a_png, a_npy = tmp_path / "a.png", tmp_path / "a.npy"
    b_png, b_npy = tmp_path / "b.png", tmp_path / "b.npy"
    r1 = run_cli("render", *NIGHT, "-o", a_png, "-o", a_npy)
    r2 = run_cli("render", *NIGHT, "--night-vision", "--overlay", "grid", "-o", b_png, "-o", b_npy)
    assert r1.returncode == 0 and r2.returncode == 0, (r1.stderr, r2.stderr)
    np.testing.assert_array_equal(np.load(a_npy), np.load(b_npy))
    assert not np.array_equal(np.asarray(Image.open(a_png)), np.asarray(Image.open(b_png)))


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        ([*NIGHT, "--bortle", "0"], "--bortle 0 must be an integer from 1 to 9"),
        (["--sun-elevation", "-20", "--bortle", "5"], "--bortle needs a place"),
        ([*NIGHT, "--overlay", "lines,stars"], "overlay 'stars' is unknown"),
        (["--model", "single", "--night-vision"], "--night-vision and --overlay need"),
    ],
)
def test_bad_night_options_are_refused_before_any_work(tmp_path, args, needle):
    out = tmp_path / "x.png"
    r = run_cli("render", *args, "-o", out)
    assert r.returncode == 2, r
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], r.stderr
    assert not out.exists()
