"""Solar eclipses: the occulted, limb-darkened fraction, the contacts, the sky and the
illuminance of the total eclipse of 2024-04-08 at Dallas.

Independent references: skyfield with the DE421 kernel of skyfield-data (offline, as in
tests/astro) for the positions and the contacts; a brute-force sum over the Sun's disk for
the occulted fraction; the measured illuminance in totality (1-10 lx: e.g. Darula et al.
2017 and the 2024 NASA/citizen-science light-meter reports).
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

from skydome.astro import Observer
from skydome.astro.eclipses import (
    disk_overlap_fraction,
    occulted_fraction,
    sky_sunlit_weight,
    solar_contacts,
)
from skydome.astro.moon import MOON_RADIUS_KM
from skydome.astro.sun import SUN_RADIUS_KM
from skydome.celestial.limb_darkening import limb_coefficients
from skydome.scene.eclipses import luminous_hidden_fraction
from tests.cli_helpers import run_cli
from tests.roots import bisect_root

# Dallas as in the gazetteer (src/skydome/data/places.csv)
DALLAS = dict(latitude=32.7767, longitude=-96.7970, elevation_m=131.0)
TOTALITY = "2024-04-08T18:42:45Z"


def _skyfield():
    warnings.filterwarnings("ignore", message=".*has expired.*")
    from skyfield.api import Loader
    from skyfield_data import get_skyfield_data_path

    load = Loader(get_skyfield_data_path())
    return load.timescale(builtin=True), load("de421.bsp")


def _de421_disks(jd_utc):
    """Topocentric apparent separation and angular radii (rad) of the Sun and the Moon at
    Dallas from DE421, with the same radii (km) as skydome."""
    from skyfield.api import wgs84

    ts, eph = _skyfield()
    t = ts.ut1_jd(np.asarray(jd_utc, float) + 0.0)  # UT1 ~ UTC to < 0.1 s in 2024
    site = eph["earth"] + wgs84.latlon(
        DALLAS["latitude"], DALLAS["longitude"], DALLAS["elevation_m"]
    )
    s = site.at(t).observe(eph["sun"]).apparent()
    m = site.at(t).observe(eph["moon"]).apparent()
    sep = s.separation_from(m).radians
    rs = np.arcsin(SUN_RADIUS_KM / s.distance().km)
    rm = np.arcsin(MOON_RADIUS_KM / m.distance().km)
    return sep, rs, rm


def _jd(iso: str) -> float:
    from skydome.astro.time import to_time

    return float(np.ravel(to_time(iso).jd_utc)[0])


# ----------------------------------------------------------------- the occulted fraction


def _brute_force(z, p, coeffs, n=3000):
    """Fraction hidden of a limb-darkened unit disk by a disk of radius p at z: midpoint sum
    on a polar grid (n x n), independent of the quadrature in occulted_fraction."""
    r = (np.arange(n) + 0.5) / n
    phi = (np.arange(n) + 0.5) / n * 2 * np.pi
    mu = np.sqrt(1 - r * r)
    law = np.polyval(coeffs[::-1], mu)
    x = r[:, None] * np.cos(phi)
    y = r[:, None] * np.sin(phi)
    inside = (x - z) ** 2 + y**2 < p * p
    w = (law * r)[:, None]
    return float(np.sum(w * inside) / (np.sum(w) * n))


@pytest.mark.parametrize(
    "z, p",
    [(1.0, 1.03), (0.5, 0.97), (0.05, 0.95), (1.5, 1.02), (0.3, 1.05), (1.9, 0.99)],
)
def test_occulted_fraction_matches_a_brute_force_sum(z, p):
    # 3000 x 3000 midpoint sums converge to ~1e-5 (the disk's edge); Neckel's 550 nm law
    coeffs = limb_coefficients(np.array([550.0]))[0]
    ours = float(occulted_fraction(z * 0.00465, 0.00465, p * 0.00465, coeffs))
    ref = _brute_force(z, p, coeffs)
    assert ours == pytest.approx(ref, abs=3e-4)


def test_uniform_fraction_is_the_lens_area():
    # a uniform disk: the closed form of two circles' lens (to the quadrature's 1e-9)
    z = np.linspace(0.0, 2.1, 50) * 0.00465
    ours = occulted_fraction(z, 0.00465, 0.0048)
    assert np.allclose(ours, disk_overlap_fraction(z, 0.00465, 0.0048), atol=1e-9)
    # limb darkening hides more when the Moon covers the bright centre, less at the limb
    coeffs = limb_coefficients(np.array([550.0]))[0]
    dark = occulted_fraction(np.array([0.0, 0.85]) * 0.00465, 0.00465, 0.3 * 0.00465, coeffs)
    flat = occulted_fraction(np.array([0.0, 0.85]) * 0.00465, 0.00465, 0.3 * 0.00465)
    assert dark[0] > flat[0] * 1.2 and dark[1] < flat[1]


# ----------------------------------------------------------------- contacts (DE421)


def _contact_errors() -> dict[str, float]:
    """Our contacts at Dallas minus DE421's (s), both topocentric apparent with the same
    radii; DE421's by bisection within 30 s of ours."""
    c = solar_contacts(Observer(**DALLAS), TOTALITY)
    assert c is not None and c.kind == "total"

    def outer(jd):
        sep, rs, rm = _de421_disks(jd)
        return float(sep - rs - rm)

    def inner(jd):
        sep, rs, rm = _de421_disks(jd)
        return float(sep - abs(rs - rm))

    m = 30 / 86400  # C2 and C3 are 4 minutes apart: 30 s brackets
    ours = {"C1": c.c1, "C2": c.c2, "C3": c.c3, "C4": c.c4}
    f = {"C1": outer, "C2": inner, "C3": inner, "C4": outer}
    ref = {k: bisect_root(f[k], ours[k] - m, ours[k] + m, xtol=1e-9) for k in ours}
    err = {k: (ours[k] - ref[k]) * 86400 for k in ref}
    print("contact errors vs DE421 (s):", {k: round(v, 2) for k, v in err.items()})
    return err


def test_dallas_contacts_near_de421_and_published():
    # Measured: C1 -0.20 s, C2 +0.06 s, C3 -0.57 s, C4 -0.22 s (Meeus' truncation of
    # ELP2000-82, 2.6" east of DE421 here, gave +4.6..+7.9 s). The disks' separation changes
    # by ~0.45"/s at the contacts, and our topocentric Sun and Moon are within 0.4" and
    # 0.41" of DE421's (tests/astro/test_astro_vs_skyfield.py): 2 s.
    err = _contact_errors()
    assert all(abs(v) < 2.0 for v in err.values()), err
    # and the published circumstances (NASA, Espenak; Dallas: 17:23:19, 18:40:41,
    # 18:44:32, 20:02:43 UTC) within 15 s (their lunar radius for C2/C3 and their place
    # differ from ours)
    c = solar_contacts(Observer(**DALLAS), TOTALITY)
    ours = {"C1": c.c1, "C2": c.c2, "C3": c.c3, "C4": c.c4}
    published = {"C1": "17:23:19", "C2": "18:40:41", "C3": "18:44:32", "C4": "20:02:43"}
    for k, hms in published.items():
        assert abs(ours[k] - _jd(f"2024-04-08T{hms}Z")) * 86400 < 15.0, k


def test_dallas_contacts_within_5_s_of_de421():
    # the requirement (ELP/MPP02: measured within 0.57 s)
    err = _contact_errors()
    assert all(abs(v) < 5.0 for v in err.values()), err


# ----------------------------------------------------------------- the direct sunlight


@pytest.mark.gl
def test_direct_sunlight_factor_through_the_partial_phase_vs_de421():
    """The direct illuminance of ``place_illuminance`` (the CLI's) over the uneclipsed one
    equals the limb-darkened visible fraction from DE421's positions within 2 % (of the
    Sun's flux), through the partial phases."""
    from skydome.atmosphere.illuminance import horizontal_illuminance
    from skydome.eclipse_illuminance import CORONA_FRACTION, place_illuminance
    from skydome.physics.constants import AU_KM
    from skydome.physics.geometry import elevation_deg
    from skydome.scene.state import state_at

    obs = Observer(**DALLAS)
    times = [
        f"2024-04-08T{h}Z"
        for h in ("17:25", "17:40", "18:00", "18:15", "18:30", "18:38", "18:50", "19:30", "20:00")
    ]
    worst = 0.0
    for t in times:
        out = place_illuminance(obs, t)
        state = state_at(obs, t)
        el = elevation_deg(state.sun.direction_true)
        scale = (AU_KM / state.sun.distance_km) ** 2
        (full,) = horizontal_illuminance(el, altitude_m=state.ground_m, sun_scale=scale)
        factor = out["direct_horizontal_lux"] / full.direct_horizontal_lux - CORONA_FRACTION
        sep, rs, rm = _de421_disks(_jd(t))
        ref = 1.0 - float(luminous_hidden_fraction(sep, rs, rm))
        print(f"{t}: direct factor {factor:.5f}, DE421 {ref:.5f}")
        # within 2 % of the Sun's flux all through; within 2 % of the visible part while a
        # fifth of the Sun shows (near C2 the visible sliver changes fast: 1.9 % of the
        # Sun at 18:38, where a second of time is a few per cent of it)
        assert abs(factor - ref) < 0.02, t
        if ref > 0.2:
            worst = max(worst, abs(factor / ref - 1.0))
            assert factor == pytest.approx(ref, rel=0.02), t
        assert out["eclipse_fraction"] == pytest.approx(1.0 - ref, abs=0.02), t
    print(f"worst relative error of the direct factor (>= 20 % visible): {worst:.2e}")


# ----------------------------------------------------------------- totality


@pytest.mark.gl
def test_totality_illuminance_cli_below_10_lux():
    res = run_cli("illuminance", "--place", "Dallas", "--time", TOTALITY, "--json")
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    print("totality:", out)
    assert out["eclipse_fraction"] > 0.9999
    # measured in totality: 1-10 lx (the sky's ring and the corona); ours is the ring lit
    # by single-scattering geometry and the corona, which must not be darker than 0.1 lx
    assert 0.1 < out["total_horizontal_lux"] < 10.0
    assert out["zenith_luminance_cd_m2"] < 1e-3 * 3000.0  # a daytime zenith is ~3000 cd/m^2
    before = run_cli("illuminance", "--place", "Dallas", "--time", "2024-04-08T16:00Z", "--json")
    assert json.loads(before.stdout)["eclipse_fraction"] == 0.0
    assert json.loads(before.stdout)["total_horizontal_lux"] > 5e4


@pytest.mark.gl
def test_totality_sky_dark_overhead_with_a_ring_and_the_twin(monkeypatch):
    """Through Sky.render (equirect): the sky in totality is the uneclipsed sky times the
    sunlit weight of each ray (GLSL eclipse_sky_weight against its float64 twin), dark at
    the zenith, brightest a few degrees above the horizon, redder low down; its horizontal
    illuminance below 10 lx; the Sun's disk hidden and the corona drawn."""
    import skydome.scene.state as state_mod
    from skydome import Sky
    from skydome.atmosphere.layer import RGBS_EFFECTIVE_NM, eclipse_air
    from skydome.atmosphere.presets import preset
    from skydome.core.cameras import EquirectCamera

    w, h = 128, 64
    with Sky("Dallas", TOTALITY, light_pollution=None, night=False) as sky:
        ecl = sky.state.solar_eclipse
        assert ecl is not None and ecl.hidden_fraction > 0.9999
        frame = sky.render(EquirectCamera(), w, h, exposure=None).data.astype(float)
    monkeypatch.setattr(state_mod, "solar_eclipse_view", lambda sun, moon: None)
    with Sky("Dallas", TOTALITY, light_pollution=None, night=False) as sky:
        assert sky.state.solar_eclipse is None
        full = sky.render(EquirectCamera(), w, h, exposure=None).data.astype(float)
        state = sky.state
    assert np.all(np.isfinite(frame))
    el = 90.0 - (np.arange(h) + 0.5) / h * 180.0
    az = (np.arange(w) + 0.5) / w * 360.0
    e, a = np.radians(el)[:, None], np.radians(az)[None, :]
    dirs = np.stack(
        np.broadcast_arrays(np.cos(e) * np.sin(a), np.cos(e) * np.cos(a), np.sin(e)), -1
    )
    params = preset("earth")
    sun = state.sun
    r_km = (params.bottom_radius_m + 131.0 + 1.7) / 1000.0
    weight = sky_sunlit_weight(
        r_km, dirs, ecl.moon_km, ecl.moon_radius_km, sun.direction_true,
        sun.angular_radius_rad, eclipse_air(params), params.bottom_radius_m / 1000.0,
        params.top_radius_m / 1000.0, channels=[(550.0 / x) ** 4 for x in RGBS_EFFECTIVE_NM[:3]],
    )  # fmt: skip
    sky_rows = (el > 1.0) & (el < 60.0)  # away from the Sun's disk (64.6 deg) and the ground
    ratio = frame[sky_rows, :, :3] / full[sky_rows, :, :3]
    ref = weight[sky_rows]
    keep = ref > 1e-3
    err = np.abs(ratio[keep] / ref[keep] - 1.0)
    print(f"GLSL weight vs float64 twin: median {np.median(err):.2e}, max {err.max():.2e}")
    # float32 sums of 48 terms, and the sky-view table's pixel directions vs ours: 2 %
    assert np.median(err) < 0.005 and err.max() < 0.02
    lum = frame[..., :3] @ np.array([0.2126, 0.7152, 0.0722])
    row = lum.mean(axis=1)
    zenith, ring = row[0], row[(el > 1) & (el < 15)].max()
    assert ring > 100 * zenith, (zenith, ring)
    low = (el > 1) & (el < 4)
    assert frame[low, :, 0].mean() > frame[low, :, 2].mean()  # the ring red low down
    up = el > 0
    cos_w = (np.sin(e) * np.cos(e))[up] * (np.pi / h) * (2 * np.pi / w)
    e_sky = float(np.sum(lum[up] * cos_w))
    print(f"sky's horizontal illuminance in totality: {e_sky:.3g} lx")
    assert e_sky < 10.0


@pytest.mark.gl
def test_disk_hidden_and_corona_drawn():
    """A close-up at the Sun in totality: nothing of the photosphere shows; the corona at
    1.1-1.5 solar radii has Baumbach's radiance (1e-6 of the disk's mean) within 10 % after
    the air's transmittance; a partial phase keeps the visible crescent's luminance."""
    from skydome import Sky
    from skydome.astro.eclipses import baumbach_corona
    from skydome.core.cameras import PerspectiveCamera

    with Sky("Dallas", TOTALITY, light_pollution=None, night=False) as sky:
        sun = sky.state.sun
        cam = sky.camera("sun", fov_deg=2.0)
        frame = sky.render(cam, 200, 200, exposure=None).data.astype(float)
        assert isinstance(cam, PerspectiveCamera)
    lum = frame[..., :3] @ np.array([0.2126, 0.7152, 0.0722])
    assert lum.max() < 1e5  # the photosphere (~1e9 cd/m^2) is hidden
    # the corona's ring at 1.25 radii: the disk's mean radiance (irradiance / solid angle,
    # 1.6e9 cd/m^2 outside the air) times Baumbach's profile, times the transmittance at
    # 64.6 deg (~0.88): 1e3..3e3 cd/m^2
    alpha = sun.angular_radius_rad
    mean_disk = sun.illuminance_lux / (2 * math.pi * (1 - math.cos(alpha)))
    expect = mean_disk * float(baumbach_corona(1.25)) * 0.88
    yy, xx = np.mgrid[0:200, 0:200]
    rho = np.hypot(xx - 99.5, yy - 99.5) * (math.radians(2.0) / 200) / alpha
    ring = lum[(rho > 1.2) & (rho < 1.3)]
    print(f"corona at 1.25 R: {np.median(ring):.4g} cd/m^2, expected ~{expect:.4g}")
    assert np.median(ring) == pytest.approx(expect, rel=0.15)
