"""The viewer's state and input mapping (no GL, no window): drags, wheel, keys, time, the
clamps that keep every value the panel shows in range, the event jumps and the atmosphere
knobs."""

from __future__ import annotations

import math

import pytest

from skydome.errors import ParameterError
from skydome.viewer.controls import (
    CLIMB_FLOOR_M,
    CLIMB_RATE_PER_S,
    EARTH_RADIUS_M,
    VIEW_ALTITUDE_RANGE_M,
    VIEW_FOV_RANGE_DEG,
    Controls,
    ViewState,
    clamp,
)

PLACE = dict(latitude_deg=35.9, longitude_deg=14.5, jd_utc=2458179.0)


def test_a_drag_turns_by_the_field_of_view_across_the_view():
    c = Controls(ViewState(yaw_deg=100.0, pitch_deg=10.0, fov_deg=60.0))
    c.press(10.0, 50.0)
    c.move(10.0 + 640.0, 50.0, 640.0)  # the whole width to the right: yaw + fov
    assert c.state.yaw_deg == pytest.approx(160.0, abs=1e-12)
    c.move(650.0, 50.0 - 64.0, 640.0)  # 64 px up: pitch + 6 deg
    assert c.state.pitch_deg == pytest.approx(16.0, abs=1e-12)
    c.release()
    c.move(0.0, 0.0, 640.0)  # no button: nothing
    assert c.state.yaw_deg == pytest.approx(160.0, abs=1e-12)


def test_the_wheel_zooms_and_the_field_of_view_stays_in_range():
    c = Controls(ViewState(fov_deg=90.0))
    c.scroll(1.0)
    assert c.state.fov_deg == pytest.approx(81.0, abs=1e-12)
    c.scroll(-2.0)
    assert c.state.fov_deg == pytest.approx(81.0 / 0.81, abs=1e-9)
    c.scroll(1000.0)
    assert c.state.fov_deg == VIEW_FOV_RANGE_DEG[0]
    c.scroll(-1000.0)
    assert c.state.fov_deg == VIEW_FOV_RANGE_DEG[1]


def test_pitch_stops_short_of_the_poles_and_yaw_wraps():
    c = Controls(ViewState(yaw_deg=350.0, pitch_deg=80.0, fov_deg=90.0))
    c.drag(90.0, -900.0, 90.0)  # +90 deg yaw, +900 deg pitch
    assert c.state.yaw_deg == pytest.approx(80.0, abs=1e-9)
    assert c.state.pitch_deg == pytest.approx(89.9)
    assert c.state.camera().pitch_deg == pytest.approx(89.9)  # a valid API camera


def test_climbing_grows_the_altitude_exponentially_and_stops_at_space():
    c = Controls(ViewState(altitude_m=100.0))
    c.key("e", True)
    c.tick(0.5)
    expected = (100.0 + CLIMB_FLOOR_M) * math.exp(CLIMB_RATE_PER_S * 0.5) - CLIMB_FLOOR_M
    assert c.state.altitude_m == pytest.approx(expected, rel=1e-12)
    for _ in range(40):
        c.tick(1.0)
    assert c.state.altitude_m == VIEW_ALTITUDE_RANGE_M[1]
    c.key("e", False)
    c.key("q", True)
    for _ in range(40):
        c.tick(1.0)
    assert c.state.altitude_m == 0.0  # down to the ground, never below


def test_walking_moves_the_place_along_the_view_azimuth():
    c = Controls(ViewState(yaw_deg=90.0, altitude_m=1000.0, **PLACE))  # looking east
    c.key("w", True)
    c.tick(0.5)  # 1000 m/s at 1 km up: 500 m east
    s = c.state
    east_m = math.radians(s.longitude_deg - 14.5) * EARTH_RADIUS_M * math.cos(math.radians(35.9))
    assert east_m == pytest.approx(500.0, rel=1e-4)
    assert s.latitude_deg == pytest.approx(35.9, abs=1e-5)


def test_space_plays_the_time_at_its_speed():
    c = Controls(ViewState(speed=3600.0, **PLACE))
    c.key("space", True)
    c.key("space", False)
    assert c.state.playing
    c.tick(0.25)
    assert (c.state.jd_utc - PLACE["jd_utc"]) * 86400.0 == pytest.approx(900.0, abs=1e-3)
    c.key("space", True)
    c.tick(0.25)
    assert not c.state.playing
    assert (c.state.jd_utc - PLACE["jd_utc"]) * 86400.0 == pytest.approx(900.0, abs=1e-3)


def test_a_stalled_frame_does_not_fling_the_camera():
    c = Controls(ViewState(yaw_deg=0.0, fov_deg=90.0))
    c.key("right", True)
    c.tick(30.0)  # counted as 1 s
    assert c.state.yaw_deg == pytest.approx(60.0, abs=1e-9)


def test_out_of_range_and_nan_values_are_clamped_not_raised():
    c = Controls(ViewState(**PLACE))
    s = c.set(
        fov_deg=500.0,
        pitch_deg=float("nan"),
        latitude_deg=123.0,
        longitude_deg=190.0,
        altitude_m=-5.0,
        speed=1e12,
        ev100=99.0,
        tonemap="nope",
        projection="cubemap",
        exposure_mode="bogus",
    )
    assert s.fov_deg == VIEW_FOV_RANGE_DEG[1]
    assert s.pitch_deg == -89.9  # NaN -> the low end
    assert s.latitude_deg == 90.0
    assert s.longitude_deg == pytest.approx(-170.0)
    assert s.altitude_m == 0.0
    assert s.speed == 864000.0
    assert s.ev100 == 40.0
    assert (s.tonemap, s.projection, s.exposure_mode) == ("filmic", "perspective", "auto")
    s.camera()  # the API accepts what the viewer holds
    with pytest.raises(ParameterError, match="no field"):
        c.set(zoom=2.0)


def test_an_abstract_state_cannot_play():
    c = Controls(ViewState(playing=True))
    assert not c.state.playing
    assert clamp(float("nan"), 1.0, 2.0) == 1.0


def test_c_cycles_the_projections():
    c = Controls()
    names = []
    for _ in range(3):
        c.key("c", True)
        names.append(c.state.projection)
    assert names == ["fisheye", "equirect", "perspective"]
    assert type(c.state.camera()).__name__ == "PerspectiveCamera"


def test_jumps_find_the_next_events():
    """Valletta, 2018-03-01 12:00 UTC: sunset 16:56 UTC, the full Moon 2018-03-02 00:51 UTC
    (USNO: full Moon 00:51 UTC; sunset at Valletta ~17:57 local = 16:57 UTC)."""
    from skydome.astro import Observer, to_time
    from skydome.viewer.jumps import next_event

    o = Observer(latitude=35.8989, longitude=14.5146)
    noon = float(to_time("2018-03-01T12:00Z").jd_utc)
    sunset = next_event(o, noon, "sunset")
    assert sunset == pytest.approx(float(to_time("2018-03-01T16:57Z").jd_utc), abs=2 / 1440)
    full = next_event(o, noon, "full_moon")
    assert full == pytest.approx(float(to_time("2018-03-02T00:51Z").jd_utc), abs=2 / 1440)
    # Pressing again goes on to the next one, not the same.
    assert next_event(o, sunset, "sunset") == pytest.approx(sunset + 1.0, abs=0.01)
    polar = Observer(latitude=80.0, longitude=0.0)  # June: the Sun never sets
    assert next_event(polar, float(to_time("2024-06-21T00:00Z").jd_utc), "sunset") is None
    with pytest.raises(ParameterError, match="must be one of"):
        next_event(o, noon, "equinox")
    # The next eclipse seen from Dallas after 2024-03-26: the total solar eclipse of
    # 2024-04-08, its greatest phase there midway between the published C2 18:40:41 and C3
    # 18:44:32 UTC (NASA/GSFC's local circumstances), 18:42:36, within a minute
    dallas = Observer(latitude=32.7767, longitude=-96.7970, elevation_m=131.0)
    start = float(to_time("2024-03-26T00:00Z").jd_utc)
    greatest = next_event(dallas, start, "eclipse")
    assert greatest == pytest.approx(float(to_time("2024-04-08T18:42:36Z").jd_utc), abs=1 / 1440)


def test_atmosphere_knobs_clamp_and_rebuild_the_preset():
    from skydome.atmosphere import preset
    from skydome.viewer.rebuild import KNOB_RANGES, Knobs, clamp_knobs

    k = Knobs.of_preset("earth")
    assert k.params().digest() == preset("earth").digest()  # untouched knobs: the preset
    k2 = clamp_knobs(k, mie_g=3.0, ozone_du=-1.0, rayleigh_scale=2.0, aod_550=0.3)
    assert (k2.mie_g, k2.ozone_du) == (KNOB_RANGES["mie_g"][1], 0.0)
    p = k2.params()
    assert p.mie_g == pytest.approx(0.99)
    assert p.aod_550 == pytest.approx(0.3, rel=1e-6)
    assert p.ozone_du == pytest.approx(0.0, abs=1e-9)
    base = preset("earth").rayleigh_scattering
    assert p.rayleigh_scattering.values[0] == pytest.approx(2.0 * base.values[0], rel=1e-12)
    # Knobs set on the command line count as changes from the preset.
    assert Knobs.of(preset("earth", aod_550=0.4)).params().aod_550 == pytest.approx(0.4)
