"""Events against skyfield's almanac; the ephemeris/events commands; Observer API."""

import json
import subprocess
import sys

import numpy as np
import pytest
from _astro_oracles import skyfield

from skydome.astro import Observer, events
from skydome.astro.time import julian_date
from skydome.errors import ParameterError


def _utc_jd(t):
    u = t.utc
    return julian_date(u.year, u.month, u.day, u.hour, u.minute, u.second)


@pytest.mark.parametrize(
    "lat, lon, date",
    [(52.0, 4.3, "2021-03-01"), (-33.9, 18.4, "1995-07-10"), (64.8, -147.7, "2010-12-01")],
)
def test_events_match_skyfield_almanac(lat, lon, date):
    """Rise/set/transit of Sun and Moon and Moon phases against skyfield + DE421.

    Measured (these three sites and weeks): Sun 0.0014 min (0.09 s), Moon 0.0062 min
    (0.4 s: Meeus' ELP truncation, a few arcseconds, at the Moon's ~15"/s of hour angle),
    phases 0.124 min (7 s: the Moon's longitude error at its 0.5"/s elongation rate).
    Bounds: 0.005, 0.02 and 0.25 min. The bisection itself is good to 0.04 s."""
    from skyfield import almanac
    from skyfield.api import wgs84

    ts, eph = skyfield()
    days = 8
    ev = events(Observer(lat, lon), date, days)
    y, m, d = map(int, date.split("-"))
    t0, t1 = ts.utc(y, m, d), ts.utc(y, m, d + days)
    site = eph["earth"] + wgs84.latlon(lat, lon)
    for body in ("sun", "moon"):
        refs = {
            f"{body}rise" if body == "moon" else "sunrise": almanac.find_risings(
                site, eph[body], t0, t1
            )[0],
            f"{body}set": almanac.find_settings(site, eph[body], t0, t1)[0],
            "transit": almanac.find_transits(site, eph[body], t0, t1),
        }
        for kind, ref in refs.items():
            ours = ev.jd_utc[(ev.kind == kind) & (ev.body == body)]
            ref_jd = _utc_jd(ref)
            assert ours.size == ref_jd.size, (body, kind)
            bound_min = 0.005 if body == "sun" else 0.02
            assert np.abs(np.sort(ours) - np.sort(ref_jd)).max() * 1440 < bound_min, (body, kind)
    tp, _ = almanac.find_discrete(t0, t1, almanac.moon_phases(eph))
    ours = ev.jd_utc[np.isin(ev.kind, ["new_moon", "first_quarter", "full_moon", "last_quarter"])]
    assert ours.size == len(tp)
    assert np.abs(ours - _utc_jd(tp)).max() * 1440 < 0.25


def test_twilight_order_and_polar_day():
    ev = events(Observer(40.0, -3.7), "2024-03-20", 1)
    order = [k for k in ev.kind if k.endswith("dawn") or k == "sunrise"]
    assert order == ["astronomical_dawn", "nautical_dawn", "civil_dawn", "sunrise"]
    polar = events(Observer(78.0, 15.0), "2024-06-21", 2)
    assert "sunrise" not in set(polar.kind) and "sunset" not in set(polar.kind)
    assert (polar.kind == "transit").sum() >= 2


def test_observer_validation_and_shapes():
    with pytest.raises(ParameterError, match="latitude = 91"):
        Observer(91, 0)
    with pytest.raises(ParameterError, match="pressure_hPa"):
        Observer(0, 0, pressure_hPa=-5)
    with pytest.raises(ParameterError, match="unknown body"):
        Observer(0, 0).sky("2024-01-01", bodies=("pluto",))
    times = np.array(
        ["2024-01-01T00:00", "2024-06-01T12:00", "2030-02-03T04:05"], dtype="datetime64[s]"
    )
    sky = Observer(np.array([[10.0], [-45.0]]), 20.0).sky(times, bodies="sun,moon,venus")
    for name in ("sun", "moon", "venus"):
        p = sky[name]
        assert p.alt.shape == (2, 3) and p.enu.shape == (2, 3, 3)
        for v in (p.alt, p.az, p.ra, p.dec, p.distance_km, p.illuminance_lux, p.enu):
            assert np.all(np.isfinite(v))
        assert np.all(p.alt >= p.alt_unrefracted)
    assert np.all((sky["moon"].illuminated_fraction >= 0) & (sky["moon"].illuminated_fraction <= 1))


def test_stars_optional():
    pytest.importorskip("skydome.astro.stars")
    sky = Observer(45.0, 7.0).sky(
        ["2024-01-01T22:00Z"], bodies=("sun", "Sirius"), stars=True, star_mag_limit=3.0
    )
    assert sky.stars is not None and sky.stars.alt.shape[0] == 1 and sky.stars.alt.shape[1] > 50
    assert np.all(np.isfinite(sky.stars.enu))
    assert float(sky["Sirius"].magnitude[0]) == pytest.approx(-1.46, abs=0.05)


def run(*args):
    return subprocess.run(
        [sys.executable, "-m", "skydome", *args], capture_output=True, text=True, timeout=120
    )


def test_cli_ephemeris_json():
    res = run(
        "ephemeris",
        "--lat",
        "39.742476",
        "--lon",
        "-105.1786",
        "--time",
        "2003-10-17T19:30:30Z",
        "--bodies",
        "sun,moon,jupiter",
        "--json",
    )
    assert res.returncode == 0, res.stderr
    data = json.loads(res.stdout)
    for body in ("sun", "moon", "jupiter"):
        for key in (
            "alt",
            "alt_unrefracted",
            "az",
            "ra",
            "dec",
            "distance_km",
            "illuminance_lux",
            "magnitude",
        ):
            assert key in data[body]
    assert "phase_angle" in data["moon"] and "illuminated_fraction" in data["moon"]
    assert data["sun"]["az"] == pytest.approx(194.34, abs=0.01)
    assert data["sun"]["alt"] > data["sun"]["alt_unrefracted"]


def test_cli_events_json():
    res = run(
        "events", "--lat", "52", "--lon", "4.3", "--date", "2024-06-21", "--days", "2", "--json"
    )
    assert res.returncode == 0, res.stderr
    kinds = [e["event"] for e in json.loads(res.stdout)["events"]]
    assert kinds.count("sunrise") == 2 and "full_moon" in kinds


@pytest.mark.parametrize(
    "args",
    [
        ("ephemeris", "--lat", "91", "--lon", "0", "--time", "2024-01-01"),
        ("ephemeris", "--lat", "10", "--lon", "0", "--time", "not-a-time"),
        ("ephemeris", "--lat", "10", "--lon", "0", "--time", "2024-01-01", "--bodies", "pluto"),
        ("events", "--lat", "10", "--lon", "0", "--date", "2024-02-30"),
    ],
)
def test_cli_bad_input(args):
    res = run(*args)
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert (
        len(lines) == 1 and lines[0].startswith("skydome: error:") and "Traceback" not in res.stderr
    )
