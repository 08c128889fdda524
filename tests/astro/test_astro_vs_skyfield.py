"""1000 random times (1900-2050) and observers against skyfield + DE421.

Both sides use the same TT and UT1 (skyfield's), so that only the ephemerides and the
reduction to the observer are compared. skyfield's ``altaz()`` without temperature and
pressure is airless, compared with our ``alt_unrefracted``; refraction is checked
separately.
"""

import numpy as np
import pytest
from _astro_oracles import ARCSEC, SKYFIELD_NAMES, skyfield

from skydome.astro import Observer
from skydome.astro.time import Time

N = 1000


@pytest.fixture(scope="module")
def comparison():
    from skyfield.api import wgs84

    ts, eph = skyfield()
    rng = np.random.default_rng(2024)
    jd = 2415020.5 + rng.random(N) * (2469807.5 - 2415022.5)
    lat = np.degrees(np.arcsin(rng.uniform(-1, 1, N)))
    lon = rng.uniform(-180, 180, N)
    h = rng.uniform(0, 3000, N)
    t = ts.tt_jd(jd)
    sky = Observer(lat, lon, h, pressure_hPa=0.0).sky(
        Time(t.ut1, t.ut1, t.tt), bodies=tuple(SKYFIELD_NAMES)
    )
    site = eph["earth"] + wgs84.latlon(lat, lon, elevation_m=h)
    out = {}
    for body, name in SKYFIELD_NAMES.items():
        app = site.at(t).observe(eph[name]).apparent()
        alt, az, dist = app.altaz()
        a, z = np.radians(alt.degrees), np.radians(az.degrees)
        ref = np.stack([np.cos(a) * np.sin(z), np.cos(a) * np.cos(z), np.sin(a)], axis=-1)
        ours = sky[body].enu_unrefracted
        sep = np.arccos(np.clip(np.sum(ref * ours, axis=-1), -1, 1)) * ARCSEC
        if body not in ("sun", "moon"):
            # both deflect light by the Sun (tests/astro/test_planet_deflection.py); for a
            # planet behind the solar disk skyfield's formula diverges (30" seen for
            # Jupiter 0.01 deg from the Sun's centre; ours is floored), so skip
            # elongations < 1 deg.
            elong = np.degrees(np.arccos(np.sum(ours * sky["sun"].enu_unrefracted, axis=-1)))
            valid = elong >= 1.0
        else:
            valid = np.ones(N, dtype=bool)
        sep = sep[valid]
        out[body] = (sep, sky[body], a, z, dist.km, app, valid)
    return out, t, site, sky


@pytest.mark.parametrize(
    "body, max_arcsec, rms_arcsec",
    [
        # Sun: the issue asks 1" (measured 0.4" max, 0.14" RMS: VSOP87 truncation 0.27",
        # IAU 1980 vs 2000A nutation 0.01", heliocentric vs barycentric velocity 0.01")
        ("sun", 1.0, 0.3),
        # Moon: ELP/MPP02 truncated at 0.003" (0.16" max, 0.035" RMS from the complete
        # series, tools/build_moon_elpmpp02.py; geocentric 0.23" / 0.05" from DE421,
        # test_moon_elpmpp02.py) plus the reduction to the observer (the Sun's 0.4" shows
        # its size): measured 0.41" max, 0.15" RMS (Meeus' truncation was 10" / 3")
        ("moon", 0.8, 0.3),
        # planets: the issue asks 30"; our VSOP87 truncation gives < 5" (measured 4.3"),
        # so 10" catches regressions while allowing for unsampled worst cases
        ("mercury", 10.0, 3.0),
        ("venus", 10.0, 3.0),
        ("mars", 10.0, 3.0),
        ("jupiter", 10.0, 3.0),
        ("saturn", 10.0, 3.0),
        ("uranus", 10.0, 3.0),
        ("neptune", 10.0, 3.0),
    ],
)
def test_positions(comparison, body, max_arcsec, rms_arcsec):
    out, *_ = comparison
    sep, pos, a, z, dist_km, _, ok = out[body]
    assert sep.max() < max_arcsec, f'{body}: max {sep.max():.2f}"'
    assert np.sqrt(np.mean(sep**2)) < rms_arcsec
    # altitude and azimuth separately (azimuth scaled by cos(alt))
    dalt = np.abs(pos.alt_unrefracted - a)[ok] * ARCSEC
    daz = (np.abs((pos.az - z + np.pi) % (2 * np.pi) - np.pi) * np.cos(a))[ok] * ARCSEC
    assert dalt.max() < max_arcsec and daz.max() < max_arcsec
    # distances: Moon 2 km (ELP/MPP02 truncated at 0.01 km: 0.3 km; measured 0.8 km =
    # 2.2e-6 topocentric), others 2e-5 relative
    rel = np.abs(pos.distance_km / dist_km - 1)
    assert rel.max() < (5e-6 if body == "moon" else 2e-5)
    assert np.all(np.isfinite(pos.enu)) and np.allclose(np.linalg.norm(pos.enu, axis=-1), 1)


def test_refraction_vs_skyfield(comparison):
    """Our Saemundsson true->apparent against skyfield's inverted Bennett formula, same
    weather (1010 hPa, 10 C), for bodies above -0.5 deg: within 5" (Meeus: the two agree to
    4"; measured 3.5")."""
    out, t, site, _ = comparison
    from skydome.astro import frames

    _, pos, a, z, _, app, _ = out["sun"]
    alt_ref, _, _ = app.altaz(temperature_C=10.0, pressure_mbar=1010.0)
    ok = np.degrees(a) > -0.5
    ours = np.degrees(a) + frames.refraction_saemundsson(np.degrees(a), 1010.0, 10.0) / 60.0
    diff = np.abs(ours - alt_ref.degrees)[ok] * 3600
    assert ok.sum() > 300 and diff.max() < 5.0
