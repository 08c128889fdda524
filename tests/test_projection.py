"""The forward camera mapping (render.projection, common/camera_project.glsl) against
camera.glsl's pixel -> direction mapping and closed-form solid angles."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from skydome.core.cameras import (
    CameraInputs,
    CubemapCamera,
    EquirectCamera,
    FisheyeCamera,
    PerspectiveCamera,
)
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs

CAMERAS = [
    (PerspectiveCamera(fov_deg=70.0, yaw_deg=120.0, pitch_deg=25.0, roll_deg=10.0), 320, 200),
    (FisheyeCamera(), 256, 256),
    (EquirectCamera(), 512, 256),
    (CubemapCamera(), 6 * 64, 64),
]
IDS = ["perspective", "fisheye", "equirect", "cubemap"]

# Each pixel writes its camera_ray direction and where camera_project puts it back.
SOURCE = """
#include "common/camera_project.glsl"
uniform int u_what;
out vec4 frag;
void main() {
    vec3 dir;
    bool ok = camera_ray(gl_FragCoord.xy, dir);
    if (u_what == 0) { frag = vec4(dir, ok ? 1.0 : 0.0); return; }
    vec2 xy;
    bool seen = camera_project(dir, xy);
    frag = vec4(xy - (gl_FragCoord.xy + u_tile_offset), camera_pixel_solid_angle(dir),
                (ok && seen) ? 1.0 : 0.0);
}
"""


@dataclass(frozen=True)
class WhatInputs(ShaderInputs):
    """What the test pass writes: 0 the directions, 1 the projection's round trip."""

    u_what: int


def _gpu(ctx, camera, w, h, what):
    fpass = FullscreenPass(
        ctx, "test_project.glsl", {"CAMERA_MODEL": camera.model},
        inputs=(CameraInputs, WhatInputs), source=SOURCE,
    )  # fmt: skip
    tex = ctx.texture((w, h), 4, dtype="f4")
    fbo = ctx.framebuffer(color_attachments=[tex])
    try:
        fpass.draw(fbo, camera.inputs(w, h), WhatInputs(what))
        return np.frombuffer(tex.read(), np.float32).reshape(h, w, 4)  # GL rows
    finally:
        fbo.release()
        tex.release()
        fpass.release()


def _centres(w, h):
    y, x = np.mgrid[0:h, 0:w] + 0.5
    return x, y


@pytest.mark.parametrize(("camera", "w", "h"), CAMERAS, ids=IDS)
def test_numpy_mapping_is_camera_glsl_and_projects_back(ctx, camera, w, h):
    x, y = _centres(w, h)
    d, ok = camera.directions(x, y, w, h)
    gpu = _gpu(ctx, camera, w, h, 0)
    seen = ok & (gpu[..., 3] > 0.5)
    # float32 trigonometry: a few 1e-6 per component.
    np.testing.assert_allclose(gpu[..., :3][seen], d[seen], atol=5e-6)
    px, py, vis = camera.project(d, w, h)
    # Round trip exact to rounding (cube-map pixels on a face edge may pick the other face).
    good = seen & vis
    assert good.mean() > 0.75
    np.testing.assert_allclose(px[good], x[good], atol=1e-6)
    np.testing.assert_allclose(py[good], y[good], atol=1e-6)


@pytest.mark.parametrize(("camera", "w", "h"), CAMERAS, ids=IDS)
def test_glsl_projection_returns_each_pixel_to_itself(ctx, camera, w, h):
    out = _gpu(ctx, camera, w, h, 1)
    seen = out[..., 3] > 0.5
    off = np.hypot(out[..., 0], out[..., 1])[seen]
    if camera.model == 2:  # the seam: azimuth 2 pi - eps may come back as 0
        off = np.minimum(off, np.abs(off - w))
    # float32 atan/asin of a float32 direction: ~1e-6 rad, under 1e-3 px at these sizes.
    assert np.percentile(off, 99.9) < 2e-3 and off.max() < 0.02
    x, y = _centres(w, h)
    d, _ = camera.directions(x, y, w, h)
    ref = camera.solid_angle(d, w, h)
    np.testing.assert_allclose(out[..., 2][seen], ref[seen], rtol=2e-5)


def test_pixel_solid_angles_add_up_to_the_closed_forms():
    # Equirect and cube map: the whole sphere, 4 pi.
    for camera, w, h in ((EquirectCamera(), 1024, 512), (CubemapCamera(), 6 * 256, 256)):
        x, y = _centres(w, h)
        d, _ = camera.directions(x, y, w, h)
        assert camera.solid_angle(d, w, h).sum() == pytest.approx(4 * math.pi, rel=1e-4)
    # A pinhole frame: the rectangle's pyramid, 4 asin(sin(a) sin(b)) for half-angles a, b.
    cam, w, h = PerspectiveCamera(fov_deg=100.0), 800, 500
    x, y = _centres(w, h)
    d, _ = cam.directions(x, y, w, h)
    a = math.radians(50.0)
    b = math.atan(math.tan(a) * h / w)
    exact = 4 * math.asin(math.sin(a) * math.sin(b))
    assert cam.solid_angle(d, w, h).sum() == pytest.approx(exact, rel=1e-5)
    # Fisheye: the hemisphere, 2 pi, to the pixels cut by the horizon circle (~1/side).
    cam, w, h = FisheyeCamera(), 1024, 1024
    x, y = _centres(w, h)
    d, ok = cam.directions(x, y, w, h)
    assert cam.solid_angle(d, w, h)[ok].sum() == pytest.approx(2 * math.pi, rel=2e-3)
