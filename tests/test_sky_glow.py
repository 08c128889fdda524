"""Natural sky glow: the airglow (van Rhijn, solar cycle, spectrum) and the zodiacal light
(Leinert et al. 1998 table 17, its geometry and colour), as float64 formulas and as frames."""

from __future__ import annotations

import math

import numpy as np
import pytest

from skydome import Sky
from skydome.core.cameras import DirectionsCamera, FisheyeCamera, direction_from_angles
from skydome.errors import ParameterError
from skydome.night import (
    AirglowLayer,
    LightPollutionLayer,
    ZodiacalLightLayer,
    s10_to_luminance,
    s10_to_mag,
    solar_cycle_factor,
    van_rhijn,
    zenith_brightness,
)
from skydome.night import airglow as ag
from skydome.night import zodiacal as zl
from skydome.physics import refraction as rf
from skydome.scene.state import state_at
from skydome.spectra import SRGB_LUMINANCE

PLACE, TIME = "Valletta", "2018-03-01T23:00Z"
ELEVATIONS = (90.0, 60.0, 30.0, 10.0, 3.0)


def directions(elevations, azimuth=123.0):
    return np.array([direction_from_angles(e, azimuth) for e in elevations])


def luminance(frame) -> np.ndarray:
    return frame.data[0, :, :3].astype(np.float64) @ SRGB_LUMINANCE


# ---------------------------------------------------------------------- units


def test_units_match_the_night_sky_conversions():
    # 220 S10 = 21.93 mag/arcsec^2 (the brief); 1 S10 = 27.78 mag/arcsec^2 (Leinert 1998 sec. 2).
    assert s10_to_mag(220.0) == pytest.approx(21.93, abs=0.005)
    assert s10_to_mag(1.0) == pytest.approx(27.78, abs=0.005)
    # L = 10.8e4 * 10^(-0.4 m), m = 10 + 2.5 log10(3600^2) - 2.5 log10(S):
    # 220 S10 -> 220 * 10.8e4 * 1e-4 / 3600^2 = 1.833e-4 cd/m^2.
    assert s10_to_luminance(220.0) == pytest.approx(220 * 10.8 / 3600**2, rel=1e-12)


# ---------------------------------------------------------------------- van Rhijn


def test_van_rhijn_closed_form_and_values():
    r = ag.EARTH_RADIUS_M / (ag.EARTH_RADIUS_M + 90e3)
    for z_deg in (0.0, 30.0, 60.0, 75.0, 80.0, 85.0, 90.0):
        z = math.radians(z_deg)
        assert van_rhijn(z) == pytest.approx(1.0 / math.sqrt(1.0 - (r * math.sin(z)) ** 2), 1e-14)
    # Values for h = 90 km, R = 6371 km computed from the closed form: 4.19 at 80 deg (not
    # ~5.4, which is the factor at 85 deg), 6.01 at the horizon, 1.94 at 60 deg.
    assert van_rhijn(math.radians(80.0)) == pytest.approx(4.19, abs=0.005)
    assert van_rhijn(math.radians(85.0)) == pytest.approx(5.34, abs=0.005)
    assert van_rhijn(math.radians(90.0)) == pytest.approx(6.01, abs=0.005)


def test_van_rhijn_is_the_slant_path_through_a_thin_shell():
    # Independent geometry: the length of a ray inside a shell 90-91 km up, divided by the
    # shell's thickness, from the ray-sphere intersection (no use of the closed form). A 1 km
    # shell differs from the thin-shell limit by < 0.5 % at z <= 85 deg.
    R = ag.EARTH_RADIUS_M
    for z_deg in (0.0, 45.0, 70.0, 80.0, 85.0):
        mu = math.cos(math.radians(z_deg))

        def distance_to(radius, mu=mu):
            return -R * mu + math.sqrt((R * mu) ** 2 + radius**2 - R**2)

        slant = distance_to(R + 90.5e3 + 500.0) - distance_to(R + 90.5e3 - 500.0)
        thin = van_rhijn(math.radians(z_deg), 90.5e3)
        assert slant / 1000.0 == pytest.approx(thin, rel=5e-3)


def test_solar_cycle_relation():
    # I = 145 + 130 (S - 0.8) / 1.2 S10, S in MJy: 145 S10 at 0.8 MJy, 275 at 2.0 MJy.
    assert solar_cycle_factor(80.0) == pytest.approx(1.0)
    assert 145.0 * solar_cycle_factor(200.0) == pytest.approx(275.0)
    # ~0.7 mag brighter at solar maximum: Walker 1988 and Krisciunas 1997 report 0.4-0.7 mag
    # for the whole sky, of which the airglow is ~2/3.
    dm = 2.5 * math.log10(solar_cycle_factor(200.0))
    assert 0.6 < dm < 0.75
    with pytest.raises(ParameterError):
        solar_cycle_factor(10.0)


def test_airglow_colour_is_green_yellow():
    # OI 557.7 nm, Na D and OI 630 nm on a continuum: a yellow-green light with more green
    # than blue (airglow photographs), and a scotopic/photopic ratio below that of the Sun
    # (~2.3 for sunlight with 1700/683 lm/W) because of the red OH and OI emission.
    sky = Sky(PLACE, TIME, layers=[AirglowLayer()])
    c = AirglowLayer().colour(sky.graph.basis)
    assert c[1] > c[2]
    assert c[0] > c[2]
    assert 0.5 < c[3] < 2.3


def test_rendered_airglow_matches_the_reference():
    layer = AirglowLayer(solar_flux_sfu=150.0)
    sky = Sky(PLACE, TIME, layers=[layer])
    frame = sky.render(DirectionsCamera(directions(ELEVATIONS)), 0, 0, exposure=None)
    z = np.radians(90.0 - np.array(ELEVATIONS))
    ref = ag.airglow_luminance(z, 145.0, 150.0, observer_height_m=sky.altitude_m())
    # The colour has Y = 1 exactly; float32 shading: 1 %.
    np.testing.assert_allclose(luminance(frame), ref, rtol=0.01)
    below = sky.render(DirectionsCamera(directions((-5.0,))), 0, 0, exposure=None)
    assert np.all(below.data == 0.0)  # the ground


def test_airglow_draws_nothing_in_the_abstract_mode():
    sky = Sky(sun_elevation_deg=-30.0, layers=[AirglowLayer()])
    frame = sky.render(DirectionsCamera(directions(ELEVATIONS)), 0, 0, exposure=None)
    assert np.all(frame.data == 0.0)


# ---------------------------------------------------------------------- zodiacal table


def test_table_nodes_and_published_values():
    t = zl.load_table()
    assert t.shape == (19, 11)
    for i, dlon in enumerate(zl.DLON_NODES_DEG):
        for j, beta in enumerate(zl.BETA_NODES_DEG):
            if np.isfinite(t[i, j]):
                assert zl.zodiacal_table_value(dlon, beta) == t[i, j]  # exact at the nodes
                assert zl.zodiacal_table_value(-dlon, -beta) == t[i, j]  # symmetric
    # Leinert et al. 1998 table 17: 77 at the ecliptic pole (= 60 S10 with 1.28e-8 per S10),
    # 259 at 90 deg elongation in the ecliptic, the gegenschein 230 at 180 deg.
    assert zl.zodiacal_s10(0.0, 90.0) == pytest.approx(60.2, abs=0.1)
    assert zl.zodiacal_table_value(90.0, 0.0) == 259.0
    assert zl.zodiacal_table_value(180.0, 0.0) == 230.0
    assert zl.zodiacal_table_value(180.0 + 360.0, 0.0) == 230.0
    # Bilinear between nodes: midway between (60, 0) 505 and (75, 0) 338.
    assert zl.zodiacal_table_value(67.5, 0.0) == pytest.approx(0.5 * (505 + 338))
    # The near-Sun fill rises monotonically towards the Sun.
    f = zl.filled_table()
    assert np.all(np.isfinite(f))
    assert np.all(np.diff(f[:3, :4], axis=1) < 0)


def test_reddening_follows_leinert():
    # f_co = 1 + b log10(lambda / 500 nm): 1 at 500 nm; at 700 nm and 90 deg elongation
    # 1 + 0.6 log10(1.4) = 1.088, at 30 deg 1 + 0.8 log10(1.4) = 1.117.
    assert zl.reddening([500.0], 60.0)[0] == pytest.approx(1.0)
    assert zl.reddening([700.0], 90.0)[0] == pytest.approx(1.0877, abs=1e-4)
    assert zl.reddening([700.0], 30.0)[0] == pytest.approx(1.1169, abs=1e-4)
    assert zl.reddening([400.0], 120.0)[0] == pytest.approx(1 + 0.9 * math.log10(0.8))


def test_ecliptic_geometry_against_the_astronomy():
    from skydome.description import observer_for

    state = state_at(observer_for(PLACE), "2018-06-21T04:00Z")  # the Sun up
    m = zl.helioecliptic_matrix(state.observer, state.time)
    # The Sun's own (airless, topocentric) direction lies at lambda - lambda_sun = 0, beta = 0
    # to within its parallax and the ecliptic latitude of the Sun (< 0.01 deg).
    dlon, beta = zl.helioecliptic_coordinates(state.sun.direction_true, m)
    assert abs(dlon) < 0.01 and abs(beta) < 0.01
    # The Moon's ecliptic latitude is within 5.3 deg of the ecliptic (its orbit's tilt, plus
    # ~1 deg of parallax seen from the ground).
    _, beta_moon = zl.helioecliptic_coordinates(state.moon.direction_true, m)
    assert abs(beta_moon) < 6.3


def test_rendered_zodiacal_light_matches_the_reference():
    layer = ZodiacalLightLayer()
    # pressure 0: no refraction, so the pixel's direction is its airless one.
    sky = Sky(PLACE, TIME, layers=[layer], pressure_hPa=0.0)
    azimuths = (0.0, 90.0, 200.0, 270.0)
    dirs = np.concatenate([directions((85.0, 45.0, 20.0, 5.0), a) for a in azimuths])
    frame = sky.render(DirectionsCamera(dirs), 0, 0, exposure=None)
    m = zl.helioecliptic_matrix(sky.observer, sky.state.time)
    dlon, beta = zl.helioecliptic_coordinates(dirs, m)
    near, far = layer.colours(sky.graph.basis)
    w = np.clip((zl.elongation_deg(dlon, beta) - 30.0) / 60.0, 0.0, 1.0)[:, None]
    ref_channels = zl.zodiacal_luminance(dlon, beta)[:, None] * ((1 - w) * near + w * far)
    ref = ref_channels[:, :3] @ SRGB_LUMINANCE
    # float32 shading and GPU atan/acos: 2 %.
    np.testing.assert_allclose(luminance(frame), ref, rtol=0.02)
    np.testing.assert_allclose(frame.data[0, :, 3], ref_channels[:, 3], rtol=0.02)


def test_zenith_report():
    sky = Sky(PLACE, TIME, layers=[AirglowLayer(), ZodiacalLightLayer()])
    report = zenith_brightness(sky.state, sky.layers)
    assert report["airglow"] == pytest.approx(22.38, abs=0.01)  # 145 S10
    # Valletta at 23 h in March: the zenith is ~30-40 deg from the ecliptic: 20-22.6.
    assert 21.0 < report["zodiacal_light"] < 23.4
    # The report is what the layers draw at the zenith (no air, no refraction): 2 %.
    bare = Sky(PLACE, TIME, layers=[AirglowLayer(), ZodiacalLightLayer()], pressure_hPa=0.0)
    up = DirectionsCamera(np.array([[0.0, 0.0, 1.0]]))
    for name in ("airglow", "zodiacal_light"):
        for layer in bare.layers:
            layer.enabled = layer.name == name
        drawn = luminance(bare.render(up, 0, 0, exposure=None))[0]
        assert drawn == pytest.approx(10.8e4 * 10 ** (-0.4 * report[name]), rel=0.02)


# ---------------------------------------------------------------------- frames


def base_layers():
    from skydome.atmosphere.layer import AtmosphereLayer
    from skydome.celestial.moon import MoonLayer
    from skydome.celestial.sun import SunLayer

    return [SunLayer(), MoonLayer(), AtmosphereLayer()]


def test_every_layer_off_leaves_the_frame_bit_identical():
    # Explicit layer lists: the same Sun, Moon and air with and without the glow layers.
    base = Sky(PLACE, TIME, layers=base_layers())
    glow = [AirglowLayer(), ZodiacalLightLayer(), LightPollutionLayer.from_bortle(8)]
    full = Sky(PLACE, TIME, layers=[*base_layers(), *glow])
    cam = FisheyeCamera()
    on = full.render(cam, 96, 96, exposure=None).data
    for layer in glow:
        full.layer(layer.name).enabled = False
    off = full.render(cam, 96, 96, exposure=None).data
    plain = base.render(cam, 96, 96, exposure=None).data
    assert np.array_equal(off, plain)
    assert not np.array_equal(on, plain)


# ---------------------------------------------------------------------- GPU tables


def test_zodiacal_grid_against_the_node_bilinear_table():
    # The shader's grid (pseudo-angles, one bilinear fetch) against the float64
    # node-bilinear interpolation of Leinert's table at 200,000 random directions. The grid
    # is exact at its own nodes; between them its bilinear differs from the node-bilinear
    # where a cell (<= 0.46 deg) straddles a table node line: measured max 0.85 %, 0.36 %
    # beyond 45 deg elongation (limits 1 % and 0.5 %). L w (the far colour's share) within
    # 0.2 % of L (measured 0.18 %).
    rng = np.random.default_rng(1)
    v = rng.normal(size=(200_000, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    dlon = np.degrees(np.arctan2(v[:, 1], v[:, 0]))
    beta = np.degrees(np.arcsin(v[:, 2]))
    ref = zl.zodiacal_luminance(dlon, beta)
    w = zl.reddening_weight(dlon, beta)
    got = zl.zodiacal_grid_value(v * rng.uniform(0.5, 2.0, (len(v), 1)))  # any length
    rel = np.abs(got[:, 0] / ref - 1.0)
    assert rel.max() < 0.01
    assert rel[zl.elongation_deg(dlon, beta) >= 45.0].max() < 0.005
    assert np.max(np.abs(got[:, 1] - ref * w) / ref) < 0.002
    # The pseudo-angles invert exactly and are monotonic in both angles.
    u, vv = zl.grid_coordinates(v)
    back_dlon, back_beta = zl.grid_angles_deg(u, vv)
    np.testing.assert_allclose(back_dlon, np.abs(dlon), atol=1e-9)
    np.testing.assert_allclose(back_beta, np.abs(beta), atol=1e-9)
    a = np.radians(np.linspace(0.0, 180.0, 1001))
    assert np.all(np.diff(zl.grid_coordinates(np.stack([np.cos(a), np.sin(a), 0 * a], -1))[0]) > 0)


def test_refraction_table_against_the_inverse_saemundsson_law():
    # The airless direction d + k (z d - up) against an independent inverse: the true
    # elevation h with h + R_S(h) = apparent, by bisection (reference.disks). The GLSL law
    # (Bennett, then two Saemundsson steps) agrees to 2.3" (measured); the table's linear
    # interpolation adds < 0.12" (measured over 200,001 elevations from -0.95 to 90 deg).
    from skydome.reference.disks import true_elevation_deg

    up = np.array([0.0, 0.0, 1.0])
    for h in np.concatenate([np.linspace(-0.9, 5.0, 40), np.linspace(5.0, 89.5, 40)]):
        z, c = math.sin(math.radians(h)), math.cos(math.radians(h))
        d = np.array([c, 0.0, z])
        for k in (rf.airless_offset(z), rf.airless_offset_lookup(z)):
            v = d + k * (z * d - up)
            h_true = math.degrees(math.atan2(v[2], v[0]))
            assert abs(h_true - true_elevation_deg(h)) * 3600.0 < 3.0, h
    z = np.sin(np.radians(np.linspace(-0.95, 89.99, 20_001)))
    c = np.sqrt(1.0 - z * z)
    shift = np.arctan(rf.airless_offset(z) * c) - np.arctan(rf.airless_offset_lookup(z) * c)
    assert np.degrees(np.abs(shift)).max() * 3600.0 < 0.2
    assert np.all(rf.airless_offset(z, 0.0) == 0.0)  # no air, no refraction


def test_rendered_zodiacal_light_with_refraction():
    # Default weather: each pixel reads the table at its airless direction (the inverse
    # Saemundsson law by bisection), near the horizon too: 2 % as above.
    from skydome.reference.disks import true_elevation_deg

    layer = ZodiacalLightLayer()
    sky = Sky(PLACE, TIME, layers=[layer])
    elevations = (0.5, 2.0, 5.0, 15.0, 45.0)
    azimuths = (60.0, 120.0, 250.0)
    dirs = np.concatenate([directions(elevations, a) for a in azimuths])
    frame = sky.render(DirectionsCamera(dirs), 0, 0, exposure=None)
    p, t = sky.state.pressure_hPa, sky.state.temperature_C
    true = np.concatenate(
        [directions([true_elevation_deg(e, p, t) for e in elevations], a) for a in azimuths]
    )
    m = zl.helioecliptic_matrix(sky.observer, sky.state.time)
    dlon, beta = zl.helioecliptic_coordinates(true, m)
    near, far = layer.colours(sky.graph.basis)
    w = zl.reddening_weight(dlon, beta)[:, None]
    ref = (zl.zodiacal_luminance(dlon, beta)[:, None] * ((1 - w) * near + w * far))[:, :3]
    np.testing.assert_allclose(luminance(frame), ref @ SRGB_LUMINANCE, rtol=0.02)
