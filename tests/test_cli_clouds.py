"""The cloud flags of ``skydome render`` (and ``timelapse``, ``view``: the same helper):
a frame with clouds differs from the clear one where the clouds are, the wind moves them in
a time-lapse, and bad values get one line, exit status 2 and nothing written."""

from __future__ import annotations

import numpy as np
import pytest

from tests.cli_helpers import run_cli

NOON = ["--lat", "35.9", "--lon", "14.5", "--time", "2021-06-21T10:00Z", "--look", "east",
        "--pitch", "30", "--size", "96x54"]  # fmt: skip


def test_render_with_clouds_writes_a_cloudy_frame(tmp_path):
    clear, cloudy = tmp_path / "clear.npy", tmp_path / "cloudy.npy"
    r1 = run_cli("render", *NOON, "-o", clear)
    r2 = run_cli("render", *NOON, "--clouds", "overcast", "--coverage", "1", "-o", cloudy)
    assert r1.returncode == 0 and r2.returncode == 0, (r1.stderr, r2.stderr)
    a, b = np.load(clear), np.load(cloudy)
    assert np.all(np.isfinite(b))
    # An overcast deck: the sky above the horizon is white-grey (R ~ B), the clear one blue.
    sky_a, sky_b = a[:20], b[:20]
    assert np.mean(sky_a[..., 2] / sky_a[..., 0]) > 1.3
    assert np.mean(sky_b[..., 2] / sky_b[..., 0]) < 1.15


def test_render_reports_the_decks_optical_depth(tmp_path):
    """The CLI says what the deck holds: its nominal optical depth (0.25 g/m^3 over 1 km of
    stratus: 37.5) and the census of its columns (closed: 100 % cloudy, the mean within 10 %
    of the nominal)."""
    out = tmp_path / "overcast.png"
    r = run_cli("render", "--sun-elevation", "45", "--size", "32x18", "--clouds", "overcast",
                "-o", out)  # fmt: skip
    assert r.returncode == 0, r.stderr
    line = next(x for x in r.stdout.splitlines() if x.startswith("clouds:"))
    assert "coverage 1.00, optical depth 37.5 per cloud" in line, line
    mean = float(line.split("columns: mean ")[1].split(",")[0])
    assert abs(mean / 37.5 - 1.0) < 0.10 and "100 % cloudy" in line, line


def test_timelapse_moves_the_clouds_with_the_wind(tmp_path):
    out = tmp_path / "frames"
    r = run_cli(
        "timelapse", "--lat", "35.9", "--lon", "14.5", "--start", "2021-06-21T10:00Z",
        "--end", "2021-06-21T10:02Z", "--step", "2min", "--size", "64x36", "--look", "east",
        "--pitch", "30", "--exposure", "14", "--format", "npy", "-o", out, "--clouds", "fair",
        "--coverage", "0.6", "--wind", "30,270",
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    first, last = sorted(out.glob("*.npy"))
    # 30 m/s for 2 minutes carries the clouds 3.6 km: the frames differ where they are
    assert not np.allclose(np.load(first), np.load(last), rtol=0.02)


@pytest.mark.parametrize(
    "args, needle",
    [
        (["--clouds", "drizzle"], "--clouds drizzle"),
        (["--coverage", "0.5"], "--coverage needs --clouds"),
        (["--clouds", "fair", "--coverage", "1.5"], "coverage must be within [0, 1]"),
        (["--clouds", "fair", "--cloud-thickness", "-5"], "thickness must be positive"),
        (["--clouds", "fair", "--wind", "fast"], "--wind must be SPEED,FROM"),
        (["--clouds", "fair", "--weather-map", "missing.png"], "weather map"),
        (["--clouds", "fair", "--cloud-base", "150000"], "above the top of the atmosphere"),
        (["--clouds", "fair", "--cloud-type", "nimbus"], "--cloud-type nimbus"),
    ],
)
def test_bad_cloud_flags_are_refused(tmp_path, args, needle):
    out = tmp_path / "x.png"
    r = run_cli("render", "--sun-elevation", "30", "--size", "32x18", *args, "-o", out)
    assert r.returncode == 2, r.stdout + r.stderr
    assert needle in r.stderr and r.stderr.strip().count("\n") == 0, r.stderr
    assert not out.exists()
