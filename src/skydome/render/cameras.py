"""Cameras: how pixels map to view directions in the observer's ENU frame.

The per-pixel mapping itself lives in ``shaders/common/camera.glsl``; these classes hold and
validate the parameters and give the shader its uniforms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skydome.astro.frames import horizontal_to_enu
from skydome.errors import ParameterError, check_choice, check_range

#: Largest frame side accepted (pixels); bigger frames exceed typical GL texture limits.
MAX_SIDE = 16384
#: Valid ranges (deg) of the perspective camera's horizontal field of view and orientation.
FOV_RANGE_DEG = (0.01, 179.0)
PITCH_RANGE_DEG = (-90.0, 90.0)
YAW_RANGE_DEG = (-360.0, 360.0)
ROLL_RANGE_DEG = (-360.0, 360.0)


def direction_from_angles(elevation_deg: float, azimuth_deg: float) -> np.ndarray:
    """Unit ENU vector (x east, y north, z up) from elevation and azimuth (from north via east)."""
    return horizontal_to_enu(math.radians(elevation_deg), math.radians(azimuth_deg))


def check_size(width: int, height: int) -> tuple[int, int]:
    """Validate a frame size; returns it as ints."""
    for name, v in (("width", width), ("height", height)):
        if not isinstance(v, (int, np.integer)) or not 1 <= v <= MAX_SIDE:
            raise ParameterError(f"frame {name} = {v} must be an integer in [1, {MAX_SIDE}]")
    return int(width), int(height)


@dataclass(frozen=True)
class Camera:
    """Base class; ``model`` selects the mapping in common/camera.glsl."""

    model = -1
    name = ""

    def frame_size(self, width: int, height: int) -> tuple[int, int]:
        """Size of the image this camera renders for a requested ``width`` x ``height``."""
        return check_size(width, height)

    def uniforms(self, width: int, height: int) -> dict[str, object]:
        return {"u_resolution": (float(width), float(height))}


@dataclass(frozen=True)
class PerspectiveCamera(Camera):
    """Pinhole camera. ``fov_deg`` is the horizontal field of view; ``yaw_deg`` the azimuth of
    the view direction (from north through east), ``pitch_deg`` its elevation, ``roll_deg`` a
    rotation about the view direction (positive tilts the camera's up vector towards
    its right, so the scene turns counter-clockwise in the image)."""

    fov_deg: float = 90.0
    yaw_deg: float = 0.0
    pitch_deg: float = 0.0
    roll_deg: float = 0.0
    model = 0
    name = "perspective"

    def __post_init__(self):
        check_range("fov_deg", self.fov_deg, *FOV_RANGE_DEG, "deg")
        check_range("pitch_deg", self.pitch_deg, *PITCH_RANGE_DEG, "deg")
        check_range("yaw_deg", self.yaw_deg, *YAW_RANGE_DEG, "deg")
        check_range("roll_deg", self.roll_deg, *ROLL_RANGE_DEG, "deg")

    def basis(self) -> np.ndarray:
        """3x3 matrix with columns right, up, forward in ENU."""
        forward = direction_from_angles(self.pitch_deg, self.yaw_deg)
        # At the zenith/nadir the horizontal reference is the yaw direction itself.
        ref = np.array([0.0, 0.0, 1.0])
        if abs(forward[2]) > 0.999999:
            ref = -np.sign(forward[2]) * direction_from_angles(0.0, self.yaw_deg)
        right = np.cross(forward, ref)
        right /= np.linalg.norm(right)
        up = np.cross(right, forward)
        c, s = math.cos(math.radians(self.roll_deg)), math.sin(math.radians(self.roll_deg))
        right, up = c * right - s * up, s * right + c * up
        return np.stack([right, up, forward], axis=1)

    def uniforms(self, width: int, height: int) -> dict[str, object]:
        return {
            **super().uniforms(width, height),
            # GLSL mat3 is column-major: pass the columns one after the other.
            "u_camera_basis": tuple(self.basis().T.ravel()),
            "u_tan_half_fov": math.tan(math.radians(self.fov_deg) / 2.0),
        }


@dataclass(frozen=True)
class FisheyeCamera(Camera):
    """Equidistant 180-degree fisheye looking at the zenith: centre = zenith, the inscribed
    circle = horizon, north up and east left (as seen looking up). Pixels outside are 0."""

    model = 1
    name = "fisheye"


@dataclass(frozen=True)
class EquirectCamera(Camera):
    """Equirectangular 360x180 environment map: azimuth 0 (north) at the left edge increasing
    eastward, zenith at the top row, nadir at the bottom."""

    model = 2
    name = "equirect"


@dataclass(frozen=True)
class CubemapCamera(Camera):
    """Six square faces side by side (+X east, -X west, +Y north, -Y south, +Z up, -Z down),
    each seen from inside with up = zenith (and north at the top for the up/down faces).
    The requested height is the face size; the image is 6·height wide."""

    model = 3
    name = "cubemap"

    def frame_size(self, width: int, height: int) -> tuple[int, int]:
        check_size(width, height)
        return check_size(6 * int(height), int(height))


@dataclass(frozen=True, eq=False)
class DirectionsCamera(Camera):
    """One pixel per given direction: ``directions`` is (H, W, 3) or (N, 3) of ENU vectors
    (N directions render as an N x 1 frame). For sampling the sky in chosen directions."""

    directions: np.ndarray = None
    model = 4
    name = "directions"

    def __post_init__(self):
        d = np.asarray(self.directions, dtype=np.float64)
        if d.ndim == 2:
            d = d[None]
        if d.ndim != 3 or d.shape[-1] != 3 or not np.all(np.isfinite(d)):
            raise ParameterError(
                f"directions must be a finite (H, W, 3) or (N, 3) array, got shape {d.shape}"
            )
        norm = np.linalg.norm(d, axis=-1, keepdims=True)
        if np.any(norm == 0):
            raise ParameterError("directions must be non-zero vectors")
        check_size(d.shape[1], d.shape[0])
        object.__setattr__(self, "directions", d / norm)

    def frame_size(self, width: int | None = None, height: int | None = None) -> tuple[int, int]:
        return self.directions.shape[1], self.directions.shape[0]


CAMERAS = {
    "perspective": PerspectiveCamera,
    "fisheye": FisheyeCamera,
    "equirect": EquirectCamera,
    "cubemap": CubemapCamera,
}


def make_camera(name: str, **kwargs) -> Camera:
    """Camera by name; only the perspective camera takes fov/yaw/pitch/roll."""
    check_choice("camera", name, CAMERAS, "camera")
    if name != "perspective":
        return CAMERAS[name]()
    return PerspectiveCamera(**kwargs)


def _rim(direction: np.ndarray, radius_rad: float, points: int = 16) -> np.ndarray:
    """The centre and ``points`` directions on a circle of angular radius ``radius_rad``
    around the unit vector ``direction`` (N + 1, 3)."""
    u = direction / np.linalg.norm(direction)
    e1 = np.cross(u, [0.0, 0.0, 1.0] if abs(u[2]) < 0.9 else [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    a = np.linspace(0.0, 2.0 * np.pi, points, endpoint=False)
    ring = math.cos(radius_rad) * u + math.sin(radius_rad) * (
        np.cos(a)[:, None] * e1 + np.sin(a)[:, None] * e2
    )
    return np.vstack([u, ring])


def _rects(camera: Camera, d: np.ndarray, w: int, h: int) -> list | None:
    """Pixel rectangles (x0, y0, x1, y1; GL: y up) that hold the directions ``d`` (N, 3)
    for camera models with a closed-form inverse of camera.glsl; None where there is none."""
    from skydome.render.projection import project  # it imports this module

    if isinstance(camera, PerspectiveCamera):
        forward = d @ camera.basis()[:, 2]
        if np.all(forward <= 0.0):
            return []  # wholly behind the camera
        if np.any(forward <= 1e-6):
            return None
        x, y, _ = project(camera, d, w, h)
        return [(x.min(), y.min(), x.max(), y.max())]
    if isinstance(camera, FisheyeCamera):
        x, y, _ = project(camera, d, w, h)
        return [(x.min(), y.min(), x.max(), y.max())]
    if isinstance(camera, EquirectCamera):
        x, y, _ = project(camera, d, w, h)
        el = np.arcsin(np.clip(d[:, 2], -1.0, 1.0))
        if np.max(np.abs(el)) > math.radians(89.0):  # around a pole: whole rows
            return [(0.0, y.min(), float(w), float(h) if el.max() > 0 else y.max())]
        if np.ptp(x) > 0.5 * w:  # across the seam at azimuth 0: one rectangle each side
            a = np.where(x > 0.5 * w, x - w, x)
            return [(a.min() + w, y.min(), float(w), y.max()), (0.0, y.min(), a.max(), y.max())]
        return [(x.min(), y.min(), x.max(), y.max())]
    return None


def disk_scissor(
    camera: Camera, width: int, height: int, direction, radius_rad: float, margin_px: int = 2
) -> list[tuple[int, int, int, int]] | None:
    """Pixel rectangles (x, y, w, h; GL: y up from the bottom) holding every pixel that can
    see a disk of angular radius ``radius_rad`` around ``direction`` (unit ENU), for drawing
    small sources (the Sun, the Moon, later planets) with a scissor test instead of over the
    whole frame. An empty list when the disk is out of the frame; None when the camera has
    no simple inverse there (cube maps, direction maps): draw everything."""
    d = np.asarray(direction, dtype=np.float64)
    rects = _rects(camera, _rim(d, radius_rad), width, height)
    if rects is None:
        return None
    out = []
    for x0, y0, x1, y1 in rects:
        ax, ay = max(math.floor(x0) - margin_px, 0), max(math.floor(y0) - margin_px, 0)
        bx, by = min(math.ceil(x1) + margin_px, width), min(math.ceil(y1) + margin_px, height)
        if bx > ax and by > ay:
            out.append((ax, ay, bx - ax, by - ay))
    return out
