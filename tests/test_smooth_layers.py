"""The frame graph's reduced-resolution path for smooth space layers (Layer.smooth_deg):
which cameras and scales get it, and that the upsampled light equals the full-resolution
light for a smooth field, alone, through the atmosphere, and across tile borders."""

from __future__ import annotations

import math

import numpy as np
import pytest

from skydome import Sky
from skydome.core.cameras import (
    CubemapCamera,
    DirectionsCamera,
    EquirectCamera,
    FisheyeCamera,
    PerspectiveCamera,
)
from skydome.core.layer import Layer
from skydome.scene.graph import MAX_SMOOTH_FACTOR, smooth_factor

# A smooth field of the direction (cd/m^2): brighter towards the east and the zenith.
SOURCE = """
#include "common/camera.glsl"
out vec4 frag;
void main() {
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) { frag = vec4(0.0); return; }
    float v = 1e-3 * (2.0 + dir.x + 0.5 * dir.z * dir.z);
    frag = vec4(v, v, v, 2.0 * v);
}
"""


def field(d: np.ndarray) -> np.ndarray:
    return 1e-3 * (2.0 + d[..., 0] + 0.5 * d[..., 2] ** 2)


class SmoothGlow(Layer):
    name = "smooth_glow"
    stage = "space"
    smooth_deg = 2.0

    def draw(self, frame):
        fpass = self.glow_pass(frame.ctx, frame.camera)
        fpass.draw(frame.fbo, frame.view)

    def glow_pass(self, ctx, camera):
        from skydome.core.cameras import CameraInputs
        from skydome.gpu import FullscreenPass

        key = ("test_smooth.glsl", camera.model)
        if key not in self._passes:
            self._passes[key] = FullscreenPass(
                ctx, "test_smooth.glsl", {"CAMERA_MODEL": camera.model}, inputs=(CameraInputs,),
                source=SOURCE,
            )  # fmt: skip
        return self._passes[key]


class SharpGlow(SmoothGlow):
    smooth_deg = None


def test_which_frames_are_drawn_reduced():
    # 90 deg over 1280 px: 0.0895 deg at the centre.
    cam = PerspectiveCamera(fov_deg=90.0)
    assert smooth_factor(cam, (1280, 720), 0.18) == 2
    assert smooth_factor(cam, (1280, 720), 0.1) == 1
    assert smooth_factor(cam, (1280, 720), 2.0) == MAX_SMOOTH_FACTOR
    assert smooth_factor(EquirectCamera(), (1024, 512), 0.18) == 1  # 0.35 deg pixels
    assert smooth_factor(FisheyeCamera(), (1024, 1024), 0.5) == 2  # 0.176 deg pixels
    assert MAX_SMOOTH_FACTOR == 4
    assert smooth_factor(CubemapCamera(), (6 * 256, 256), 10.0) == 1  # faces apart
    assert smooth_factor(DirectionsCamera(np.eye(3)), (3, 1), 10.0) == 1


@pytest.mark.parametrize(
    ("camera", "w", "h"),
    [
        (PerspectiveCamera(fov_deg=60.0, yaw_deg=80.0, pitch_deg=20.0), 640, 360),
        (FisheyeCamera(), 512, 512),
        (EquirectCamera(), 4096, 2048),  # two tiles: the reduced tiles' margins meet
    ],
    ids=["perspective", "fisheye", "equirect-tiled"],
)
def test_reduced_light_alone_equals_the_field(camera, w, h):
    # No volume layer: the graph adds the reduced light itself (scene/add_smooth.glsl).
    f = smooth_factor(camera, (w, h), SmoothGlow.smooth_deg)
    assert f > 1
    got = Sky(sun_elevation_deg=-30.0, layers=[SmoothGlow()]).render(camera, w, h, exposure=None)
    y, x = np.mgrid[0:h, 0:w] + 0.5
    d, seen = camera.directions(x, y[::-1], w, h)  # rows of the frame: top first
    inside = seen.copy()
    if isinstance(camera, FisheyeCamera):
        # Within a reduced pixel of the horizon circle the bilinear read meets the zeros
        # outside it: the atmosphere's ground hides those pixels in a sky.
        rho = np.hypot(x - w / 2, y - h / 2) / (w / 2)
        inside &= rho < 1.0 - 2.0 * f / w * 2
    ref = field(d)
    # Bilinear interpolation of a smooth field from pixels f times larger: the error is the
    # field's curvature over a reduced pixel, here < 1e-4 relative.
    np.testing.assert_allclose(got.data[..., 1][inside], ref[inside], rtol=2e-4)


def test_reduced_light_through_the_atmosphere_equals_full_resolution():
    # The atmosphere reads the reduced light in its own composite (common/behind.glsl).
    cam, w, h = PerspectiveCamera(fov_deg=60.0, yaw_deg=80.0, pitch_deg=20.0), 640, 360
    smooth = Sky(sun_elevation_deg=-30.0, extra_layers=[SmoothGlow()])
    sharp = Sky(sun_elevation_deg=-30.0, extra_layers=[SharpGlow()])
    a = smooth.render(cam, w, h, exposure=None).data
    b = sharp.render(cam, w, h, exposure=None).data
    sky = b[..., 1] > 1e-4  # above the ground
    assert sky.mean() > 0.5
    np.testing.assert_allclose(a[..., 1][sky], b[..., 1][sky], rtol=5e-4)
    smooth.layer("smooth_glow").enabled = False
    plain = Sky(sun_elevation_deg=-30.0).render(cam, w, h, exposure=None).data
    assert np.array_equal(smooth.render(cam, w, h, exposure=None).data, plain)


def test_factor_one_is_the_full_resolution_path():
    # Pixels as large as the layer's detail: drawn at full resolution, bit for bit.
    cam, w, h = EquirectCamera(), 256, 128  # 1.4 deg pixels, > 2 deg / 2
    assert smooth_factor(cam, (w, h), 2.0) == 1
    a = Sky(sun_elevation_deg=-30.0, layers=[SmoothGlow()]).render(cam, w, h, exposure=None)
    b = Sky(sun_elevation_deg=-30.0, layers=[SharpGlow()]).render(cam, w, h, exposure=None)
    assert np.array_equal(a.data, b.data)
    assert math.isfinite(float(a.data.sum()))
