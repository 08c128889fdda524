"""The clouds' light map (skydome.clouds.light_map, clouds/cloud_light_map.glsl): the key
light's transmittance through the clouds from the sphere of their lowest base, which the
full-quality march reads for the light of the air, the fog and the ground under the clouds
where it marched each of those paths.

The map's texels are held to the shadow query (CloudLayer.light_transmittance, the same sums
marched from the same points), and a user's full-quality frame with the map to the "best"
quality beside the same frame with every light path marched (the map switched off for it).
"""

from __future__ import annotations

import numpy as np
import pytest

W, H = 960, 540


def _sky(sun_deg: float, quality: str = "full", clouds: str = "fair"):
    from skydome import Sky
    from skydome.clouds.layer import CloudLayer
    from skydome.clouds.params import Clouds

    # fair cumulus, or a broken deck (75 % cover, its base at 1.8 km)
    kind = (Clouds("fair", seed=3) if clouds == "fair"
            else Clouds("broken", coverage=0.75, base_m=1800, seed=4))  # fmt: skip
    layer = CloudLayer(kind, quality=quality)
    return Sky(sun_elevation_deg=sun_deg, sun_azimuth_deg=150.0, clouds=layer)


def _camera():
    from skydome.core.cameras import PerspectiveCamera

    # 40 deg from the Sun's azimuth, 15 deg up: cumulus near and far, the ground in front
    return PerspectiveCamera(fov_deg=90.0, yaw_deg=190.0, pitch_deg=15.0)


@pytest.mark.gl
@pytest.mark.parametrize("sun_deg", [60.0, 12.0])
def test_light_map_texels_hold_the_clouds_transmittance(sun_deg):
    # Each texel holds clouds_transmittance from its point of the lowest base's sphere (10 m
    # back along the light); the shadow query marches the same sums (LIGHT_PATH_STEPS samples
    # a crossing) from the same point, given in float32 km, where the map's shader makes it
    # from the texel's coordinates in float32. Measured: all but a few in a thousand agree
    # within 1e-7 (99.5 % of them at a Sun 12 deg up, whose crossings are longer; the mean
    # difference 1.3e-3 there). The few are points where the 4 samples' sum flips: a shell's
    # crossing found in float32 at 6400 km from the centre moves its samples by up to a
    # metre with the point's rounding, and a sample on a cloud's edge (the density there
    # changes steeply) then hits or misses it (the same texels' T moves from 1 to 0.003 and
    # 0.02 with the point taken 10, 50 or 200 m back: the marched paths are as sensitive).
    # A wrong point (centre, warp, steps) would part most of them. Bars: 99 % within 1e-4,
    # the mean difference below 5e-3.
    from skydome.clouds.light_map import LIGHT_MAP_TEXELS, LIGHT_PATH_STEPS, texel_points

    with _sky(sun_deg) as sky:
        sky.render(_camera(), W, H, exposure=None)
        layer = sky.layer("clouds")
        cloud = layer.cloud_inputs()
        texture = layer.light_map(cloud, layer.texture_inputs())
        n = LIGHT_MAP_TEXELS
        held = np.frombuffer(texture.read(), dtype=np.float32).reshape(n, n)
        rng = np.random.default_rng(5)
        texels = rng.integers(0, n, size=(4000, 2))
        _, base_km, *centre = layer._light_map_warp(cloud)
        assert base_km == min(cloud.u_cloud_shell[0], cloud.u_cloud_shell[2])
        points = texel_points(texels, base_km, centre) - 0.01 * np.asarray(cloud.u_light_direction)
        # the texels the march reads: points where a ray towards the light leaves the sphere
        # (along the light, upwards through it), within 100 km of the camera
        light = np.asarray(cloud.u_light_direction)
        radius = np.linalg.norm(points, axis=1)
        inside = (
            np.all(np.isfinite(points), axis=1)
            & (points @ light > 0.02 * radius)
            & (np.hypot(points[:, 0], points[:, 1]) < 100.0)
        )
        texels, points = texels[inside], points[inside]
        ground_km = (layer._air().bottom_radius_m + layer.ground_m) / 1e3
        points_m = np.column_stack([points[:, :2] * 1e3, (points[:, 2] - ground_km) * 1e3])
        marched = layer.light_transmittance(points_m, steps=LIGHT_PATH_STEPS)
    mapped = held[texels[:, 1], texels[:, 0]]
    assert inside.sum() > 1500
    assert 0.2 < marched.mean() < 0.95  # shadows and light both among the points
    error = np.abs(mapped - marched)
    assert np.mean(error < 1e-4) > 0.99
    assert error.mean() < 5e-3


def _frames(sun_deg: float, clouds: str):
    """Luminance of the user's full-quality frame, of the same with every light path marched
    and of the "best" quality's (every pixel marched, finer steps; no map)."""
    from skydome.clouds.layer import CloudLayer

    with _sky(sun_deg, clouds=clouds) as sky:
        camera = _camera()
        mapped = sky.render(camera, W, H, exposure=None).data[..., 1].copy()
        layer = sky.layer("clouds")
        assert layer._light_map is not None  # the user's frame read the map
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(CloudLayer, "_light_map_inputs", lambda *a: None)
            marched = sky.render(camera, W, H, exposure=None).data[..., 1].copy()
    with _sky(sun_deg, quality="best", clouds=clouds) as sky:
        best = sky.render(_camera(), W, H, exposure=None).data[..., 1].copy()
    return mapped, marched, best


@pytest.mark.gl
@pytest.mark.parametrize(("clouds", "sun_deg"), [("fair", 60.0), ("fair", 12.0), ("deck", 20.0)])
def test_full_quality_frame_with_the_light_map_is_as_accurate_as_marched_paths(clouds, sun_deg):
    # The map puts a shadow's edge within a texel (12 m near the camera to ~1 km 30 km away)
    # where the marched paths put it at a point, and where 4 samples of a long crossing hit
    # or miss a cloud's edge both sums are noisy, each in its own way: against the "best"
    # quality both frames are off about alike. Measured at 960x540 (the mean |relative
    # error| against best with the map / marched; the mean luminance with the map against
    # marched; the two frames' mean and median difference): fair 60 deg 2.57 / 2.54 %,
    # -0.006 %, 0.25 %, 0; fair 12 deg 3.07 / 3.05 %, +0.05 %, 0.60 %, 0; the deck 20 deg
    # 5.17 / 4.41 %, +0.21 %, 2.2 %, 0.31 %: the deck's shadows on the ground near the
    # camera, which best draws as sharp as a point Sun's, the map spreads over its texels
    # (12-80 m there; the Sun's half-degree disk spreads them over ~50 m under a 1.8 km
    # base). Bars: the map's error at most 1.25x the marched paths', the mean luminance
    # within 0.5 % of theirs, the frames' mean difference below 4 %, their median below 1 %.
    mapped, marched, best = _frames(sun_deg, clouds)
    assert np.all(np.isfinite(mapped))
    error_mapped = np.mean(np.abs(mapped / best - 1.0))
    error_marched = np.mean(np.abs(marched / best - 1.0))
    assert error_mapped < 1.25 * error_marched
    assert abs(mapped.mean() / marched.mean() - 1.0) < 0.005
    rel = np.abs(mapped / marched - 1.0)
    assert rel.mean() < 0.04
    assert np.median(rel) < 0.01


@pytest.mark.gl
def test_light_map_only_where_it_serves():
    # "best" (the reference) marches every path; the interactive mode's first frame of a
    # sky marches them too (while the time runs every frame is a first one), its next
    # frames of the same sky read the map; a camera above the clouds' base or a key light
    # below LIGHT_MAP_MIN_ELEVATION_DEG (10 deg) draws no map.
    with _sky(40.0, quality="best") as sky:
        sky.render(_camera(), 64, 36, exposure=None)
        assert sky.layer("clouds")._light_map is None
    with _sky(40.0, quality="interactive") as sky:
        sky.render(_camera(), 64, 36, exposure=None)
        assert sky.layer("clouds")._light_map is None
        sky.render(_camera(), 64, 36, exposure=None)
        assert sky.layer("clouds")._light_map is not None
    with _sky(40.0) as sky:
        sky.render(_camera(), 64, 36, altitude_m=5000.0, exposure=None)
        assert sky.layer("clouds")._light_map is None
    with _sky(8.0) as sky:  # below LIGHT_MAP_MIN_ELEVATION_DEG
        sky.render(_camera(), 64, 36, exposure=None)
        assert sky.layer("clouds")._light_map is None
    with _sky(40.0) as sky:  # a small march goes without (a map costs it more than it saves)
        sky.render(_camera(), 64, 36, exposure=None)
        assert sky.layer("clouds")._light_map is None
        before = sky.render(_camera(), 320, 180, exposure=None).data.copy()
        sky.render(_camera(), 640, 640, exposure=None)  # a 320x320 march: drawn
        assert sky.layer("clouds")._light_map is not None
        # and a small frame is the same whatever came before it
        np.testing.assert_array_equal(sky.render(_camera(), 320, 180, exposure=None).data, before)


@pytest.mark.gl
def test_shadow_query_steps_checked():
    # light_transmittance's steps: an integer in 1-64, else one line naming it
    from skydome.errors import ParameterError

    with _sky(40.0) as sky:
        sky.render(_camera(), 32, 18, exposure=None)
        layer = sky.layer("clouds")
        for bad in (0, 65, 2.5, True, "8"):
            with pytest.raises(ParameterError, match="steps"):
                layer.light_transmittance([[0.0, 0.0, 0.0]], steps=bad)
        one, many = (layer.light_transmittance([[0.0, 0.0, 0.0]], steps=s) for s in (1, 64))
    assert one.shape == many.shape == (1,)
    assert 0.0 <= one[0] <= 1.0 and 0.0 <= many[0] <= 1.0
