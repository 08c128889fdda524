"""The frame graph, the one render path: frames drawn in tiles (with per-pixel inputs cut
into the same tiles), GL state restored after a failed draw, what a frame reports."""

from __future__ import annotations

import numpy as np
import pytest

from skydome.core.cameras import (
    MIN_ALTITUDE_M,
    DirectionsCamera,
    EquirectCamera,
    PerspectiveCamera,
    direction_from_angles,
)
from skydome.errors import ParameterError
from skydome.gpu.passes import FullscreenPass
from tests.air_frames import precomputed_frames, single_frames

SUN = direction_from_angles(20.0, 135.0)


def test_gl_state_is_restored_after_a_failed_draw(monkeypatch):
    # The per-pixel path draws its surface pass with additive blending behind a depth test.
    # If that pass raises, the shared context must come back to GL's defaults: a later pass
    # that does not set them (the single-scattering one) must draw exactly as before.
    single = single_frames()
    cam = PerspectiveCamera(fov_deg=60, yaw_deg=135, pitch_deg=10)
    before = single.render(cam, 64, 32, sun_direction=SUN).data
    r = precomputed_frames(sky_view=False)
    r.render(cam, 64, 32, sun_direction=SUN)  # every pass compiled: two draws per frame now
    real = FullscreenPass.draw
    calls = []

    def second_fails(self, *args, **kwargs):
        calls.append(self)
        if len(calls) == 2:  # the surface pass, after blending and the depth test are on
            raise RuntimeError("mid-draw failure")
        return real(self, *args, **kwargs)

    monkeypatch.setattr(FullscreenPass, "draw", second_fails)
    with pytest.raises(RuntimeError, match="mid-draw"):
        r.render(cam, 64, 32, sun_direction=SUN)
    monkeypatch.undo()
    for _ in range(2):  # with blending left on, the second draw would add to the first
        after = single.render(cam, 64, 32, sun_direction=SUN).data
        np.testing.assert_array_equal(after, before)


def test_frames_report_the_altitude_used():
    f = precomputed_frames().render(PerspectiveCamera(), 16, 8, sun_direction=SUN, altitude_m=0)
    assert f.info["altitude_m"] == MIN_ALTITUDE_M
    assert f.info["altitude_requested_m"] == 0.0
    g = precomputed_frames().render(PerspectiveCamera(), 16, 8, sun_direction=SUN, altitude_m=5)
    assert g.info["altitude_m"] == 5.0 and "altitude_requested_m" not in g.info


@pytest.mark.parametrize(
    "make",
    [
        lambda: precomputed_frames(),
        lambda: precomputed_frames(sky_view=False),
        lambda: single_frames(jitter=True),
    ],
    ids=["sky-view", "per-pixel", "single-jittered"],
)
def test_tiled_frames_equal_whole_frames(monkeypatch, make):
    # Tiles see the whole frame through u_resolution and their place through u_tile_offset:
    # the same pixel centres, so the same values (the jitter pattern repeats every 4 pixels,
    # and tiles are multiples of 4 wide).
    r = make()
    cam = EquirectCamera()
    whole = r.render(cam, 200, 100, sun_direction=SUN).data
    monkeypatch.setattr("skydome.scene.graph.TILE_SIZE", 64)
    tiled = r.render(cam, 200, 100, sun_direction=SUN).data
    np.testing.assert_allclose(tiled, whole, rtol=1e-6, atol=1e-9)


def test_tiled_inputs_and_directions(monkeypatch):
    # Per-pixel inputs (a depth image, a direction map) are cut into the same tiles.
    r = precomputed_frames()
    rng = np.random.default_rng(3)
    d = rng.normal(size=(70, 90, 3))
    d[..., 2] = np.abs(d[..., 2]) * 0.3
    cam = DirectionsCamera(d)
    depth = rng.uniform(100.0, 30_000.0, size=(70, 90))
    depth[::7] = np.inf  # +inf: no scene along those rays
    whole = r.render(cam, 0, 0, sun_direction=SUN, depth_m=depth)
    monkeypatch.setattr("skydome.scene.graph.TILE_SIZE", 32)
    tiled = r.render(cam, 0, 0, sun_direction=SUN, depth_m=depth)
    np.testing.assert_allclose(tiled.data, whole.data, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(
        tiled.info["transmittance"], whole.info["transmittance"], rtol=1e-6, atol=1e-9
    )
    # Rays with no scene see the open sky: the same as a frame without a depth image.
    sky = r.render(cam, 0, 0, sun_direction=SUN).data
    np.testing.assert_allclose(whole.data[::7], sky[::7], rtol=1e-5, atol=1e-9)
    np.testing.assert_allclose(whole.info["transmittance"][::7], 0.0, atol=1e-6)


def test_a_frame_as_wide_as_the_largest_size():
    # 16384 pixels, eight tiles: GL memory stays at one tile's targets whatever the frame.
    f = precomputed_frames().render(EquirectCamera(), 16_384, 8, sun_direction=SUN)
    assert f.data.shape == (8, 16_384, 4)
    assert np.all(np.isfinite(f.data)) and f.luminance.min() > 0
    # Azimuth runs across the whole width: the brightest column is towards the Sun (135°).
    brightest = np.argmax(f.luminance[3]) / 16_384 * 360.0
    assert brightest == pytest.approx(135.0, abs=2.0)


def test_depth_image_errors_name_the_problem():
    r = precomputed_frames()
    with pytest.raises(ParameterError, match=r"depth_m must be a \(8, 16\) array.*got \(16, 8\)"):
        r.render(PerspectiveCamera(), 16, 8, sun_direction=SUN, depth_m=np.ones((16, 8)))
    with pytest.raises(ParameterError, match="NaN"):
        r.render(PerspectiveCamera(), 16, 8, sun_direction=SUN, depth_m=np.full((8, 16), np.nan))


def test_depth_and_shadow_maps_through_the_users_path():
    # Sky.render takes the same per-pixel inputs: the aerial perspective of a scene of one's
    # own, its RGB transmittance in frame.info, and light shafts of shadow lengths.
    from skydome import Sky

    with Sky(sun_elevation_deg=6.0, sun_azimuth_deg=250.0) as sky:
        cam = PerspectiveCamera(fov_deg=60, yaw_deg=230, pitch_deg=-2)
        depth = np.full((18, 32), np.inf)
        depth[9:] = 15e3
        f = sky.render(cam, 32, 18, altitude_m=1500.0, depth_m=depth, exposure=None)
        t = f.info["transmittance"]
        assert t.shape == (18, 32, 3)
        # 15 km of air near the ground: T in (0, 1), redder light kept (Rayleigh's lambda^-4).
        assert np.all((t[9:] > 0.1) & (t[9:] < 1.0)) and np.all(t[9:, :, 0] > t[9:, :, 2])
        shadow = np.full((18, 32), 8000.0)
        shaded = sky.render(cam, 32, 18, altitude_m=1500.0, shadow_length_m=shadow, exposure=None)
        open_sky = sky.render(cam, 32, 18, altitude_m=1500.0, exposure=None)
        assert np.all(shaded.luminance[:9] < open_sky.luminance[:9])


def test_supersampled_frames_are_the_mean_of_their_rays():
    # supersample n: the frame drawn at n x the size, each pixel the mean of its n x n rays,
    # and so each per-pixel output (the transmittance to a scene). Checked against the big
    # frame averaged here, by hand; the depth image is one value per pixel for all its rays.
    r = precomputed_frames()
    cam = PerspectiveCamera(fov_deg=70, yaw_deg=120, pitch_deg=5)
    depth = np.full((12, 20), np.inf)
    depth[8:] = 8e3
    f = r.render(cam, 20, 12, sun_direction=SUN, depth_m=depth, supersample=3)
    big = r.render(cam, 60, 36, sun_direction=SUN, depth_m=np.kron(depth, np.ones((3, 3))))
    by_hand = big.data.astype(np.float64).reshape(12, 3, 20, 3, 4).mean(axis=(1, 3))
    np.testing.assert_allclose(f.data, by_hand, rtol=1e-6, atol=1e-9)
    t = big.info["transmittance"].astype(np.float64).reshape(12, 3, 20, 3, 3).mean(axis=(1, 3))
    np.testing.assert_allclose(f.info["transmittance"], t, rtol=1e-6, atol=1e-9)
    assert f.data.shape == (12, 20, 4) and f.info["supersample"] == 3
    assert "supersample" not in big.info


def test_supersample_errors_name_the_problem():
    r = precomputed_frames()
    for bad in (0, 5, 1.5, True):
        with pytest.raises(ParameterError, match="supersample"):
            r.render(PerspectiveCamera(), 16, 8, sun_direction=SUN, supersample=bad)
    with pytest.raises(ParameterError, match=r"supersample 4 would draw 16400x32 pixels"):
        r.render(EquirectCamera(), 4100, 8, sun_direction=SUN, supersample=4)
    d = np.tile([[[0.0, 1.0, 0.2]]], (4, 6, 1))
    with pytest.raises(ParameterError, match="DirectionsCamera"):
        r.render(DirectionsCamera(d), 0, 0, sun_direction=SUN, supersample=2)


def test_supersampling_the_user_path_converges_on_clouds_at_the_horizon():
    # The reason for it: a broken deck near the horizon at sunset, one ray per pixel (the
    # march at half the resolution), is a speckle of lit and shaded cloud, detail finer than
    # a pixel. More rays a pixel converge on the pixel's mean: against 16 rays a pixel
    # (supersample 4), 2 x 2 leave less error than 1 and keep the mean (measured: the rms
    # of ln L 0.34 -> 0.26 at 1-10 deg above the horizon, 0.12 -> 0.05 above 20 deg; the
    # band's mean 8 % low with one ray, 2 % with 2 x 2).
    from skydome import Sky
    from skydome.clouds.layer import CloudLayer
    from skydome.clouds.params import Clouds

    deck = CloudLayer(Clouds("broken", coverage=0.75, base_m=1800, seed=4))
    with Sky(sun_elevation_deg=2.0, sun_azimuth_deg=300.0, clouds=deck) as sky:
        cam = PerspectiveCamera(fov_deg=90, yaw_deg=300, pitch_deg=6)
        frames = {n: sky.render(cam, 160, 90, exposure=None, supersample=n) for n in (1, 2, 4)}
    elevation = np.degrees(np.arctan((45 - (np.arange(90) + 0.5)) / 80)) + 6
    horizon, high = (elevation > 1) & (elevation < 10), elevation > 20
    ref = frames[4].luminance

    def rms_ln(n, rows):
        return np.sqrt(np.mean((np.log(frames[n].luminance[rows]) - np.log(ref[rows])) ** 2))

    assert rms_ln(2, horizon) < 0.85 * rms_ln(1, horizon)
    assert rms_ln(2, high) < 0.6 * rms_ln(1, high)
    assert frames[2].luminance[horizon].mean() == pytest.approx(ref[horizon].mean(), rel=0.04)
    assert frames[2].info["supersample"] == 2


def test_supersampled_stars_look_as_at_one_ray_a_pixel():
    # A point source's PSF is given in the frame's pixels: supersampled, it is drawn n x
    # wider and box-filtered back, the same Gaussian integrated over the same pixels. The 20
    # brightest pixels (stars, over the median sky) within 1 % of one ray a pixel (measured
    # 0.0-0.3 %: the sky and the Milky Way under them sampled differently); drawn n x
    # narrower they were up to 2.6 x brighter at the peak. The flux (the mean) is kept.
    from skydome import Sky

    with Sky((-24.6272, -70.4039, 2635.0), "2024-05-01T03:00Z") as sky:
        cam = PerspectiveCamera(fov_deg=20, yaw_deg=180, pitch_deg=60)
        one = sky.render(cam, 96, 96, exposure=None).luminance
        two = sky.render(cam, 96, 96, exposure=None, supersample=2).luminance
    sky_level = np.median(one)
    top = np.argsort(one.ravel())[-20:]
    ratio = (two.ravel()[top] - sky_level) / (one.ravel()[top] - sky_level)
    np.testing.assert_allclose(ratio, 1.0, atol=0.01)
    assert two.mean() == pytest.approx(one.mean(), rel=1e-3)
