"""Crepuscular rays: the air in the clouds' shadows at a low Sun, drawn as rays that converge on
the Sun (the clouds' light shafts, clouds/cloud_shafts.glsl, taken off the sky about the
shadows' mean distance: atmosphere/shadow_map.glsl).

A ray is a shadow beam seen in perspective: along it the sky is darkened at every distance
from the Sun, so the darkening's profile across position angles about the Sun is the same
near it and far from it. Blobs (the shadows sampled too sparsely, or placed at the camera)
are not.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

W, H = 480, 270
SUN_DEG = 5.0


def _frame(shafts: bool):
    from skydome import Sky
    from skydome.clouds.layer import CloudLayer
    from skydome.clouds.params import Clouds

    layer = CloudLayer(Clouds("fair", coverage=0.15, seed=1), shafts=shafts)
    with Sky(sun_elevation_deg=SUN_DEG, sun_azimuth_deg=180.0, clouds=layer) as sky:
        camera = sky.camera("sun", fov_deg=100, pitch_deg=18)
        frame = sky.render(camera, W, H, exposure=None)
        x, y = np.meshgrid(np.arange(W) + 0.5, np.arange(H) + 0.5)
        dirs, _ = camera.directions(x, y, W, H)
    return frame.data[..., 1], np.asarray(dirs)[::-1]  # the frame's rows are top first


@pytest.mark.gl
def test_crepuscular_rays_converge_on_the_sun():
    # fair cumulus (15 % cover) with the Sun 5 deg up behind them: the frame with light shafts
    # over the frame without, in the open sky (away from the clouds' pixels, where the two
    # are equal); the shafts only take light off; across position angles about the Sun
    # (3 deg bins) the darkening at 8-12 deg from it and at 18-26 deg, each less its
    # quadratic trend, correlate above 0.85 (0.96 drawn; the shadows sampled three times
    # per crossing, at the camera, gave 0.62)
    shafted, dirs = _frame(True)
    plain, _ = _frame(False)
    ratio = shafted / plain
    assert ratio.max() <= 1.0 + 1e-5
    e = math.radians(SUN_DEG)
    sun = np.array([0.0, -math.cos(e), math.sin(e)])
    angle = np.degrees(np.arccos(np.clip(dirs @ sun, -1.0, 1.0)))
    elevation = np.degrees(np.arcsin(dirs[..., 2]))
    cloud = np.abs(ratio - 1.0) < 1e-3
    near = cloud.copy()  # the clouds' pixels and four around them
    for dy in range(-4, 5):
        for dx in range(-4, 5):
            near |= np.roll(np.roll(cloud, dy, 0), dx, 1)
    across = np.cross(sun, [0.0, 0.0, 1.0])
    across /= np.linalg.norm(across)
    position = np.degrees(np.arctan2(dirs @ across, dirs @ np.cross(across, sun)))

    def profile(lo, hi):
        pick = (angle > lo) & (angle < hi) & (elevation > 1.0) & ~near
        k = np.floor((position[pick] + 90.0) / 3.0).astype(int)
        return np.array([ratio[pick][k == b].mean() if np.sum(k == b) >= 5 else np.nan
                         for b in range(60)])  # fmt: skip

    near_sun, far = profile(8.0, 12.0), profile(18.0, 26.0)
    ok = ~np.isnan(near_sun) & ~np.isnan(far)
    assert ok.sum() >= 10
    bins = np.arange(60)[ok]

    def detrended(p):
        return p[ok] - np.polyval(np.polyfit(bins, p[ok], 2), bins)

    assert np.corrcoef(detrended(near_sun), detrended(far))[0, 1] > 0.85
