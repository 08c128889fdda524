"""Lunar eclipses: the contacts of 2022-11-08 (DE421 and the published ones), the Moon in
the Earth's umbra through Sky.render (its brightness, colour and Danjon L), and the
eclipses that ``skydome events`` lists.

Independent references: skyfield with DE421 (skyfield-data, offline) for the geocentric
positions; NASA's circumstances of the 2022-11-08 eclipse (Espenak, eclipse.gsfc.nasa.gov:
P1 08:02:17, U1 09:09:12, U2 10:16:39, U3 11:41:38, U4 12:49:03, P4 13:56:09 UT); the
observed brightness of totally eclipsed Moons (1e-3..1e-5 of the full Moon, red).
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from skydome.astro.eclipses import (
    danjon_from_luminance_ratio,
    earth_shadow_radii,
    lunar_contacts,
)
from skydome.astro.time import to_time
from tests.cli_helpers import run_cli
from tests.roots import bisect_root

MID_TOTALITY = "2022-11-08T10:59:06Z"


def _jd(iso: str) -> float:
    return float(np.ravel(to_time(iso).jd_utc)[0])


def _de421_axis_distance(jd_utc):
    """Geocentric apparent distance of the Moon's centre from the antisolar point, the
    Moon's semidiameter and the shadow's radii (rad), from DE421, Danjon's radii."""
    warnings.filterwarnings("ignore", message=".*has expired.*")
    from skyfield.api import Loader
    from skyfield_data import get_skyfield_data_path

    from skydome.astro.moon import MOON_RADIUS_KM

    load = Loader(get_skyfield_data_path())
    ts, eph = load.timescale(builtin=True), load("de421.bsp")
    t = ts.ut1_jd(float(jd_utc))
    earth = eph["earth"].at(t)
    s = earth.observe(eph["sun"]).apparent()
    m = earth.observe(eph["moon"]).apparent()
    d = np.pi - s.separation_from(m).radians
    umbra, penumbra = earth_shadow_radii(m.distance().km, s.distance().km)
    return d, np.arcsin(MOON_RADIUS_KM / m.distance().km), umbra, penumbra


def test_contacts_2022_11_08_vs_de421_and_published():
    c = lunar_contacts(MID_TOTALITY)
    assert c is not None and c.kind == "total"
    ours = {"P1": c.p1, "U1": c.u1, "U2": c.u2, "U3": c.u3, "U4": c.u4, "P4": c.p4}

    def edge(kind):
        def f(jd):
            d, rm, um, pen = _de421_axis_distance(jd)
            return float(d - {"P": pen + rm, "U": um + rm, "T": um - rm}[kind])

        return f

    kinds = {"P1": "P", "U1": "U", "U2": "T", "U3": "T", "U4": "U", "P4": "P"}
    m = 2 / 1440
    err = {
        k: (ours[k] - bisect_root(edge(kinds[k]), ours[k] - m, ours[k] + m, xtol=1e-9)) * 86400
        for k in ours
    }
    print("lunar contacts minus DE421 (s):", {k: round(v, 2) for k, v in err.items()})
    # the same shadow (Danjon) on both sides: only the Moon's place differs (2-3" here, the
    # Moon crossing the shadow at ~0.5"/s: ~5 s); 10 s bounds it
    assert all(abs(v) < 10.0 for v in err.values()), err
    published = {
        "P1": "08:02:17", "U1": "09:09:12", "U2": "10:16:39",
        "U3": "11:41:38", "U4": "12:49:03", "P4": "13:56:09",
    }  # fmt: skip
    off = {k: (ours[k] - _jd(f"2022-11-08T{v}Z")) * 86400 for k, v in published.items()}
    print("lunar contacts minus NASA (s):", {k: round(v, 1) for k, v in off.items()})
    # NASA's shadow is Danjon's too, but their Earth radius and flattening differ slightly
    # (a 0.1 % larger shadow moves the contacts by ~15 s): 30 s
    assert all(abs(v) < 30.0 for v in off.values()), off


def test_umbra_light_is_red_from_the_atmosphere():
    """The refracted light at the shadow's centre and half-way out: a fraction of 1e-6..1e-2
    of direct sunlight, red over green over blue (the limb path's Rayleigh and ozone
    transmittance of the ``earth`` preset)."""
    from skydome.scene.eclipses import umbra_light

    wl = np.array([450.0, 550.0, 650.0])
    f = umbra_light(wl, 378000.0, 0.00466, np.array([0.0, 2300.0, 4000.0]))
    assert np.all(f[:2, 2] > f[:2, 1]) and np.all(f[:2, 1] > f[:2, 0])
    assert np.all((f[:, 1] > 1e-7) & (f[:, 1] < 1e-2))
    assert f[2, 1] > f[0, 1]  # brighter towards the umbra's edge (higher, clearer rays)
    # near the edge the rays pass above most of the air but through the ozone layer, whose
    # Chappuis band takes green and orange: the blue-turquoise fringe (blue ~ green there)
    assert f[2, 0] > 0.5 * f[2, 1]


@pytest.mark.gl
def test_moon_at_mid_totality_through_sky_render(monkeypatch):
    """A close-up of the Moon at Dallas at mid-totality: 1e-3..1e-5 of the uneclipsed Moon
    at the same place and time (the same render with the shadow taken out), R > G > B, and a
    Danjon L reported."""
    import skydome.scene.state as state_mod
    from skydome import Sky

    def render():
        with Sky("Dallas", MID_TOTALITY, light_pollution=None, night=False) as sky:
            cam = sky.camera("moon", fov_deg=1.0)
            data = sky.render(cam, 160, 120, exposure=None).data.astype(float)
            return data, sky.state

    eclipsed, state = render()
    assert state.lunar_eclipse is not None
    monkeypatch.setattr(state_mod, "lunar_eclipse_view", lambda *a, **k: None)
    full, _ = render()
    assert np.all(np.isfinite(eclipsed))
    y = np.array([0.2126, 0.7152, 0.0722])
    lum_full = full[..., :3] @ y
    disk = lum_full > 0.3 * np.median(lum_full[lum_full > np.percentile(lum_full, 90)])
    assert 0.2 < disk.mean() < 0.8  # the Moon fills part of the frame
    background = eclipsed[~disk].mean(axis=0)
    moon = eclipsed[disk].mean(axis=0) - background
    moon_full = full[disk].mean(axis=0) - full[~disk].mean(axis=0)
    ratio = float(moon[:3] @ y) / float(moon_full[:3] @ y)
    danjon = float(danjon_from_luminance_ratio(ratio))
    r, g, b = moon[:3]
    print(
        f"mid-totality Moon: {ratio:.3g} of the full Moon, R:G:B = {r / g:.3g}:1:{b / g:.3g}, "
        f"Danjon L = {danjon:.2f}"
    )
    assert 1e-5 < ratio < 1e-3
    assert r > g > b > 0.0
    assert state.lunar_eclipse.moon_light_factor == pytest.approx(ratio, rel=0.3)


def test_events_lists_the_eclipses_with_contacts():
    res = run_cli("events", "--place", "Dallas", "--date", "2022-11-08", "--json")
    assert res.returncode == 0, res.stderr
    rows = json.loads(res.stdout)["events"]
    lunar = {r["event"]: r for r in rows if r["event"].startswith("lunar_eclipse_")}
    assert set(lunar) == {f"lunar_eclipse_{k}" for k in ("P1", "U1", "U2", "max", "U3", "U4", "P4")}
    assert "Moon at" in lunar["lunar_eclipse_U2"]["note"]
    res = run_cli("events", "--place", "Dallas", "--date", "2024-04-08", "--json")
    solar = [r for r in json.loads(res.stdout)["events"] if r["event"].startswith("solar_")]
    assert [r["event"][-2:] for r in solar] == ["C1", "C2", "ax", "C3", "C4"]
    assert solar[0]["time"].startswith("2024-04-08T17:23")
    # Paris saw neither: the solar eclipse was below its horizon, the lunar one by day
    res = run_cli("events", "--place", "Paris", "--date", "2024-04-08", "--json")
    assert not [r for r in json.loads(res.stdout)["events"] if "eclipse" in r["event"]]
