"""The command line of a sky for a place and time: ``render --place/--lat/--lon --time``,
``timelapse`` and ``places``; bad input gets one line, exit status 2 and nothing written."""

from __future__ import annotations

import os

import numpy as np
import pytest

from tests.cli_helpers import run_cli

VALLETTA = ["--place", "Valletta", "--time", "2018-03-01T19:00Z"]


def assert_refused(result, *needles: str) -> None:
    assert result.returncode == 2, result
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("skydome: error: "), result.stderr
    for needle in needles:
        assert needle in lines[0], lines[0]


def test_render_a_place_and_time_reports_the_lights(tmp_path):
    out = tmp_path / "v.npy"
    r = run_cli("render", *VALLETTA, "--look", "moon", "--fov", "5", "--size", "96x54", "-o", out)
    assert r.returncode == 0, r.stderr
    # Valletta, 2018-03-01 19:00 UTC: the Sun 25.7 deg below the horizon, a full Moon 28.5 deg
    # up in the east (skydome ephemeris gives the same).
    assert "sun: elevation -25.67 deg, azimuth 279.89 deg" in r.stdout
    assert "moon: elevation 28.49 deg, azimuth 98.52 deg, 99.9 % lit" in r.stdout
    assert "exposure EV100" in r.stdout
    frame = np.load(out)
    assert frame.shape == (54, 96, 4) and np.isfinite(frame).all()
    # Looking at the Moon: its disk (0.5 deg, 10 px at a 5 deg field) is the brightest spot,
    # at the centre. A pixel holds the part of the disk it covers (core.cameras.disk_samples),
    # so the pixels it touches are those within about half a pixel of its rim: more than
    # pi 5.2^2, fewer than pi 6.2^2 (measured 102).
    lum = frame[..., :3] @ np.array([0.2126, 0.7152, 0.0722])
    disk = lum > 10 * np.median(lum)
    ys, xs = np.nonzero(disk)
    assert np.pi * 5.2**2 < disk.sum() < np.pi * 6.2**2
    assert abs(ys.mean() - 26.5) < 0.5 and abs(xs.mean() - 47.5) < 0.5


def test_render_lat_lon_and_place_agree(tmp_path):
    a, b = tmp_path / "a.npy", tmp_path / "b.npy"
    # --bortle 1: no artificial glow, as at a position given as numbers (a named city has its
    # estimated light pollution by default)
    r1 = run_cli(
        "render", *VALLETTA, "--bortle", "1", "--size", "32x18", "--look", "zenith", "-o", a
    )
    r2 = run_cli(
        "render", "--lat", "35.8989", "--lon", "14.5146", "--elevation", "56",
        "--time", "2018-03-01T20:00+01:00", "--size", "32x18", "--look", "zenith", "-o", b,
    )  # fmt: skip
    assert r1.returncode == 0 and r2.returncode == 0, (r1.stderr, r2.stderr)
    np.testing.assert_allclose(np.load(a), np.load(b), rtol=1e-6)


@pytest.mark.parametrize(
    "args, needles",
    [
        (["--lat", "91", "--lon", "0", "--time", "2018-03-01T19:00Z"], ["--lat 91", "-90 to 90"]),
        (["--place", "Valletta", "--time", "tomorrow"], ["--time 'tomorrow'", "ISO 8601"]),
        (["--place", "Atlantis", "--time", "2018-03-01T19:00Z"], ["unknown place 'Atlantis'", "did you mean"]),
        ([*VALLETTA, "--sun-elevation", "5"], ["--sun-elevation"]),
        (["--place", "Valletta"], ["needs --time"]),
        (["--time", "2018-03-01T19:00Z"], ["--time needs a place"]),
        (["--lat", "35"], ["--lat and --lon go together"]),
        (["--place", "Valletta", "--lat", "35", "--lon", "14", "--time", "2018-03-01"], ["--place and --lat"]),
        ([*VALLETTA, "--look", "up"], ["--look"]),
        (["--look", "moon"], ["--look moon needs a place"]),
    ],
)  # fmt: skip
def test_render_refuses_bad_places_and_times(tmp_path, args, needles):
    out = tmp_path / "sky.png"
    assert_refused(run_cli("render", *args, "--size", "16x8", "-o", out), *needles)
    assert list(tmp_path.iterdir()) == []


def test_render_refuses_an_unwritable_output(tmp_path):
    assert_refused(
        run_cli("render", *VALLETTA, "-o", tmp_path / "missing" / "sky.png"), "does not exist"
    )


TIMELAPSE = ["timelapse", "--place", "Valletta", "--start", "2018-03-01T16:50Z"]


def test_timelapse_to_mp4_and_to_frames(tmp_path):
    import imageio_ffmpeg

    mp4 = tmp_path / "dusk.mp4"
    r = run_cli(
        *TIMELAPSE, "--end", "2018-03-01T17:10Z", "--step", "5min", "--size", "64x36", "-o", mp4
    )
    assert r.returncode == 0, r.stderr
    assert "5 frames" in r.stdout and "eye adaptation" in r.stdout
    reader = imageio_ffmpeg.read_frames(str(mp4))
    meta = next(reader)
    frames = [np.frombuffer(f, np.uint8).reshape(36, 64, 3) for f in reader]
    assert meta["size"] == (64, 36) and len(frames) == 5
    # Dusk: a sky is drawn in every frame (the exposure follows the eye, not black or white).
    for f in frames:
        assert 5 < f.mean() < 250
    folder = tmp_path / "frames"
    r = run_cli(
        *TIMELAPSE, "--end", "2018-03-01T17:00Z", "--step", "10min", "--size", "32x18",
        "--format", "exr", "--exposure", "10", "-o", f"{folder}/",
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    names = sorted(p.name for p in folder.iterdir())
    assert names == ["frame_000000.exr", "frame_000001.exr"]


@pytest.mark.parametrize(
    "args, needles",
    [
        (["--end", "2018-03-01T17:00Z", "--step", "0"], ["--step 0", "longer than zero"]),
        (["--end", "2018-03-01T17:00Z", "--step", "soon"], ["--step soon"]),
        (["--end", "2018-03-01T16:00Z"], ["--end", "before --start"]),
        (["--end", "2018-04-01T00:00Z", "--step", "10s"], ["261,781 frames", "--yes"]),
        (["--end", "2018-03-01T17:00Z", "--exposure", "auto"], ["flickers"]),
        (["--end", "2018-03-01T17:00Z", "--size", "33x18"], ["even width"]),
        (["--end", "2018-03-01T17:00Z", "--altitude", "-5"], ["--altitude -5"]),
    ],
)  # fmt: skip
def test_timelapse_refuses_bad_input(tmp_path, args, needles):
    out = tmp_path / "day.mp4"
    assert_refused(run_cli(*TIMELAPSE, *args, "-o", out), *needles)
    assert list(tmp_path.iterdir()) == []


def test_timelapse_refuses_unwritable_outputs(tmp_path):
    r = run_cli(*TIMELAPSE, "--end", "2018-03-01T17:00Z", "-o", tmp_path / "no" / "day.mp4")
    assert_refused(r)
    assert_refused(run_cli(*TIMELAPSE, "--end", "2018-03-01T17:00Z", "-o", tmp_path / "day.gif"))
    assert list(tmp_path.iterdir()) == []


def test_places_lists_and_searches():
    r = run_cli("places", "paranal")
    assert r.returncode == 0 and "Paranal" in r.stdout and "-24.62" in r.stdout
    assert run_cli("places").stdout.count("\n") > 300


@pytest.mark.parametrize("target", ["dusk.mp4", "frames/"])
def test_timelapse_interrupted_leaves_complete_output(tmp_path, monkeypatch, target):
    # Ctrl-C (KeyboardInterrupt) during the fourth frame: the MP4 holds the three frames
    # written and plays; a frame folder holds three complete frames and nothing else.
    import imageio_ffmpeg

    from skydome.scene.graph import FrameGraph

    original = FrameGraph.frame_texture
    calls = {"n": 0}

    def interrupted(self, *args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 4:
            raise KeyboardInterrupt
        return original(self, *args, **kwargs)

    monkeypatch.setattr(FrameGraph, "frame_texture", interrupted)
    out = f"{tmp_path}/{target}"
    r = run_cli(
        *TIMELAPSE, "--end", "2018-03-01T17:50Z", "--step", "5min", "--size", "32x18", "-o", out
    )
    assert r.returncode == 130 and "holds the 3 frames rendered" in r.stdout
    if target.endswith(".mp4"):
        reader = imageio_ffmpeg.read_frames(out)
        next(reader)
        assert sum(1 for _ in reader) == 3
        assert sorted(p.name for p in tmp_path.iterdir()) == ["dusk.mp4"]  # no temporary file
    else:
        names = sorted(p.name for p in (tmp_path / "frames").iterdir())
        assert names == [f"frame_00000{i}.png" for i in range(3)]


def test_timelapse_frames_need_a_new_or_empty_folder_or_replace(tmp_path):
    folder = tmp_path / "frames"
    args = [*TIMELAPSE, "--end", "2018-03-01T17:00Z", "--step", "10min", "--size", "32x18",
            "--exposure", "10", "-o", folder]  # fmt: skip
    assert run_cli(*args).returncode == 0
    before = {p.name: p.stat().st_mtime_ns for p in folder.iterdir()}
    assert sorted(before) == ["frame_000000.png", "frame_000001.png"]
    # Again into the same folder: refused, the frames of the first run untouched.
    assert_refused(run_cli(*args), "holds 2 frames of an earlier run", "add --replace")
    assert {p.name: p.stat().st_mtime_ns for p in folder.iterdir()} == before
    # --replace: every old frame goes, whatever its format or number of digits.
    (folder / "frame_0000002.exr").write_bytes(b"from an older run")
    r = run_cli(*args, "--replace", "--format", "jpg")
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in folder.iterdir()) == ["frame_000000.jpg", "frame_000001.jpg"]
    # A file that is not a frame: refused even with --replace, and nothing is touched.
    (folder / "notes.txt").write_text("the user's")
    before = sorted(p.name for p in folder.iterdir())
    assert_refused(run_cli(*args, "--replace"), "'notes.txt'", "not frames")
    assert sorted(p.name for p in folder.iterdir()) == before


def test_timelapse_killed_leaves_a_temporary_file_the_next_run_removes(tmp_path):
    """SIGKILL in the middle of a long MP4: no target, one temporary file named by its
    writer's PID; the next time-lapse in that folder removes it."""
    import subprocess
    import sys
    import time

    from skydome.io.atomic import TEMP_NAME
    from tests.cli_helpers import cli_env

    long = [*TIMELAPSE, "--end", "2018-03-02T16:50Z", "--step", "1min", "--size", "32x18"]
    cmd = [sys.executable, "-m", "skydome", *long, "-o", str(tmp_path / "long.mp4")]
    proc = subprocess.Popen(cmd, env=cli_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        deadline = time.monotonic() + 300
        while not [n for n in os.listdir(tmp_path) if n.endswith(".tmp.mp4")]:  # not a probe
            assert proc.poll() is None, proc.stderr.read()
            assert time.monotonic() < deadline, "no frame written in 300 s"
            time.sleep(0.05)
        time.sleep(0.5)  # a few frames into it
    finally:
        proc.kill()
        proc.communicate()
    (left,) = os.listdir(tmp_path)
    assert TEMP_NAME.match(left)[1] == str(proc.pid) and left.endswith(".tmp.mp4")
    short = [*TIMELAPSE, "--end", "2018-03-01T16:55Z", "--step", "5min", "--size", "32x18"]
    r = run_cli(*short, "-o", tmp_path / "short.mp4")
    assert r.returncode == 0, r.stderr
    assert os.listdir(tmp_path) == ["short.mp4"]


def test_timelapse_shows_the_night_layers_in_a_total_eclipse(ctx):
    # The time-lapse leaves the night layers out by day (the Sun >= 10 deg: under 0.6 % of the
    # darkest sky), but not while an eclipse hides >= 90 % of the Sun: at Dallas on
    # 2024-04-08 the Sun stood 60-67 deg up both in the partial phase an hour before totality
    # (layers off) and in totality at 18:42 UTC (on: Venus and Jupiter were seen).
    from skydome import Sky
    from skydome.cli.timelapse_cmd import show_night_sky
    from skydome.description import NIGHT_LAYERS

    for when, on in (("2024-04-08T17:40Z", False), ("2024-04-08T18:42Z", True)):
        with Sky("Dallas", when, ctx=ctx) as sky:
            assert sky.state.sun.elevation_deg > 60.0
            show_night_sky(sky.graph, sky.state)
            night = [la for la in sky.layers if la.name in NIGHT_LAYERS]
            assert night and all(la.enabled is on for la in night), when
