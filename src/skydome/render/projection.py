"""Where a direction lands in a frame: the forward mapping of ``shaders/common/camera.glsl``.

``camera.glsl`` maps a pixel to its view direction; point sources (stars, planets) and
overlays (constellation lines, labels) need the inverse: the frame position of a direction,
and the solid angle of a pixel there. This is the float64 twin of
``shaders/common/camera_project.glsl``; the tests hold both to ``camera_ray``.

Frame positions are GL pixel coordinates of the whole frame: x to the right, y up from the
bottom edge, pixel (i, j) covering [i, i + 1] x [j, j + 1] (its centre, gl_FragCoord, at
i + 0.5). A ``DirectionsCamera`` has no forward mapping (its pixels are arbitrary).
"""

from __future__ import annotations

import math

import numpy as np

from skydome.errors import ParameterError
from skydome.render.cameras import (
    Camera,
    CubemapCamera,
    EquirectCamera,
    FisheyeCamera,
    PerspectiveCamera,
)

__all__ = [
    "has_projection",
    "project",
    "pixel_solid_angle",
    "pixel_directions",
    "centre_pixel_angle",
]


def has_projection(camera: Camera) -> bool:
    """True for the camera models with a closed-form forward mapping."""
    return isinstance(camera, (PerspectiveCamera, FisheyeCamera, EquirectCamera, CubemapCamera))


def _unit(directions) -> np.ndarray:
    d = np.asarray(directions, dtype=np.float64)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def _cube_face(d: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Face index (camera.glsl's order) and face coordinates p in [-1, 1]^2 of directions."""
    ax = np.argmax(np.abs(d), axis=-1)
    comp = np.take_along_axis(d, ax[..., None], axis=-1)[..., 0]
    face = 2 * ax + (comp < 0)
    m = np.abs(comp)
    x, y, z = d[..., 0] / m, d[..., 1] / m, d[..., 2] / m
    # Inverses of cube_face_direction: +X (1,-px,py), -X (-1,px,py), +Y (px,1,py),
    # -Y (-px,-1,py), +Z (-px,py,1), -Z (px,py,-1).
    px = np.choose(face, [-y, y, x, -x, -x, x])
    py = np.choose(face, [z, z, z, z, y, y])
    return face, px, py


def project(camera: Camera, directions, width: int, height: int):
    """Frame positions (x, y) in GL pixels of unit ENU ``directions`` (..., 3) for a frame
    of ``width`` x ``height`` (the camera's frame size), and a mask of the directions the
    camera sees (in front of a perspective camera, above the fisheye's horizon)."""
    d = _unit(directions)
    w, h = float(width), float(height)
    if isinstance(camera, PerspectiveCamera):
        local = d @ camera.basis()  # (right, up, forward)
        t = math.tan(math.radians(camera.fov_deg) / 2.0)
        f = local[..., 2]
        ok = f > 1e-9
        safe = np.where(ok, f, 1.0)
        x = (local[..., 0] / (safe * t) + 1.0) * 0.5 * w
        y = (local[..., 1] / (safe * t / (w / h)) + 1.0) * 0.5 * h
        return x, y, ok
    if isinstance(camera, FisheyeCamera):
        zenith = np.arccos(np.clip(d[..., 2], -1.0, 1.0))
        az = np.arctan2(d[..., 0], d[..., 1])
        rho = zenith / (0.5 * math.pi) * 0.5 * min(w, h)
        return 0.5 * w - rho * np.sin(az), 0.5 * h + rho * np.cos(az), zenith <= 0.5 * math.pi
    if isinstance(camera, EquirectCamera):
        el = np.arcsin(np.clip(d[..., 2], -1.0, 1.0))
        az = np.mod(np.arctan2(d[..., 0], d[..., 1]), 2.0 * math.pi)
        return az / (2.0 * math.pi) * w, (el / math.pi + 0.5) * h, np.ones(d.shape[:-1], bool)
    if isinstance(camera, CubemapCamera):
        face, px, py = _cube_face(d)
        side = h
        x = face * side + (px + 1.0) * 0.5 * side
        return x, (py + 1.0) * 0.5 * side, np.ones(d.shape[:-1], bool)
    raise ParameterError(f"a {camera.name} camera has no forward mapping (no point sources)")


def pixel_solid_angle(camera: Camera, directions, width: int, height: int) -> np.ndarray:
    """Solid angle (sr) of one pixel of the frame where it sees each of ``directions``."""
    d = _unit(directions)
    w, h = float(width), float(height)
    if isinstance(camera, PerspectiveCamera):
        local = d @ camera.basis()
        f = np.maximum(local[..., 2], 1e-12)
        step = 2.0 * math.tan(math.radians(camera.fov_deg) / 2.0) / w  # tangent-plane pixel
        # dOmega = dA cos^3(theta) on the plane at unit distance: cos(theta) = f / |local|.
        return step * step * f**3
    if isinstance(camera, FisheyeCamera):
        k = (0.5 * math.pi) / (0.5 * min(w, h))  # rad per pixel, radially and across
        z = np.arccos(np.clip(d[..., 2], -1.0, 1.0))
        return k * k * np.where(z > 1e-9, np.sin(z) / np.maximum(z, 1e-12), 1.0)
    if isinstance(camera, EquirectCamera):
        cos_el = np.sqrt(np.maximum(1.0 - d[..., 2] ** 2, 0.0))
        return (2.0 * math.pi / w) * (math.pi / h) * cos_el
    if isinstance(camera, CubemapCamera):
        m = np.max(np.abs(d), axis=-1)
        step = 2.0 / h
        return step * step * m**3
    raise ParameterError(f"a {camera.name} camera has no forward mapping (no point sources)")


def pixel_directions(camera: Camera, x, y, width: int, height: int):
    """The view directions at frame positions (x, y) (GL pixels), as camera.glsl computes
    them for pixel centres, and a mask of the positions that see the sky (float64)."""
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    w, h = float(width), float(height)
    ok = np.ones(np.broadcast(x, y).shape, bool)
    if isinstance(camera, PerspectiveCamera):
        t = math.tan(math.radians(camera.fov_deg) / 2.0)
        local = np.stack(
            np.broadcast_arrays((2 * x / w - 1) * t, (2 * y / h - 1) * t / (w / h), 1.0), -1
        )
        d = local @ camera.basis().T
    elif isinstance(camera, FisheyeCamera):
        side = min(w, h)
        px, py = (x - 0.5 * w) / (0.5 * side), (y - 0.5 * h) / (0.5 * side)
        rho = np.hypot(px, py)
        ok = rho <= 1.0
        zen, az = rho * 0.5 * math.pi, np.arctan2(-px, py)
        d = np.stack([np.sin(zen) * np.sin(az), np.sin(zen) * np.cos(az), np.cos(zen)], -1)
    elif isinstance(camera, EquirectCamera):
        az, el = x / w * 2 * math.pi, (y / h - 0.5) * math.pi
        d = np.stack([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)], -1)
    elif isinstance(camera, CubemapCamera):
        side = h
        face = np.clip(np.floor(x / side), 0, 5).astype(int)
        px, py = np.mod(x, side) / side * 2 - 1, y / side * 2 - 1
        one = np.ones_like(px)
        d = np.stack(
            [
                np.choose(face, [one, -one, px, -px, -px, px]),
                np.choose(face, [-px, px, one, -one, py, py]),
                np.choose(face, [py, py, py, py, one, -one]),
            ],
            -1,
        )
    else:
        raise ParameterError(f"a {camera.name} camera has no closed-form pixel mapping")
    return _unit(d), ok


def centre_pixel_angle(camera: Camera, width: int, height: int) -> float:
    """Angular size (rad) of a pixel at the frame's centre: the square root of its solid
    angle (for a direction map, the mean over its pixels' spread is not defined: 0)."""
    if not has_projection(camera):
        return 0.0
    d, _ = pixel_directions(camera, 0.5 * width, 0.5 * height, width, height)
    return float(np.sqrt(pixel_solid_angle(camera, d, width, height)))
