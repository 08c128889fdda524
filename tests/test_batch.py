"""skydome batch: specs (TOML and YAML) checked whole, jobs with deterministic names, outputs
identical to single renders through Sky, a resumable manifest (checksums), and Dask: a local
cluster of 2 workers, one of which is killed mid-run."""

from __future__ import annotations

import gc
import math
import os
import signal
from pathlib import Path

import numpy as np
import pytest

from skydome import EquirectCamera, Sky
from skydome.batch import (
    COLUMNS,
    JobRunner,
    Manifest,
    expand_jobs,
    load_spec,
    parse_spec,
    render_many,
)
from skydome.errors import ParameterError
from skydome.io import read_exr
from skydome.physics import spherical_harmonics as sh
from skydome.spectra import SRGB_LUMINANCE
from tests.cli_helpers import run_cli
from tests.test_viewer_soak import rss_bytes

pytest.importorskip("distributed")
pytest.importorskip("pyarrow")

SPEC_TOML = """
[sky]
places = ["Valletta", [48.8566, 2.3522]]
times = { start = "2018-06-21T08:00", stop = "2018-06-21T12:00", step = "2h" }
weather = ["none", "hazy"]
[output]
camera = ["equirect", { type = "perspective", fov = 60, look = "sun", name = "sun60" }]
size = "64x32"
formats = ["exr", "png"]
"""

SPEC_YAML = """
sky:
  places: [Valletta, [48.8566, 2.3522]]
  times: {start: "2018-06-21T08:00", stop: "2018-06-21T12:00", step: 2h}
  weather: [none, hazy]
output:
  camera: [equirect, {type: perspective, fov: 60, look: sun, name: sun60}]
  size: 64x32
  formats: [exr, png]
"""


def _abstract_spec(tmp_path: Path, elevations, azimuths, formats=("exr", "npy"), size="64x32"):
    path = tmp_path / "spec.toml"
    path.write_text(
        "[sky]\n"
        f"sun_elevation = {list(elevations)}\n"
        f"sun_azimuth = {list(azimuths)}\n"
        "[output]\n"
        'camera = "equirect"\n'
        f'size = "{size}"\n'
        f"formats = {list(formats)!r}\n".replace("'", '"')
    )
    return path


# ---------------------------------------------------------------------------- the spec


def test_toml_and_yaml_give_the_same_jobs_with_deterministic_names(tmp_path):
    (tmp_path / "a.toml").write_text(SPEC_TOML)
    (tmp_path / "a.yaml").write_text(SPEC_YAML)
    toml_jobs = expand_jobs(load_spec(tmp_path / "a.toml"))
    yaml_jobs = expand_jobs(load_spec(tmp_path / "a.yaml"))
    # 2 places x 3 times x 2 weathers x 2 cameras
    assert len(toml_jobs) == 24
    assert [j.name for j in toml_jobs] == [j.name for j in yaml_jobs]
    assert len({j.name for j in toml_jobs}) == 24
    # the same spec expanded again names its jobs the same
    assert [j.name for j in expand_jobs(load_spec(tmp_path / "a.toml"))] == [
        j.name for j in toml_jobs
    ]
    # Times without an offset are the place's local time: Valletta keeps CEST (UTC+2) in
    # June, a place given by numbers UTC (as on the command line).
    valletta = sorted({j.time_utc for j in toml_jobs if j.place == "Valletta"})
    paris = sorted({j.time_utc for j in toml_jobs if j.place != "Valletta"})
    assert valletta == ["2018-06-21T06:00:00Z", "2018-06-21T08:00:00Z", "2018-06-21T10:00:00Z"]
    assert paris == ["2018-06-21T08:00:00Z", "2018-06-21T10:00:00Z", "2018-06-21T12:00:00Z"]
    name = toml_jobs[0].name
    assert name.startswith("valletta_20180621T060000Z_equirect-64x32_"), name


def test_the_issue_spec_of_sun_angles(tmp_path):
    spec = parse_spec({
        "sky": {"sun_elevation": [5, 20, 40, 60], "sun_azimuth": [90, 270]},
        "output": {"camera": "equirect", "size": "128x64", "formats": ["exr"]},
    })  # fmt: skip
    jobs = expand_jobs(spec)
    assert len(jobs) == 8
    assert {(j.sun_elevation_deg, j.sun_azimuth_deg) for j in jobs} == {
        (e, a) for e in (5.0, 20.0, 40.0, 60.0) for a in (90.0, 270.0)
    }
    assert all(j.files() == {"exr": f"{j.name}.exr"} for j in jobs)


def test_times_written_as_toml_and_yaml_datetimes(tmp_path):
    # unquoted datetimes: with an offset as they say, without one the place's local time
    (tmp_path / "t.toml").write_text(
        '[sky]\nplaces = "Valletta"\ntimes = [2018-06-21T08:00:00Z, 2018-06-21T12:00:00]\n'
    )
    (tmp_path / "t.yaml").write_text(
        "sky:\n  places: Valletta\n  times: [2018-06-21T08:00:00Z, 2018-06-21 12:00:00]\n"
    )
    for name in ("t.toml", "t.yaml"):
        jobs = expand_jobs(load_spec(tmp_path / name))
        assert [j.time_utc for j in jobs] == ["2018-06-21T08:00:00Z", "2018-06-21T10:00:00Z"]


BAD_SPECS = [
    ('[sky]\nsun_elevation = 5\nwether = "fog"\n', "sky.wether"),
    ("[sky]\nsun_elevation = 5\n[outputs]\n", "outputs"),
    ('[sky]\nplaces = ["Valletta", "Atlantis"]\ntimes = "2018-03-01T08:00"\n', "sky.places[1]"),
    (
        '[sky]\nplaces = "Valletta"\n'
        'times = { start = "2018-03-01T12:00", stop = "2018-03-01T08:00", step = "1h" }\n',
        "sky.times.stop",
    ),
    ('[sky]\nsun_elevation = 5\n[output]\ncamera = "fish"\n', "output.camera[0].type"),
    ('[sky]\nsun_elevation = 5\n[output]\nsize = "64by32"\n', "output.size[0]"),
    ("[sky]\nsun_elevation = 95\n", "sky.sun_elevation[0]"),
    ('[sky]\nsun_elevation = 5\n[output]\nformats = ["tiff"]\n', "output.formats[0]"),
    ('[sky]\nplaces = "Valletta"\n', "sky.times"),
    ('[sky]\nsun_elevation = 5\nweather = "hail"\n', "sky.weather[0]"),
]


@pytest.mark.parametrize(("text", "key"), BAD_SPECS, ids=[k for _, k in BAD_SPECS])
def test_bad_specs_exit_2_with_one_line_naming_the_key_and_make_nothing(tmp_path, text, key):
    spec = tmp_path / "bad.toml"
    spec.write_text(text)
    out = tmp_path / "out"
    r = run_cli("batch", spec, "-o", out, "--serial")
    assert r.returncode == 2, r
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("skydome: error: "), r.stderr
    assert f"'{key}'" in lines[0], lines[0]
    assert not out.exists()
    with pytest.raises(ParameterError, match=key.replace("[", r"\[").replace("]", r"\]")):
        load_spec(spec)


# ---------------------------------------------------------------------------- outputs


@pytest.mark.gl
def test_outputs_are_the_single_renders_and_the_manifest_their_light(tmp_path):
    # Valletta on the solstice, clear and hazy, equirect and a 60 deg camera at the Sun: every
    # file holds the very frame Sky(...).render gives for the same parameters (bit for bit).
    spec = parse_spec({
        "sky": {"places": ["Valletta"], "times": ["2018-06-21T08:00"],
                "weather": ["none", "hazy"]},
        "output": {"camera": ["equirect", {"type": "perspective", "fov": 60, "look": "sun"}],
                   "size": "64x32", "formats": ["exr", "png", "npy"]},
    })  # fmt: skip
    jobs = expand_jobs(spec)
    assert len(jobs) == 4
    result = render_many(jobs, tmp_path, serial=True, progress=False)
    assert result.rendered == 4 and not result.failed, result.failed
    rows = {r["job"]: r for r in result.rows}
    from PIL import Image

    for job in jobs:
        weather = job.weather
        with Sky("Valletta", job.time_utc, weather=weather) as sky:
            cam = EquirectCamera() if job.camera == "equirect" else sky.camera("sun", fov_deg=60.0)
            frame = sky.render(cam, 64, 32, tonemap="filmic")
            light = sky.lighting()
        npy = np.load(tmp_path / f"{job.name}.npy")
        exr, _ = read_exr(tmp_path / f"{job.name}.exr")
        png = np.asarray(Image.open(tmp_path / f"{job.name}.png").convert("RGB"))
        assert np.array_equal(npy, frame.data)
        assert np.array_equal(exr, frame.data)
        assert np.array_equal(png, frame.image)
        row = rows[job.name]
        assert row["sun_altitude_deg"] == sky.state.sun.elevation_deg
        got_sh = np.array([[row[f"sh_{i}_{c}"] for c in "rgb"] for i in range(9)])
        assert np.array_equal(got_sh, light.sh)
        # The manifest's light from the tables (as `skydome illuminance`, at the place's
        # ground) against the rendered map's: the diffuse light on a horizontal surface from
        # the 9 harmonics within 3 % (Ramamoorthi-Hanrahan's bound for smooth skies; 2.4 %
        # clear, 0.7 % hazy seen), the direct light the Sun's disk measured in the frame
        # times sin(altitude) within 1 % (the disk's light through a 2 deg camera; 0.5 %
        # clear, 0.01 % hazy seen). (The manifest's light was the sea level's before: under
        # the hazy weather 2.5-5.5 % below the drawn disk's at Valletta's 56 m.)
        up = sh.evaluate(light.sh, np.array([[0.0, 0.0, 1.0]]))[0] @ SRGB_LUMINANCE
        assert row["diffuse_horizontal_lux"] == pytest.approx(up, rel=0.03)
        direct = light.sun.illuminance_lux * math.sin(math.radians(row["sun_altitude_deg"]))
        assert row["direct_horizontal_lux"] == pytest.approx(direct, rel=0.01)
        assert row["global_horizontal_lux"] == pytest.approx(
            row["direct_horizontal_lux"] + row["diffuse_horizontal_lux"], rel=1e-12
        )
    # a sky at 08:00 CEST (06:00 UTC) in Valletta: the Sun low in the east-north-east
    morning = rows[jobs[0].name]
    assert morning["time_local"] == "2018-06-21T08:00:00+02:00"
    assert 10.0 < morning["sun_altitude_deg"] < 30.0 and 60.0 < morning["sun_azimuth_deg"] < 90.0


@pytest.mark.gl
def test_none_writes_only_the_light_and_a_second_run_renders_nothing(tmp_path):
    path = _abstract_spec(tmp_path, [10, 45], [180], formats=["none"])
    jobs = expand_jobs(load_spec(path))
    out = tmp_path / "out"
    first = render_many(jobs, out, serial=True, progress=False)
    assert first.rendered == 2 and not first.failed
    assert sorted(p.name for p in out.iterdir()) == ["manifest.csv", "manifest.parquet"]
    second = render_many(jobs, out, serial=True, progress=False)
    assert (second.rendered, second.skipped) == (0, 2)
    rows = Manifest.load(out).rows
    assert all(r["status"] == "ok" and r["sh_0_g"] > 0 and r["lights"] for r in rows.values())


@pytest.mark.gl
def test_a_runner_keeps_its_memory_flat_over_many_jobs(tmp_path):
    # A worker renders thousands of skies: each job's sky, frame, light and illuminance
    # (the tables' probe) must leave nothing behind. Before the illuminance shared the sky's
    # tables it uploaded a set per call: +27 MB a job, +430 MB over these 16.
    path = _abstract_spec(tmp_path, [float(e) for e in range(-4, 44, 2)], [200])
    jobs = expand_jobs(load_spec(path))
    runner = JobRunner()
    try:
        for job in jobs[:8]:
            assert runner.run(job, tmp_path)["status"] == "ok"
        gc.collect()
        before = rss_bytes()
        for job in jobs[8:]:
            assert runner.run(job, tmp_path)["status"] == "ok"
        gc.collect()
        grown_mib = (rss_bytes() - before) / 2**20
    finally:
        runner.close()
    assert grown_mib < 40.0, f"{grown_mib:.0f} MiB more after {len(jobs) - 8} jobs"


# ---------------------------------------------------------------------------- Dask


def _check_folder(out: Path, jobs, formats=("exr", "npy")) -> dict:
    """Every job's files there once and whole, no temporary file left, the manifest a row
    per job (Parquet and CSV alike), each "ok" with the files' checksums."""
    import pyarrow.parquet as pq

    names = sorted(p.name for p in out.iterdir())
    assert not [n for n in names if n.startswith(".")], names  # no temporary files
    expected = sorted([f"{j.name}.{f}" for j in jobs for f in formats])
    assert names == sorted([*expected, "manifest.csv", "manifest.parquet"])
    for j in jobs:
        data = np.load(out / f"{j.name}.npy")  # a truncated file would not load
        assert data.shape == (32, 64, 4) and np.all(np.isfinite(data))
        exr, _ = read_exr(out / f"{j.name}.exr")
        assert np.array_equal(exr, data)
    table = pq.read_table(out / "manifest.parquet")
    assert table.column_names == list(COLUMNS)
    jobs_column = table.column("job").to_pylist()
    assert sorted(jobs_column) == sorted(j.name for j in jobs)  # a row per job, none twice
    csv_rows = Manifest.load(out).rows
    (out / "manifest.parquet").rename(out / "parquet.bak")
    assert Manifest.load(out).rows == csv_rows  # the CSV holds the same rows
    (out / "parquet.bak").rename(out / "manifest.parquet")
    assert all(r["status"] == "ok" for r in csv_rows.values())
    return csv_rows


@pytest.mark.gl
def test_a_local_cluster_of_two_workers_renders_40_jobs_as_one_process_does(tmp_path):
    path = _abstract_spec(tmp_path, [-4, 2, 6, 10, 15, 20, 30, 45, 60, 80], [0, 90, 180, 270])
    jobs = expand_jobs(load_spec(path))
    assert len(jobs) == 40
    out = tmp_path / "out"
    result = render_many(jobs, out, workers=2, progress=False)
    assert result.rendered == 40 and not result.failed, result.failed[:1]
    rows = _check_folder(out, jobs)
    workers = {r["worker"] for r in rows.values()}
    assert len(workers) == 2 and str(os.getpid()) not in {w.split(":")[-1] for w in workers}
    # the workers' frames are this process's, bit for bit
    for job in jobs[::13]:
        with Sky(sun_elevation_deg=job.sun_elevation_deg, sun_azimuth_deg=job.sun_azimuth_deg) as s:
            frame = s.render(EquirectCamera(), 64, 32)
        assert np.array_equal(np.load(out / f"{job.name}.npy"), frame.data), job.name
    again = render_many(jobs, out, workers=2, progress=False)
    assert (again.rendered, again.skipped) == (0, 40)
    # a damaged file is found by its checksum and its job alone rendered again
    victim = out / f"{jobs[7].name}.exr"
    victim.write_bytes(victim.read_bytes()[:100])
    fixed = render_many(jobs, out, serial=True, progress=False)
    assert (fixed.rendered, fixed.skipped) == (1, 39)
    _check_folder(out, jobs)


@pytest.mark.gl
def test_a_worker_killed_mid_run_leaves_every_output_once_and_whole(tmp_path):
    from distributed import Client, LocalCluster

    path = _abstract_spec(tmp_path, [-2, 3, 7, 12, 18, 25, 35, 50, 65, 85], [45, 135, 225, 315])
    jobs = expand_jobs(load_spec(path))
    out = tmp_path / "out"
    cluster = LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    watcher = Client(cluster)
    seen, killed = [], []

    def kill_one(row):
        # After the 6th result, SIGKILL a worker that is rendering (as a machine lost would).
        seen.append(row)
        if len(seen) == 6:
            pid = next(iter(watcher.run(os.getpid).values()))
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    try:
        result = render_many(
            jobs, out, scheduler=cluster.scheduler_address, progress=False, on_row=kill_one
        )
    finally:
        watcher.close()
        cluster.close()
    assert killed, "no worker was killed"
    assert not result.failed, result.failed[:1]
    rows = _check_folder(out, jobs)
    by_worker = {r["worker"].split(":")[-1] for r in rows.values()}
    # the killed worker's unfinished jobs ran on the others (its restart included)
    assert len(by_worker) >= 2
    again = render_many(jobs, out, serial=True, progress=False)
    assert (again.rendered, again.skipped) == (0, 40)


# ---------------------------------------------------------------------------- the command


@pytest.mark.gl
def test_the_command_renders_a_spec_then_finds_it_done(tmp_path):
    path = _abstract_spec(tmp_path, [8], [250], formats=["exr", "png"])
    out = tmp_path / "out"
    r = run_cli("batch", path, "-o", out, "--serial")
    assert r.returncode == 0, r.stderr
    assert "1 rendered (0 failed), 0 complete before" in r.stderr
    rows = Manifest.load(out).rows
    (row,) = rows.values()
    assert row["sun_altitude_deg"] == pytest.approx(8.0, abs=1e-9)
    r = run_cli("batch", path, "-o", out, "--serial")
    assert r.returncode == 0 and "0 rendered (0 failed), 1 complete before" in r.stderr
    dry = run_cli("batch", path, "--dry-run", "-o", tmp_path / "dry")
    assert dry.returncode == 0 and dry.stdout.strip() == row["job"]
    assert not (tmp_path / "dry").exists()
