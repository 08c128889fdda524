"""Local time: a time without an offset given with a gazetteer place is the place's wall-clock
time (its IANA zone, daylight saving included), in the Python API, the command line, the
time-lapse range and ephemeris/events; ``--utc``/``utc=True`` and a place given as numbers
read it as UTC; a time the zone's clocks skip or repeat is refused, naming the flag.

The offsets checked are the tz database's facts, written out by hand here (CET = UTC+1,
CEST = UTC+2; Chile's summer UTC-3, winter UTC-4; Sydney's summer UTC+11): the test would
fail on a wrong zone, a zone read as UTC, or a daylight-saving rule ignored.
"""

from __future__ import annotations

import datetime as dt
import json
from zoneinfo import ZoneInfo

import numpy as np
import pytest
from PIL import Image

from skydome.astro import to_time
from skydome.astro.time import LocalTimeError, format_local
from skydome.description import SkyDescription
from skydome.errors import ParameterError
from tests.cli_helpers import run_cli


def _iso(t) -> str:
    return str(t.iso())


# ---------------------------------------------------------------- to_time with a zone

LOCAL_CASES = [
    # zone, local wall-clock time, UTC it is
    ("Europe/Malta", "2018-03-01T20:00", "2018-03-01T19:00:00Z"),  # CET, winter
    ("Europe/Paris", "2024-07-05T23:30", "2024-07-05T21:30:00Z"),  # CEST, summer: UTC+2
    ("Europe/Paris", "2024-01-05T23:30", "2024-01-05T22:30:00Z"),  # CET: UTC+1
    ("America/Santiago", "2024-01-15T22:00", "2024-01-16T01:00:00Z"),  # southern summer -3
    ("America/Santiago", "2024-07-15T22:00", "2024-07-16T02:00:00Z"),  # southern winter -4
    ("Australia/Sydney", "2024-01-15T20:00", "2024-01-15T09:00:00Z"),  # AEDT +11
    ("Australia/Sydney", "2024-07-15T20:00", "2024-07-15T10:00:00Z"),  # AEST +10
    ("Pacific/Honolulu", "2024-07-15T20:00", "2024-07-16T06:00:00Z"),  # HST -10, no DST
    ("Europe/Paris", "2024-07-05", "2024-07-04T22:00:00Z"),  # a bare date: local midnight
]


@pytest.mark.parametrize("zone, local, utc", LOCAL_CASES)
def test_naive_time_in_a_zone(zone, local, utc):
    assert _iso(to_time(local, zone=ZoneInfo(zone))) == utc
    naive = dt.datetime.fromisoformat(local)
    assert _iso(to_time(naive, zone=ZoneInfo(zone))) == utc  # a naive datetime the same


def test_a_time_with_an_offset_or_z_ignores_the_zone():
    paris = ZoneInfo("Europe/Paris")
    for text in ("2024-07-05T21:30Z", "2024-07-05T23:30+02:00", "2024-07-05T17:30-04:00"):
        assert _iso(to_time(text, zone=paris)) == "2024-07-05T21:30:00Z"
    aware = dt.datetime(2024, 7, 5, 21, 30, tzinfo=dt.timezone.utc)
    assert _iso(to_time(aware, zone=paris)) == "2024-07-05T21:30:00Z"
    # instants, never local: datetime64 and Julian Dates
    assert _iso(to_time(np.datetime64("2024-07-05T21:30"), zone=paris)) == "2024-07-05T21:30:00Z"
    jd = float(to_time("2024-07-05T21:30Z").jd_utc)
    assert _iso(to_time(jd, zone=paris)) == "2024-07-05T21:30:00Z"
    assert _iso(to_time("2024-07-05T23:30")) == "2024-07-05T23:30:00Z"  # no zone: UTC


def test_gap_and_fold_are_refused_with_the_offsets():
    """2024-03-31 the French clocks go from 02:00 CET to 03:00 CEST (02:30 never happens);
    2024-10-27 from 03:00 CEST back to 02:00 CET (02:30 happens twice)."""
    paris = ZoneInfo("Europe/Paris")
    with pytest.raises(LocalTimeError) as gap:
        to_time("2024-03-31T02:30", zone=paris)
    msg = str(gap.value)
    assert "does not exist in Europe/Paris" in msg and "UTC+01:00 to UTC+02:00" in msg
    with pytest.raises(LocalTimeError) as fold:
        to_time("2024-10-27T02:30", zone=paris)
    msg = str(fold.value)
    assert "ambiguous in Europe/Paris" in msg and "+02:00" in msg and "+01:00" in msg
    # either side, with its offset
    assert _iso(to_time("2024-10-27T02:30+02:00", zone=paris)) == "2024-10-27T00:30:00Z"
    assert _iso(to_time("2024-10-27T02:30+01:00", zone=paris)) == "2024-10-27T01:30:00Z"
    # the minutes just outside are fine
    assert _iso(to_time("2024-03-31T03:00", zone=paris)) == "2024-03-31T01:00:00Z"
    assert _iso(to_time("2024-10-27T03:00", zone=paris)) == "2024-10-27T02:00:00Z"
    # southern hemisphere: Chile's clocks go back from 24:00 to 23:00 on 2024-04-06
    with pytest.raises(LocalTimeError, match="ambiguous in America/Santiago"):
        to_time("2024-04-06T23:30", zone=ZoneInfo("America/Santiago"))


def test_format_local():
    malta = ZoneInfo("Europe/Malta")
    t = to_time("2018-03-01T19:00Z")
    assert format_local(t, malta) == "2018-03-01 20:00:00 CET (UTC+01:00)"
    assert format_local(t, None) == "2018-03-01 19:00:00 UTC"
    assert format_local(to_time("2024-07-05T21:30Z"), ZoneInfo("Europe/Paris")).endswith(
        "23:30:00 CEST (UTC+02:00)"
    )


# ---------------------------------------------------------------- the Python API


def test_sky_description_reads_a_naive_time_in_the_place_zone():
    local = SkyDescription.of("Valletta", "2018-03-01T20:00")
    assert local.timezone == "Europe/Malta"
    assert local.time.jd_utc == SkyDescription.of("Valletta", "2018-03-01T19:00Z").time.jd_utc
    assert _iso(SkyDescription.of("Valletta", "2018-03-01T20:00", utc=True).time) == (
        "2018-03-01T20:00:00Z"
    )
    # a position as numbers has no zone: UTC
    numbers = SkyDescription.of((35.8989, 14.5146), "2018-03-01T20:00")
    assert numbers.timezone == "" and _iso(numbers.time) == "2018-03-01T20:00:00Z"
    # the southern hemisphere's summer time
    paranal = SkyDescription.of("Paranal", "2024-01-15T22:00")
    assert _iso(paranal.time) == "2024-01-16T01:00:00Z"
    # with_ keeps the rule: the description's zone, a new place's zone
    assert _iso(local.with_(time="2018-03-01T23:00").time) == "2018-03-01T22:00:00Z"
    moved = local.with_(place="Paranal", time="2018-03-01T23:00")
    assert moved.timezone == "America/Santiago"
    assert _iso(moved.time) == "2018-03-02T02:00:00Z"  # Chile's summer time, UTC-3
    with pytest.raises(LocalTimeError):
        SkyDescription.of("Paris", "2024-03-31T02:30")
    with pytest.raises(ParameterError, match="time zone"):
        SkyDescription(timezone="Mars/Olympus_Mons")


# ---------------------------------------------------------------- the command line


@pytest.mark.gl
def test_render_local_time_is_the_same_frame_as_utc(tmp_path):
    """The issue's check: --place Valletta --time 2018-03-01T20:00 (CET) renders the frame
    of --time 2018-03-01T19:00Z, bit for bit (PNG and EXR); --utc with 19:00 too."""
    runs = {
        "local": ["--time", "2018-03-01T20:00"],
        "utc_z": ["--time", "2018-03-01T19:00Z"],
        "utc_flag": ["--time", "2018-03-01T19:00", "--utc"],
    }
    outputs = {}
    for name, when in runs.items():
        png, exr = tmp_path / f"{name}.png", tmp_path / f"{name}.exr"
        r = run_cli("render", "--place", "Valletta", *when, "--size", "64x36", "-o", png, "-o", exr)
        assert r.returncode == 0, r.stderr
        outputs[name] = (png.read_bytes(), exr.read_bytes(), r)
    for name in ("utc_z", "utc_flag"):
        assert np.array_equal(
            np.asarray(Image.open(tmp_path / "local.png")),
            np.asarray(Image.open(tmp_path / f"{name}.png")),
        )
        # the EXR's pixels bit for bit (its header holds the render's timing)
        assert _exr_pixels(tmp_path / "local.exr") == _exr_pixels(tmp_path / f"{name}.exr")
    local_err = outputs["local"][2].stderr
    assert (
        "time: 2018-03-01 20:00:00 CET (UTC+01:00, Europe/Malta) = 2018-03-01 19:00:00 UTC"
        in local_err
    )
    assert "time:" not in outputs["local"][2].stdout  # stdout stays the report's


def _exr_pixels(path) -> bytes:
    from skydome.io import read_exr

    return np.ascontiguousarray(read_exr(path)[0]).tobytes()


@pytest.mark.parametrize(
    "args, needles",
    [
        (["--place", "Paris", "--time", "2024-03-31T02:30"], ["--time", "does not exist"]),
        (["--place", "Paris", "--time", "2024-10-27T02:30"], ["--time", "ambiguous"]),
        (["--place", "Paris", "--time", "noon"], ["--time 'noon'", "local time"]),
    ],
)
def test_render_refuses_a_time_the_clocks_skip(tmp_path, args, needles):
    out = tmp_path / "x.png"
    r = run_cli("render", *args, "-o", out)
    assert r.returncode == 2, r
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("skydome: error: "), r.stderr
    for needle in needles:
        assert needle in lines[0], lines[0]
    assert not out.exists()


def test_every_command_with_a_time_says_so_in_its_help():
    for command, flag_words in (
        ("render", ["local time", "--utc"]),
        ("view", ["local time", "--utc"]),
        ("illuminance", ["local time", "--utc"]),
        ("timelapse", ["local time", "--utc"]),
        ("ephemeris", ["local time", "--utc", "--place"]),
        ("events", ["local time", "--utc", "--place"]),
    ):
        r = run_cli(command, "--help")
        assert r.returncode == 0, (command, r.stderr)
        text = " ".join(r.stdout.split())
        for word in flag_words:
            assert word in text, (command, word)


def test_ephemeris_takes_a_place_and_shows_local_time():
    """Paris, 2024-07-05 23:30 CEST: the same positions as 21:30Z at the place's position;
    the time line on stderr, JSON alone on stdout."""
    r = run_cli("ephemeris", "--place", "Paris", "--time", "2024-07-05T23:30", "--bodies",
                "sun", "--json")  # fmt: skip
    assert r.returncode == 0, r.stderr
    local = json.loads(r.stdout)
    assert local["time_utc"] == "2024-07-05T21:30:00Z"
    assert local["time_local"] == "2024-07-05 23:30:00 CEST (UTC+02:00)"
    assert local["timezone"] == "Europe/Paris"
    assert r.stderr.strip() == (
        "time: 2024-07-05 23:30:00 CEST (UTC+02:00, Europe/Paris) = 2024-07-05 21:30:00 UTC"
    )
    u = run_cli("ephemeris", "--lat", "48.8566", "--lon", "2.3522", "--elevation", "35",
                "--time", "2024-07-05T21:30", "--bodies", "sun", "--json")  # fmt: skip
    assert u.returncode == 0, u.stderr
    assert json.loads(u.stdout)["sun"] == local["sun"]
    assert "without an offset is UTC" in u.stderr
    both = run_cli(
        "ephemeris", "--place", "Paris", "--lat", "1", "--lon", "2", "--time", "2024-07-05"
    )
    assert both.returncode == 2 and "--place and --lat/--lon" in both.stderr


def test_events_take_a_place_and_show_local_times():
    """Sydney, 2024-01-15 (AEDT, UTC+11): the day runs from local midnight (13:00 UTC the day
    before), and every row's local time is its UTC time plus 11 h."""
    r = run_cli("events", "--place", "Sydney", "--date", "2024-01-15", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["timezone"] == "Australia/Sydney"
    rows = [e for e in out["events"] if not e.get("all_day")]
    assert rows and all("time_local" in e for e in rows)
    first = dt.datetime(2024, 1, 14, 13, tzinfo=dt.timezone.utc)
    for e in rows:
        utc = dt.datetime.fromisoformat(e["time"].replace("Z", "+00:00"))
        local = dt.datetime.fromisoformat(e["time_local"])
        assert local.utcoffset() == dt.timedelta(hours=11) and local == utc
        assert first <= utc < first + dt.timedelta(days=1)
    sunset = next(e for e in rows if e["event"] == "sunset")
    # Sydney's sunset on 2024-01-15 is at 20:09 AEDT (Geoscience Australia's and
    # timeanddate.com's tables, to the minute): within a minute of it.
    at = dt.datetime.fromisoformat(sunset["time_local"])
    assert abs(at - dt.datetime(2024, 1, 15, 20, 9, 30, tzinfo=at.tzinfo)) < dt.timedelta(
        seconds=90
    )
    table = run_cli("events", "--place", "Sydney", "--date", "2024-01-15")
    assert table.returncode == 0 and "AEDT" in table.stdout and "Australia/Sydney" in table.stdout
    assert "time: 2024-01-15 00:00:00 AEDT (UTC+11:00, Australia/Sydney)" in table.stderr


@pytest.mark.gl
def test_timelapse_range_is_local_too(tmp_path):
    """--start/--end without an offset are the place's local time: the frames of 20:00-20:02
    CET at Valletta are those of 19:00-19:02Z, and the line on stderr gives both ends."""
    frames = {}
    for name, (start, end) in {
        "local": ("2018-03-01T20:00", "2018-03-01T20:02"),
        "utc": ("2018-03-01T19:00Z", "2018-03-01T19:02Z"),
    }.items():
        folder = tmp_path / name
        r = run_cli("timelapse", "--place", "Valletta", "--start", start, "--end", end,
                    "--step", "1min", "--size", "32x18", "--exposure", "0", "--format", "npy",
                    "-o", folder)  # fmt: skip
        assert r.returncode == 0, r.stderr
        frames[name] = [np.load(p) for p in sorted(folder.glob("*.npy"))]
        if name == "local":
            assert (
                "time: 2018-03-01 20:00:00 CET (UTC+01:00, Europe/Malta) = 2018-03-01 19:00:00 "
                "UTC to 2018-03-01 20:02:00 CET" in r.stderr
            ), r.stderr
    assert len(frames["local"]) == 3
    for a, b in zip(frames["local"], frames["utc"], strict=True):
        assert np.array_equal(a, b)
