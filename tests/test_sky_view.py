"""Sky-view tables (render/sky_view.py): frames drawn from them agree with per-pixel lookups in
the 4D tables, and the tables are redrawn exactly when the camera altitude or a light moves."""

import numpy as np
import pytest

from skydome.atmosphere import preset
from skydome.atmosphere.layer import AtmosphereLayer
from skydome.core.cameras import (
    DirectionsCamera,
    EquirectCamera,
    PerspectiveCamera,
    direction_from_angles,
)
from skydome.spectra import SRGB_LUMINANCE
from tests.air_frames import AirFrames
from tests.air_frames import precomputed_frames as precomputed_renderer


def direct_renderer():
    return precomputed_renderer(sky_view=False)


def relative_errors(a, b):
    y_a, y_b = a[..., :3] @ SRGB_LUMINANCE, b[..., :3] @ SRGB_LUMINANCE
    ok = y_b > 0
    rel = np.abs(y_a - y_b)[ok] / y_b[ok]
    return float(np.sqrt(np.mean(rel**2))), float(np.percentile(rel, 99))


def log_uniform_image(lo: float, hi: float, shape: tuple[int, int], seed: int) -> np.ndarray:
    """Distances (m) spread evenly in log between lo and hi, one per pixel."""
    rng = np.random.default_rng(seed)
    return np.exp(rng.uniform(np.log(lo), np.log(hi), shape))


def errors_against_sky(a, b, camera, w, h, **kw):
    """RMS and 99th percentile of |a - b| in luminance over the luminance of the open sky in
    the same direction (per-pixel lookups), for frames a, b of ``camera`` rendered with kw."""
    sky = direct_renderer().render(camera, w, h, **kw).data[..., :3] @ SRGB_LUMINANCE
    ok = sky > 0
    err = np.abs((a.data[..., :3] - b.data[..., :3]) @ SRGB_LUMINANCE)[ok] / sky[ok]
    return float(np.sqrt(np.mean(err**2))), float(np.percentile(err, 99))


@pytest.mark.parametrize("altitude_m", [0.0, 10_000.0])
@pytest.mark.parametrize("sun_elevation", [60.0, 5.0, -6.0, -12.0])
def test_sky_view_frame_matches_direct_lookups(altitude_m, sun_elevation):
    # The tables tabulate smooth phase-free values at 0.7 deg in azimuth and <= 0.7 deg in
    # elevation (finer at the horizon); bilinear interpolation of such functions is good to
    # ~1e-3 (measured 0.017-0.05% RMS, p99 <= 0.24%, worst at Sun -12 deg where the Earth's
    # shadow sharpens the sky). Bounds: RMS 0.2%, p99 1%, in luminance and in the scotopic
    # channel, over the whole sphere, ground and twilight included.
    sun = direction_from_angles(sun_elevation, 200.0)
    cam = EquirectCamera()
    a = precomputed_renderer().render(cam, 256, 128, sun_direction=sun, altitude_m=altitude_m)
    b = direct_renderer().render(cam, 256, 128, sun_direction=sun, altitude_m=altitude_m)
    assert a.info["path"] == "sky-view" and b.info["path"] == "direct"
    rms, p99 = relative_errors(a.data, b.data)
    assert rms < 2e-3 and p99 < 1e-2
    s_a, s_b = a.data[..., 3], b.data[..., 3]
    ok = s_b > 0
    rel_s = np.abs(s_a - s_b)[ok] / s_b[ok]
    assert np.sqrt(np.mean(rel_s**2)) < 2e-3


@pytest.mark.parametrize("atmosphere", ["hazy", "mars"])
@pytest.mark.parametrize("sun_elevation", [5.0, -6.0])
def test_sky_view_matches_direct_lookups_for_other_atmospheres(atmosphere, sun_elevation):
    # Dense haze (sharper Mie forward peak, hazier ground at the horizon) and another planet
    # (radii, dust): the same bounds (measured 0.02-0.08% RMS, p99 <= 0.27%).
    sun = direction_from_angles(sun_elevation, 200.0)
    a, b = (
        precomputed_renderer(atmosphere, sky_view=v).render(
            EquirectCamera(), 256, 128, sun_direction=sun
        )
        for v in (True, False)
    )
    rms, p99 = relative_errors(a.data, b.data)
    assert rms < 2e-3 and p99 < 1e-2


def test_sun_disk_and_second_light_match_direct_lookups():
    # The Sun layer's disk seen through the air: the sky-view path reads the transmittance
    # from its view-transmittance table (1024 texels over the view cosine), the direct path
    # computes it per pixel: measured 5e-6 apart at the disk's centre (the disk is 1e9 cd/m^2,
    # the sky 4e4). A second light (e.g. the Moon) uses its own tables.
    from skydome import Sky
    from skydome.celestial.sun import SunLayer

    disks = []
    for sky_view in (True, False):
        air = AtmosphereLayer(config=precomputed_renderer().sky.config, sky_view=sky_view)
        with Sky(sun_elevation_deg=12.0, sun_azimuth_deg=140.0, layers=[SunLayer(), air]) as sky:
            d = sky.state.sun.direction
            disks.append(sky.render(DirectionsCamera(np.array([d])), 0, 0, exposure=None).data)
    assert disks[0][0, 0, 1] > 1e8  # the disk, not the sky
    np.testing.assert_allclose(disks[0], disks[1], rtol=1e-4)
    sun = direction_from_angles(12.0, 140.0)
    moon = direction_from_angles(35.0, 300.0)
    cam = EquirectCamera()
    kw = {"sun_direction": sun, "light2_direction": moon, "light2_scale": 2e-6}
    a = precomputed_renderer().render(cam, 128, 64, **kw).data
    b = direct_renderer().render(cam, 128, 64, **kw).data
    rms, p99 = relative_errors(a, b)
    assert rms < 2e-3 and p99 < 1e-2


@pytest.mark.parametrize("altitude_m", [2.0, 1000.0, 10_000.0])
@pytest.mark.parametrize("sun_elevation", [45.0, 5.0, -4.0])
def test_aerial_perspective_tables_match_direct_lookups(altitude_m, sun_elevation):
    # Aerial perspective for a scene at 50 m to 150 km (random per pixel, half the frame
    # without a scene), from the direction x distance tables vs per-pixel lookups. The
    # in-scatter of a short path is a small difference of two table values in both, so its
    # error is measured against the sky radiance of the direction (the brightness scale a
    # scene is composited against): measured <= 0.44% RMS and p99 <= 1.8% (twilight, 20 km
    # scenes). Bounds 1% RMS, 3% p99. The RGB transmittance is computed the same way in both.
    sun = direction_from_angles(sun_elevation, 200.0)
    cam = EquirectCamera()
    w, h = 256, 128
    depth = log_uniform_image(50.0, 150_000.0, (h, w), seed=1)
    depth[:, : w // 2] = 0.0
    kw = {"sun_direction": sun, "altitude_m": altitude_m}
    a = precomputed_renderer().render(cam, w, h, depth_m=depth, **kw)
    b = direct_renderer().render(cam, w, h, depth_m=depth, **kw)
    assert a.info["path"] == "sky-view" and b.info["path"] == "direct"
    rms, p99 = errors_against_sky(a, b, cam, w, h, **kw)
    assert rms < 1e-2 and p99 < 3e-2
    np.testing.assert_allclose(a.info["transmittance"], b.info["transmittance"], atol=2e-4)


@pytest.mark.parametrize("altitude_m", [2.0, 1000.0])
@pytest.mark.parametrize("sun_elevation", [15.0, 2.0, -3.0])
def test_light_shafts_from_tables_match_direct_lookups(altitude_m, sun_elevation):
    # Shadowed lengths of 10 m to 50 km (random per pixel, a quarter of the frame without):
    # the sky minus the tables' aerial perspective of the shadowed part, against Bruneton's
    # per-pixel T(x, x_p) S(x_p). Error / sky radiance of the direction: measured <= 0.06%
    # RMS, p99 <= 0.17%; bounds 0.5% RMS, 2% p99.
    sun = direction_from_angles(sun_elevation, 90.0)
    cam = EquirectCamera()
    w, h = 128, 64
    shadow = log_uniform_image(10.0, 50_000.0, (h, w), seed=0)
    shadow[:, : w // 4] = 0.0
    kw = {"sun_direction": sun, "altitude_m": altitude_m}
    a = precomputed_renderer().render(cam, w, h, shadow_length_m=shadow, **kw)
    b = direct_renderer().render(cam, w, h, shadow_length_m=shadow, **kw)
    assert a.info["path"] == "sky-view"
    rms, p99 = errors_against_sky(a, b, cam, w, h, **kw)
    assert rms < 5e-3 and p99 < 2e-2
    # Shadowed pixels are darker than the open sky; unshadowed ones equal it.
    open_sky = precomputed_renderer().render(cam, w, h, **kw).data
    assert np.all(a.data[:, w // 2 :, 1] <= open_sky[:, w // 2 :, 1] * (1 + 1e-6))
    np.testing.assert_allclose(a.data[:, : w // 4], open_sky[:, : w // 4], rtol=1e-6)


@pytest.mark.parametrize("altitude_m", [2.0, 10_000.0])
@pytest.mark.parametrize("sun_elevation", [15.0, -3.0])
def test_light_shafts_with_a_scene_match_direct_lookups(altitude_m, sun_elevation):
    # Both inputs (Bruneton's GetSkyRadianceToPoint drops the last shadow length before the
    # scene): measured <= 0.35% RMS, p99 <= 0.31% of the open sky; bounds 1% RMS, 3% p99.
    sun = direction_from_angles(sun_elevation, 90.0)
    cam = EquirectCamera()
    w, h = 128, 64
    shadow = log_uniform_image(10.0, 50_000.0, (h, w), seed=0)
    shadow[:, : w // 4] = 0.0
    depth = log_uniform_image(50.0, 150_000.0, (h, w), seed=1)
    depth[:, w // 2 : 3 * w // 4] = 0.0
    kw = {"sun_direction": sun, "altitude_m": altitude_m}
    both = {"shadow_length_m": shadow, "depth_m": depth}
    a = precomputed_renderer().render(cam, w, h, **both, **kw)
    b = direct_renderer().render(cam, w, h, **both, **kw)
    assert a.info["path"] == "sky-view"
    rms, p99 = errors_against_sky(a, b, cam, w, h, **kw)
    assert rms < 1e-2 and p99 < 3e-2


def test_tables_are_redrawn_only_when_needed():
    r = AirFrames(
        preset("earth"),
        config=precomputed_renderer().sky.config,
        ctx=precomputed_renderer().graph.ctx,
    )
    sun = direction_from_angles(20.0, 100.0)
    r.render(PerspectiveCamera(yaw_deg=0.0), 16, 8, sun_direction=sun)
    assert r.sky.sky_view.draws == 1
    r.render(PerspectiveCamera(yaw_deg=90.0, pitch_deg=30.0), 32, 16, sun_direction=sun)
    r.render(EquirectCamera(), 32, 16, sun_direction=sun, sun_scale=0.5)
    assert r.sky.sky_view.draws == 1  # camera turned, frame size and Sun scale changed: kept
    r.render(EquirectCamera(), 32, 16, sun_direction=direction_from_angles(20.5, 100.0))
    assert r.sky.sky_view.draws == 2
    r.render(EquirectCamera(), 32, 16, sun_direction=sun, altitude_m=100.0)
    assert r.sky.sky_view.draws == 3
    depth = np.full((16, 32), 500.0)
    r.render(EquirectCamera(), 32, 16, sun_direction=sun, altitude_m=100.0, depth_m=depth)
    assert r.sky.sky_view.draws == 4  # the aerial-perspective tables, drawn on first use
    r.render(EquirectCamera(), 32, 16, sun_direction=sun, altitude_m=100.0, depth_m=depth * 2)
    assert r.sky.sky_view.draws == 4
    r.release()


@pytest.mark.parametrize(
    "kwargs",
    [
        {"altitude_m": 2e5},  # above the atmosphere (top at 100 km): its limb is a sharp edge
    ],
)
def test_direct_lookups_where_tables_do_not_apply(kwargs):
    f = precomputed_renderer().render(
        EquirectCamera(), 16, 8, sun_direction=direction_from_angles(30.0, 0.0), **kwargs
    )
    assert f.info["path"] == "direct"


def test_sky_view_size_validation():
    with pytest.raises(ValueError):
        AtmosphereLayer("earth", sky_view_size=(64, 63))
