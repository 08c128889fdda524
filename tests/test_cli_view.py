"""``skydome view``: bad input is one line and exit status 2 before any window opens; a
missing optional dependency says how to install it; ``--frames N --screenshot FILE``
draws N frames in a window (Xvfb), saves the last and prints the median frame rate."""

from __future__ import annotations

import re
import sys

import numpy as np
import pytest

from tests.cli_helpers import run_cli
from tests.viewer_support import x_display  # noqa: F401  (fixture)

PLACE = ("--place", "Valletta", "--time", "2018-03-01T12:00Z")


@pytest.mark.parametrize(
    "args, words",
    [
        (("--fov", "500"), "--fov 500"),
        (("--camera", "cubemap"), "--camera cubemap"),
        (("--frames", "0"), "--frames 0"),
        (("--screenshot", "x.png"), "--frames"),
        (("--size", "5000x100"), "--size 5000x100"),
        (("--speed", "1e9"), "--speed"),
        (("--exposure", "bright"), "--exposure bright"),
        (("--sun-elevation", "10"), "--sun-elevation"),
    ],
)
def test_bad_input_is_one_line_and_status_2(tmp_path, args, words):
    r = run_cli("view", *PLACE, *args, cwd=tmp_path)
    assert r.returncode == 2, r
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], r.stderr
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "args",
    [
        ("--place", "Valletta", "--time", "2018-03-01T12:00Z", "--sun-elevation", "10"),
        ("--time", "2018-03-01T12:00Z"),
        ("--look", "moon"),
        ("--lat", "35"),
        ("--place", "Valletta", "--time", "tomorrow"),
        ("--sun-elevation", "95"),
        ("--place", "Valletta", "--time", "2018-03-01T12:00Z", "--look", "up"),
    ],
)
def test_view_and_render_check_place_time_and_sun_alike(tmp_path, args):
    """One helper (cli.describe.place_time_sun) checks these flags for both commands:
    the same bad flags give the same one-line message."""
    view = run_cli("view", *args, "--frames", "1", cwd=tmp_path)
    render = run_cli("render", *args, "--size", "16x8", cwd=tmp_path)
    assert view.returncode == render.returncode == 2, (view, render)
    assert view.stderr == render.stderr and len(view.stderr.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_view_without_time_takes_now_where_render_asks_for_it():
    from datetime import datetime, timezone
    from types import SimpleNamespace

    from skydome.cli.describe import place_time_sun
    from skydome.errors import ParameterError

    flags = SimpleNamespace(place="Valletta", lat=None, lon=None, elevation=None,
                            sun_elevation=None, sun_azimuth=None, look=None)  # fmt: skip
    with pytest.raises(ParameterError, match="a place needs --time"):
        place_time_sun(flags, None)
    pts = place_time_sun(flags, None, default_now=True)
    now = datetime.now(timezone.utc).timestamp() / 86400.0 + 2440587.5  # Unix epoch = JD
    assert abs(float(pts.time.jd_utc) - now) < 60.0 / 86400.0  # within a minute of now
    assert not pts.abstract and pts.sun_elevation_deg == 30.0


def test_without_glfw_it_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "glfw", None)  # import glfw -> ImportError
    r = run_cli("view", *PLACE, "--frames", "1")
    assert r.returncode == 2
    assert "pip install 'skydome[viewer]'" in r.stderr and len(r.stderr.splitlines()) == 1


def test_frames_and_screenshot(tmp_path, x_display):  # noqa: F811
    pytest.importorskip("glfw")
    pytest.importorskip("imgui_bundle")
    from PIL import Image

    png = tmp_path / "view.png"
    r = run_cli(
        "view", *PLACE, "--no-night", "--size", "320x180", "--look", "south",
        "--exposure", "14", "--frames", "5", "--screenshot", str(png),
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    # a still view: the first frame drawn, the others its kept frame shown again
    assert re.search(r"^\d+\.\d fps drawn \(.* ms per redraw; 1 of 5 frames drawn anew\)(; render scale .*)?$",
                     r.stdout, re.M), r.stdout  # fmt: skip
    img = np.asarray(Image.open(png).convert("RGB"))
    assert img.shape == (180, 320, 3) and img.std() > 2.0


def test_turn_draws_every_frame_anew(tmp_path, x_display):  # noqa: F811
    # --turn moves the camera every frame: each frame is drawn anew (the fps counts those)
    pytest.importorskip("glfw")
    pytest.importorskip("imgui_bundle")
    r = run_cli("view", *PLACE, "--no-night", "--size", "160x90", "--yaw", "90", "--pitch", "10",
                "--exposure", "14", "--frames", "5", "--turn", "15", "--no-panel")  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert re.search(r"^\d+\.\d fps drawn \(.* ms per redraw; 5 of 5 frames drawn anew\)(; render scale .*)?$",
                     r.stdout, re.M), r.stdout  # fmt: skip
    bad = run_cli("view", *PLACE, "--frames", "2", "--turn", "400")
    assert bad.returncode == 2 and "--turn" in bad.stderr and len(bad.stderr.splitlines()) == 1


def test_the_viewer_draws_clouds_interactively(tmp_path, x_display):  # noqa: F811
    """``skydome view --clouds`` marches them in the interactive mode (an eighth of the
    resolution, accumulated over frames): the screenshot's sky is an overcast grey-white
    where the clear sky is blue."""
    pytest.importorskip("glfw")
    pytest.importorskip("imgui_bundle")
    from PIL import Image

    png = tmp_path / "clouds.png"
    r = run_cli(
        "view", *PLACE, "--no-night", "--size", "320x180", "--look", "south", "--pitch", "30",
        "--exposure", "14", "--frames", "8", "--screenshot", str(png), "--no-panel",
        "--clouds", "overcast", "--coverage", "1",
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    img = np.asarray(Image.open(png).convert("RGB")).astype(float)
    top = img[:60]  # the sky: an overcast deck is grey-white, a clear sky blue (B > 1.3 R)
    assert np.mean(top[..., 2] / np.maximum(top[..., 0], 1.0)) < 1.15
