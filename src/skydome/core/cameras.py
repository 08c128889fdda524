"""Cameras: how pixels map to view directions in the observer's ENU frame, and back.

The per-pixel mapping lives in ``shaders/common/camera.glsl`` (pixel -> direction) and
``shaders/common/camera_project.glsl`` (direction -> pixel); each camera class holds and
validates its parameters, gives the shader its uniforms, and carries the float64 twins of
both mappings as methods (``directions``, ``project``) with the solid angle of a pixel
(``solid_angle``). The tests hold the twins to ``camera_ray``.

Frame positions are GL pixel coordinates of the whole frame: x to the right, y up from the
bottom edge, pixel (i, j) covering [i, i + 1] x [j, j + 1] (its centre, gl_FragCoord, at
i + 0.5). A ``DirectionsCamera`` has no closed-form mapping (its pixels are arbitrary).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from skydome.errors import ParameterError, check_choice, check_range
from skydome.gpu.inputs import ShaderInputs
from skydome.physics.geometry import direction_from_angles
from skydome.physics.packing import mat3

__all__ = [
    "CAMERAS",
    "Camera",
    "CubemapCamera",
    "DirectionsCamera",
    "EquirectCamera",
    "FisheyeCamera",
    "PerspectiveCamera",
    "check_size",
    "direction_from_angles",
    "disk_samples",
    "disk_scissor",
    "make_camera",
]

#: Largest frame side accepted (pixels); bigger frames exceed typical GL texture limits.
MAX_SIDE = 16384
#: Valid ranges (deg) of the perspective camera's horizontal field of view and orientation.
FOV_RANGE_DEG = (0.01, 179.0)
PITCH_RANGE_DEG = (-90.0, 90.0)
YAW_RANGE_DEG = (-360.0, 360.0)
ROLL_RANGE_DEG = (-360.0, 360.0)
#: Largest camera altitude accepted (m).
MAX_ALTITUDE_M = 1e8
#: Cameras closer to the ground are raised to this height (m): float32 positions in km are
#: resolved to about 0.5 m at the planet radius.
MIN_ALTITUDE_M = 1.0


def check_size(width: int, height: int) -> tuple[int, int]:
    """Validate a frame size; returns it as ints."""
    for name, v in (("width", width), ("height", height)):
        if not isinstance(v, (int, np.integer)) or not 1 <= v <= MAX_SIDE:
            raise ParameterError(f"frame {name} = {v} must be an integer in [1, {MAX_SIDE}]")
    return int(width), int(height)


def effective_altitude_m(altitude_m: float) -> float:
    """The camera altitude (m) the renderers use: ``altitude_m`` checked, and raised to
    MIN_ALTITUDE_M when below it."""
    h = check_range("altitude", altitude_m, 0.0, MAX_ALTITUDE_M, "m")
    return max(h, MIN_ALTITUDE_M)


def check_direction(name: str, direction) -> np.ndarray:
    """A finite non-zero 3-vector, normalised."""
    s = np.asarray(direction, dtype=np.float64).reshape(-1)
    n = float(np.linalg.norm(s)) if s.shape == (3,) and np.all(np.isfinite(s)) else 0.0
    if n == 0.0:
        raise ParameterError(f"{name} must be a finite non-zero 3-vector, got {direction!r}")
    return s / n


@dataclass(frozen=True)
class CameraInputs(ShaderInputs):
    """A camera's uniforms (``shaders/common/camera.glsl``) for one tile of a frame: the
    frame's size (px), the tile's offset in it (px), the perspective camera's basis and
    field, a DirectionsCamera's direction map (a texture of the tile)."""

    u_resolution: tuple[float, float]
    u_tile_offset: tuple[float, float] = (0.0, 0.0)
    u_camera_basis: tuple[float, ...] | None = None
    u_tan_half_fov: float | None = None
    u_direction_map: object = None


def _unit(directions) -> np.ndarray:
    d = np.asarray(directions, dtype=np.float64)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


@dataclass(frozen=True)
class Camera:
    """Base class; ``model`` selects the mapping in common/camera.glsl."""

    model: ClassVar[int] = -1
    name: ClassVar[str] = ""
    #: Whether the camera has closed-form mappings (project, directions, solid_angle).
    has_projection: ClassVar[bool] = True

    def frame_size(self, width: int, height: int) -> tuple[int, int]:
        """Size of the image this camera renders for a requested ``width`` x ``height``."""
        return check_size(width, height)

    def inputs(
        self, width: float, height: float, tile_offset=(0.0, 0.0), direction_map=None
    ) -> CameraInputs:
        """The camera's shader inputs for a frame of ``width`` x ``height`` pixels, a tile
        at ``tile_offset`` (px) and, for a DirectionsCamera, the tile's direction map."""
        return CameraInputs(
            (float(width), float(height)),
            (float(tile_offset[0]), float(tile_offset[1])),
            u_direction_map=direction_map,
        )

    # ------------------------------------------------------------------ float64 twins

    def _no_mapping(self):
        return ParameterError(f"a {self.name} camera has no forward mapping (no point sources)")

    def project(self, directions, width: int, height: int):
        """Frame positions (x, y) in GL pixels of unit ENU ``directions`` (..., 3) for a frame
        of ``width`` x ``height`` (the camera's frame size), and a mask of the directions the
        camera sees (in front of a perspective camera, above the fisheye's horizon)."""
        raise self._no_mapping()

    def solid_angle(self, directions, width: int, height: int) -> np.ndarray:
        """Solid angle (sr) of one pixel of the frame where it sees each of ``directions``."""
        raise self._no_mapping()

    def directions(self, x, y, width: int, height: int):
        """The view directions at frame positions (x, y) (GL pixels), as camera.glsl
        computes them for pixel centres, and a mask of the positions that see the sky."""
        raise ParameterError(f"a {self.name} camera has no closed-form pixel mapping")

    def pixel_angle(self, width: int, height: int) -> float:
        """Angular size (rad) of a pixel at the frame's centre: the square root of its solid
        angle (0 for a camera without a closed-form mapping)."""
        if not self.has_projection:
            return 0.0
        return _pixel_angle(self, width, height)

    def _disk_rects(self, d: np.ndarray, w: int, h: int) -> list | None:
        """Pixel rectangles (x0, y0, x1, y1; GL: y up) holding the directions ``d`` (N, 3),
        or None where the camera has no simple inverse (draw everything)."""
        return None


@functools.lru_cache(maxsize=64)
def _pixel_angle(camera: Camera, width: float, height: float) -> float:
    """Camera.pixel_angle's value, cached by the (frozen) camera and the frame size: the
    glare, the eye and the small sources ask for it several times a frame."""
    d, _ = camera.directions(0.5 * width, 0.5 * height, width, height)
    return float(np.sqrt(camera.solid_angle(d, width, height)))


@functools.lru_cache(maxsize=256)
def _perspective_basis(pitch_deg: float, yaw_deg: float, roll_deg: float) -> np.ndarray:
    """A perspective camera's basis (columns right, up, forward in ENU), read-only. Cached:
    a frame asks for it some twenty times (its inputs, its disks' scissors, its point
    sources), and the time-lapse or the viewer's camera keeps its angles across frames."""
    forward = direction_from_angles(pitch_deg, yaw_deg)
    # At the zenith/nadir the horizontal reference is the yaw direction itself.
    ref = np.array([0.0, 0.0, 1.0])
    if abs(forward[2]) > 0.999999:
        ref = -np.sign(forward[2]) * direction_from_angles(0.0, yaw_deg)
    right = np.cross(forward, ref)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    c, s = math.cos(math.radians(roll_deg)), math.sin(math.radians(roll_deg))
    right, up = c * right - s * up, s * right + c * up
    basis = np.stack([right, up, forward], axis=1)
    basis.setflags(write=False)
    return basis


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
    model: ClassVar[int] = 0
    name: ClassVar[str] = "perspective"

    def __post_init__(self):
        check_range("fov_deg", self.fov_deg, *FOV_RANGE_DEG, "deg")
        check_range("pitch_deg", self.pitch_deg, *PITCH_RANGE_DEG, "deg")
        check_range("yaw_deg", self.yaw_deg, *YAW_RANGE_DEG, "deg")
        check_range("roll_deg", self.roll_deg, *ROLL_RANGE_DEG, "deg")

    def basis(self) -> np.ndarray:
        """3x3 matrix with columns right, up, forward in ENU (read-only: shared by every
        camera of the same angles)."""
        return _perspective_basis(self.pitch_deg, self.yaw_deg, self.roll_deg)

    def inputs(
        self, width: float, height: float, tile_offset=(0.0, 0.0), direction_map=None
    ) -> CameraInputs:
        return CameraInputs(
            (float(width), float(height)),
            (float(tile_offset[0]), float(tile_offset[1])),
            mat3(self.basis()),
            math.tan(math.radians(self.fov_deg) / 2.0),
            direction_map,
        )

    def project(self, directions, width: int, height: int):
        return self._project_local(_unit(directions) @ self.basis(), width, height)

    def _project_local(self, local: np.ndarray, width: int, height: int):
        """project() of directions already in the camera's frame (right, up, forward)."""
        w, h = float(width), float(height)
        t = math.tan(math.radians(self.fov_deg) / 2.0)
        f = local[..., 2]
        ok = f > 1e-9
        safe = np.where(ok, f, 1.0)
        x = (local[..., 0] / (safe * t) + 1.0) * 0.5 * w
        y = (local[..., 1] / (safe * t / (w / h)) + 1.0) * 0.5 * h
        return x, y, ok

    def solid_angle(self, directions, width: int, height: int) -> np.ndarray:
        local = _unit(directions) @ self.basis()
        f = np.maximum(local[..., 2], 1e-12)
        step = 2.0 * math.tan(math.radians(self.fov_deg) / 2.0) / float(width)
        # dOmega = dA cos^3(theta) on the plane at unit distance: cos(theta) = f / |local|.
        return step * step * f**3

    def directions(self, x, y, width: int, height: int):
        x, y, w, h = _positions(x, y, width, height)
        t = math.tan(math.radians(self.fov_deg) / 2.0)
        local = np.stack(
            np.broadcast_arrays((2 * x / w - 1) * t, (2 * y / h - 1) * t / (w / h), 1.0), -1
        )
        return _unit(local @ self.basis().T), np.ones(np.broadcast(x, y).shape, bool)

    def _disk_rects(self, d, w, h):
        local = _unit(d) @ self.basis()  # (right, up, forward)
        forward = local[:, 2]
        if np.all(forward <= 0.0):
            return []  # wholly behind the camera
        # Wholly beyond one of the frustum's side planes (through the eye, DISK_MARGIN_PX
        # beyond the frame's edge, as disk_scissor's rectangles): out of the frame. A disk
        # beside the camera straddles the eye's plane and would otherwise be drawn everywhere.
        tan_x = math.tan(math.radians(self.fov_deg) / 2.0) * (1.0 + 2.0 * DISK_MARGIN_PX / w)
        tan_y = math.tan(math.radians(self.fov_deg) / 2.0) * (h + 2.0 * DISK_MARGIN_PX) / w
        x, y = local[:, 0], local[:, 1]
        if (
            np.all(x > tan_x * forward)
            or np.all(x < -tan_x * forward)
            or np.all(y > tan_y * forward)
            or np.all(y < -tan_y * forward)
        ):
            return []
        if np.any(forward <= 1e-6):
            return None
        x, y, _ = self._project_local(local, w, h)
        return [(x.min(), y.min(), x.max(), y.max())]


@dataclass(frozen=True)
class FisheyeCamera(Camera):
    """Equidistant 180-degree fisheye looking at the zenith: centre = zenith, the inscribed
    circle = horizon, north up and east left (as seen looking up). Pixels outside are 0."""

    model: ClassVar[int] = 1
    name: ClassVar[str] = "fisheye"

    def project(self, directions, width: int, height: int):
        d = _unit(directions)
        w, h = float(width), float(height)
        zenith = np.arccos(np.clip(d[..., 2], -1.0, 1.0))
        az = np.arctan2(d[..., 0], d[..., 1])
        rho = zenith / (0.5 * math.pi) * 0.5 * min(w, h)
        return 0.5 * w - rho * np.sin(az), 0.5 * h + rho * np.cos(az), zenith <= 0.5 * math.pi

    def solid_angle(self, directions, width: int, height: int) -> np.ndarray:
        d = _unit(directions)
        k = (0.5 * math.pi) / (0.5 * min(float(width), float(height)))  # rad per pixel
        z = np.arccos(np.clip(d[..., 2], -1.0, 1.0))
        return k * k * np.where(z > 1e-9, np.sin(z) / np.maximum(z, 1e-12), 1.0)

    def directions(self, x, y, width: int, height: int):
        x, y, w, h = _positions(x, y, width, height)
        side = min(w, h)
        px, py = (x - 0.5 * w) / (0.5 * side), (y - 0.5 * h) / (0.5 * side)
        rho = np.hypot(px, py)
        zen, az = rho * 0.5 * math.pi, np.arctan2(-px, py)
        d = np.stack([np.sin(zen) * np.sin(az), np.sin(zen) * np.cos(az), np.cos(zen)], -1)
        return _unit(d), rho <= 1.0

    def _disk_rects(self, d, w, h):
        x, y, _ = self.project(d, w, h)
        return [(x.min(), y.min(), x.max(), y.max())]


@dataclass(frozen=True)
class EquirectCamera(Camera):
    """Equirectangular 360x180 environment map: azimuth 0 (north) at the left edge increasing
    eastward, zenith at the top row, nadir at the bottom."""

    model: ClassVar[int] = 2
    name: ClassVar[str] = "equirect"

    def project(self, directions, width: int, height: int):
        d = _unit(directions)
        w, h = float(width), float(height)
        el = np.arcsin(np.clip(d[..., 2], -1.0, 1.0))
        az = np.mod(np.arctan2(d[..., 0], d[..., 1]), 2.0 * math.pi)
        return az / (2.0 * math.pi) * w, (el / math.pi + 0.5) * h, np.ones(d.shape[:-1], bool)

    def solid_angle(self, directions, width: int, height: int) -> np.ndarray:
        d = _unit(directions)
        cos_el = np.sqrt(np.maximum(1.0 - d[..., 2] ** 2, 0.0))
        return (2.0 * math.pi / float(width)) * (math.pi / float(height)) * cos_el

    def directions(self, x, y, width: int, height: int):
        x, y, w, h = _positions(x, y, width, height)
        az, el = x / w * 2 * math.pi, (y / h - 0.5) * math.pi
        d = np.stack([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)], -1)
        return _unit(d), np.ones(np.broadcast(x, y).shape, bool)

    def _disk_rects(self, d, w, h):
        x, y, _ = self.project(d, w, h)
        el = np.arcsin(np.clip(d[:, 2], -1.0, 1.0))
        if np.max(np.abs(el)) > math.radians(89.0):  # around a pole: whole rows
            return [(0.0, y.min(), float(w), float(h) if el.max() > 0 else y.max())]
        if np.ptp(x) > 0.5 * w:  # across the seam at azimuth 0: one rectangle each side
            a = np.where(x > 0.5 * w, x - w, x)
            return [(a.min() + w, y.min(), float(w), y.max()), (0.0, y.min(), a.max(), y.max())]
        return [(x.min(), y.min(), x.max(), y.max())]


@dataclass(frozen=True)
class CubemapCamera(Camera):
    """Six square faces side by side (+X east, -X west, +Y north, -Y south, +Z up, -Z down),
    each seen from inside with up = zenith (and north at the top for the up/down faces).
    The requested height is the face size; the image is 6·height wide."""

    model: ClassVar[int] = 3
    name: ClassVar[str] = "cubemap"

    def frame_size(self, width: int, height: int) -> tuple[int, int]:
        check_size(width, height)
        return check_size(6 * int(height), int(height))

    @staticmethod
    def _face(d: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Face index (camera.glsl's order) and face coordinates p in [-1, 1]^2."""
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

    def project(self, directions, width: int, height: int):
        d = _unit(directions)
        face, px, py = self._face(d)
        side = float(height)
        x = face * side + (px + 1.0) * 0.5 * side
        return x, (py + 1.0) * 0.5 * side, np.ones(d.shape[:-1], bool)

    def solid_angle(self, directions, width: int, height: int) -> np.ndarray:
        d = _unit(directions)
        m = np.max(np.abs(d), axis=-1)
        step = 2.0 / float(height)
        return step * step * m**3

    def directions(self, x, y, width: int, height: int):
        x, y, _, h = _positions(x, y, width, height)
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
        return _unit(d), np.ones(np.broadcast(x, y).shape, bool)


@dataclass(frozen=True, eq=False)
class DirectionsCamera(Camera):
    """One pixel per given direction: ``directions`` is (H, W, 3) or (N, 3) of ENU vectors
    (N directions render as an N x 1 frame). For sampling the sky in chosen directions."""

    view_directions: np.ndarray = None
    model: ClassVar[int] = 4
    name: ClassVar[str] = "directions"
    has_projection: ClassVar[bool] = False

    def __post_init__(self):
        try:
            d = np.asarray(self.view_directions, dtype=np.float64)
        except (TypeError, ValueError, OverflowError):
            raise ParameterError(
                "directions must be a finite (H, W, 3) or (N, 3) array of numbers, got "
                f"{type(self.view_directions).__name__} {str(self.view_directions)[:60]}"
            ) from None
        if d.ndim == 2:
            d = d[None]
        if d.ndim != 3 or d.shape[-1] != 3 or not np.all(np.isfinite(d)):
            raise ParameterError(
                f"directions must be a finite (H, W, 3) or (N, 3) array, got shape {d.shape}"
            )
        # Scaled before the norm, which overflows for components beyond ~1e154.
        scale = np.max(np.abs(d), axis=-1, keepdims=True)
        if np.any(scale == 0):
            raise ParameterError("directions must be non-zero vectors")
        d = d / scale
        check_size(d.shape[1], d.shape[0])
        object.__setattr__(self, "view_directions", d / np.linalg.norm(d, axis=-1, keepdims=True))

    def frame_size(self, width: int | None = None, height: int | None = None) -> tuple[int, int]:
        return self.view_directions.shape[1], self.view_directions.shape[0]


def _positions(x, y, width, height):
    return (
        np.asarray(x, dtype=np.float64),
        np.asarray(y, dtype=np.float64),
        float(width),
        float(height),
    )


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


#: The directions of _rim's circle: cosines and sines of RIM_POINTS angles, and the factor by
#: which the polygon through them is widened to hold the circle (its vertices at
#: radius / cos(pi / RIM_POINTS): the edges' midpoints on the circle).
RIM_POINTS = 16
_RIM_COS = np.cos(np.linspace(0.0, 2.0 * np.pi, RIM_POINTS, endpoint=False))[:, None]
_RIM_SIN = np.sin(np.linspace(0.0, 2.0 * np.pi, RIM_POINTS, endpoint=False))[:, None]
_RIM_WIDEN = 1.0 / math.cos(math.pi / RIM_POINTS)


def _rim(direction: np.ndarray, radius_rad: float) -> np.ndarray:
    """The centre and RIM_POINTS directions around the unit vector ``direction`` (N + 1, 3):
    the vertices of a polygon holding the circle of angular radius ``radius_rad``."""
    ux, uy, uz = (float(v) for v in direction)
    norm = math.sqrt(ux * ux + uy * uy + uz * uz)
    ux, uy, uz = ux / norm, uy / norm, uz / norm
    # e1 = u x (z, or x near the poles), e2 = u x e1: a basis of the circle's plane.
    if abs(uz) < 0.9:
        e1 = np.array([uy, -ux, 0.0])
    else:
        e1 = np.array([0.0, uz, -uy])
    e1 /= np.linalg.norm(e1)
    u = np.array([ux, uy, uz])
    e2 = np.array([uy * e1[2] - uz * e1[1], uz * e1[0] - ux * e1[2], ux * e1[1] - uy * e1[0]])
    a = radius_rad * _RIM_WIDEN
    ring = math.cos(a) * u + math.sin(a) * (_RIM_COS * e1 + _RIM_SIN * e2)
    return np.vstack([u, ring])


#: The disks (the Sun, the Moon) are sampled at DISK_SAMPLES_PER_RADIUS points across their
#: radius at least: each pixel averages n x n points over its area, n = ceil(
#: DISK_SAMPLES_PER_RADIUS / the radius in pixels) (1 once the radius spans that many
#: pixels), at most DISK_SAMPLES_MAX. One point per pixel puts a whole pixel inside or
#: outside the disk: the Sun 3.8 pixels in radius (1280 x 720, 90 deg) then held 8.6 % too
#: much light and the Moon 15 %, and a disk narrower than a pixel could vanish; a disk
#: spanning 12 points per radius is within about 1 % (the lattice points in a circle:
#: 1 / (pi R^(4/3)) at R points per radius), at any frame size.
DISK_SAMPLES_PER_RADIUS = 12.0
DISK_SAMPLES_MAX = 32


def disk_samples(
    camera: Camera, width: int, height: int, radius_rad: float, rects: list | None
) -> int:
    """Points per pixel side (n: n x n a pixel) over which ``celestial/disk_pixel.glsl``'s
    disks of angular radius ``radius_rad`` average in a frame of ``width`` x ``height`` of
    ``camera`` (see DISK_SAMPLES_PER_RADIUS), drawn over ``rects`` (:func:`disk_scissor`'s
    rectangles for the disk's pass). 1 where it found none to confine the pass to (None: a
    cube map, a disk beside a perspective camera): that pass covers the whole frame."""
    if rects is None:
        return 1
    pixel = camera.pixel_angle(width, height)
    if pixel <= 0.0 or radius_rad <= 0.0:
        return 1
    n = math.ceil(DISK_SAMPLES_PER_RADIUS * pixel / radius_rad - 1e-9)
    return min(max(n, 1), DISK_SAMPLES_MAX)


#: Pixels around a disk's rectangle in disk_scissor (the pixels whose area reaches it).
DISK_MARGIN_PX = 2


def disk_scissor(
    camera: Camera,
    width: int,
    height: int,
    direction,
    radius_rad: float,
    margin_px: int = DISK_MARGIN_PX,
) -> list[tuple[int, int, int, int]] | None:
    """Pixel rectangles (x, y, w, h; GL: y up from the bottom) holding every pixel that can
    see a disk of angular radius ``radius_rad`` around ``direction`` (unit ENU), for drawing
    small sources (the Sun, the Moon, planets) with a scissor test instead of over the
    whole frame. An empty list when the disk is out of the frame; None when the camera has
    no simple inverse there (cube maps, direction maps): draw everything."""
    d = np.asarray(direction, dtype=np.float64)
    rects = camera._disk_rects(_rim(d, radius_rad), width, height)
    if rects is None:
        return None
    out = []
    for x0, y0, x1, y1 in rects:
        ax, ay = max(math.floor(x0) - margin_px, 0), max(math.floor(y0) - margin_px, 0)
        bx, by = min(math.ceil(x1) + margin_px, width), min(math.ceil(y1) + margin_px, height)
        if bx > ax and by > ay:
            out.append((ax, ay, bx - ax, by - ay))
    return out
