"""Light for a user's 3D scene from the sky that is drawn (clouds and weather included): the
Sun's and the Moon's direction, size and illuminance at the ground, the sky's irradiance as
order-2 spherical harmonics, and directional lights that reproduce it.

>>> from skydome import Sky
>>> with Sky("Valletta", "2018-03-01T10:00") as sky:              # doctest: +SKIP
...     light = sky.lighting()
...     light.sun.illuminance_rgb, light.sh.shape, len(light.lights)

Everything is measured on an equirect map of the sky in cd/m^2 (``size``, default 256 x
128), drawn three times: without the Sun's and the Moon's disks (the sky alone: the map
returned, the harmonics and the lights), and with each disk alone added (its light, the
difference, integrated over the map: the disk's illuminance on a surface facing it, after
the air and the clouds). Units: illuminance in lux, linear sRGB with Y = illuminance; axes
x east, y north, z up (ENU).

- ``sh``: 9 x RGB irradiance coefficients (Ramamoorthi & Hanrahan 2001, order (l, m) =
  (0,0), (1,-1), (1,0), (1,1), (2,-2), (2,-1), (2,0), (2,1), (2,2), ``physics.
  spherical_harmonics``): E(n) = sum_i sh[i] Y_i(n), the clamped cosine's convolution
  included, for the sky alone (the disks split out: treat the Sun as a light).
- ``lights``: N directional lights (default 16: see DEFAULT_LIGHTS) from a median cut of the map
  (Debevec 2005, "A median cut algorithm for light probe sampling": the map split N - 1 times
  at the energy median along the longer side of the brightest region; each region a light
  at its energy-weighted direction with its light), then their intensities rescaled (one
  non-negative factor each, colours kept) so that their irradiance on the 6 axes and the 8
  cube diagonals matches the map's (the axes weighted 10 to 1).
- The disks' illuminance is measured through a 2 deg camera aimed at each (a pixel of the
  map is coarser than the disks).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from skydome.atmosphere.mie import nnls
from skydome.core.cameras import EquirectCamera
from skydome.core.frame import Frame
from skydome.errors import ParameterError
from skydome.lighting_ibl import DEFAULT_FACE_SIZE, DEFAULT_SAMPLES, PrefilteredCube, prefilter
from skydome.physics import spherical_harmonics as sh
from skydome.spectra import SRGB_LUMINANCE

#: The map the lighting is measured on (pixels): 1.4 deg per pixel, the Sun's disk sub-pixel
#: (its light is kept whole by the disk layers' energy-conserving draw).
DEFAULT_SIZE = (256, 128)
#: Directional lights by default. Seed 000 named 6; but 6 clamped-cosine lights cannot hold
#: a sky's irradiance (median-cut ones missed the axes by 30-90 %, lights on the axes were
#: exact there and 100-120 % off on the diagonals); 16 median-cut lights, rescaled, hold the
#: axes within 1 % and the diagonals within 5-14 % (clear, fair and overcast skies, the Sun
#: -4 to 70 deg; lights whose rescale is 0 are dropped: 9 remained in each).
DEFAULT_LIGHTS = 16
#: Field (deg) of the camera that measures a disk's light.
DISK_FIELD_DEG = 2.0
#: Its frame (pixels a side).
DISK_FRAME_PX = 96
#: The 6 axes (ENU), where the lights must hold the sky's irradiance best.
AXES = np.array(
    [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64
)
#: The 8 cube diagonals, where the axis lights are checked between their axes.
DIAGONALS = np.array(
    [[sx, sy, sz] for sx in (1, -1) for sy in (1, -1) for sz in (1, -1)], dtype=np.float64
) / math.sqrt(3.0)


@dataclass(frozen=True)
class BodyLight:
    """The Sun or the Moon as a light: ``direction`` (unit ENU, towards it, apparent),
    ``angular_radius_deg``, and ``illuminance_rgb`` (lx, linear sRGB, Y = illuminance) on a
    surface facing it at the ground, after the air and the clouds."""

    direction: tuple[float, float, float]
    angular_radius_deg: float
    illuminance_rgb: tuple[float, float, float]

    @property
    def illuminance_lux(self) -> float:
        """Its illuminance Y (lx) on a surface facing it."""
        return float(np.asarray(self.illuminance_rgb) @ SRGB_LUMINANCE)

    def as_dict(self) -> dict:
        return {
            "direction": list(self.direction),
            "angular_radius_deg": self.angular_radius_deg,
            "illuminance_rgb": list(self.illuminance_rgb),
            "illuminance_lux": self.illuminance_lux,
        }


@dataclass(frozen=True)
class DirectionalLight:
    """A distant light: ``direction`` (unit ENU, towards it) and ``illuminance_rgb`` (lx) on
    a surface facing it."""

    direction: tuple[float, float, float]
    illuminance_rgb: tuple[float, float, float]

    def as_dict(self) -> dict:
        return {"direction": list(self.direction), "illuminance": list(self.illuminance_rgb)}


@dataclass(frozen=True)
class Lighting:
    """What lights a scene under a sky (see the module docstring)."""

    sun: BodyLight | None
    moon: BodyLight | None
    sh: np.ndarray
    lights: tuple[DirectionalLight, ...]
    sky_map: Frame = field(repr=False)

    def irradiance(self, normals) -> np.ndarray:
        """The sky's irradiance (lx, RGB) on Lambertian surfaces facing unit ``normals``
        (N, 3), from the harmonics."""
        return sh.evaluate(self.sh, np.atleast_2d(normals))

    def lights_irradiance(self, normals) -> np.ndarray:
        """The irradiance (lx, RGB) the directional lights give surfaces facing ``normals``."""
        n = np.atleast_2d(np.asarray(normals, dtype=np.float64))
        d = np.array([li.direction for li in self.lights])
        e = np.array([li.illuminance_rgb for li in self.lights])
        return np.maximum(n @ d.T, 0.0) @ e

    def exact_irradiance(self, normals) -> np.ndarray:
        """The sky's irradiance (lx, RGB) on surfaces facing ``normals``, integrated over the
        map pixel by pixel (what the harmonics and the lights approximate)."""
        radiance, dirs, omega = map_samples(self.sky_map)
        return sh.exact_irradiance(radiance, dirs, omega, np.atleast_2d(normals))

    def lights_error(self, normals) -> np.ndarray:
        """The lights' relative error in Y on surfaces facing ``normals`` against the map."""
        exact = self.exact_irradiance(normals) @ SRGB_LUMINANCE
        got = self.lights_irradiance(normals) @ SRGB_LUMINANCE
        return got / np.maximum(exact, 1e-30) - 1.0

    def prefiltered(
        self,
        ctx=None,
        *,
        face_size: int = DEFAULT_FACE_SIZE,
        with_sun: bool = False,
        samples: int = DEFAULT_SAMPLES,
    ) -> PrefilteredCube:
        """The prefiltered specular cube map (split sum, GGX; :mod:`skydome.lighting_ibl`)
        of :attr:`sky_map` in ``ctx`` (the Sky's: ``sky.graph.ctx``; default the shared
        headless context): the sky alone, or ``with_sun`` the Sun as a point source too."""
        return prefilter(
            self.sky_map, ctx, face_size=face_size, samples=samples,
            sun=self.sun if with_sun else None,
        )  # fmt: skip

    def as_dict(self) -> dict:
        """JSON-able: ``sun``, ``moon`` (or None), ``sh`` (9 rows of RGB, lx), ``lights``."""
        return {
            "sun": None if self.sun is None else self.sun.as_dict(),
            "moon": None if self.moon is None else self.moon.as_dict(),
            "sh": self.sh.tolist(),
            "sh_convention": (
                "E(n) = sum_i sh[i] Y_i(n), lux, linear sRGB (Y = illuminance); real basis "
                "(l,m) = (0,0),(1,-1),(1,0),(1,1),(2,-2),(2,-1),(2,0),(2,1),(2,2); Y_1,-1 ~ y, "
                "Y_1,0 ~ z, Y_1,1 ~ x; x east, y north, z up; the sky alone (no disks)"
            ),
            "lights": [li.as_dict() for li in self.lights],
        }


def map_samples(frame: Frame) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(radiance (N, 3) cd/m^2, unit directions (N, 3), solid angles (N,) sr) of the pixels of
    an equirect ``frame`` (rows top first)."""
    h, w = frame.data.shape[:2]
    cam = EquirectCamera()
    x, y = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    dirs, _ = cam.directions(x, y, w, h)  # GL rows: y from the bottom
    dirs = np.asarray(dirs)[::-1].reshape(-1, 3)  # the frame's rows, top first
    omega = cam.solid_angle(dirs, w, h).reshape(-1)
    return np.asarray(frame.data[..., :3], dtype=np.float64).reshape(-1, 3), dirs, omega


def _disk_layer(sky, name: str):
    return next((la for la in sky.layers if la.name == name), None)


def _body(sky, name: str, light, layer) -> BodyLight:
    """A disk's light: frames of a camera aimed at it with and without its layer, their
    difference integrated over the pixels' solid angles (its illuminance facing it)."""
    cam = sky.camera(name, fov_deg=DISK_FIELD_DEG)
    n = DISK_FRAME_PX
    layer.enabled = True
    with_disk = np.asarray(sky.render(cam, n, n, exposure=None).data[..., :3], np.float64)
    layer.enabled = False
    without = np.asarray(sky.render(cam, n, n, exposure=None).data[..., :3], np.float64)
    x, y = np.meshgrid(np.arange(n) + 0.5, np.arange(n) + 0.5)
    dirs, _ = cam.directions(x, y, n, n)
    omega = cam.solid_angle(np.asarray(dirs).reshape(-1, 3), n, n)
    rgb = (with_disk - without)[::-1].reshape(-1, 3).T @ omega  # frame rows top first
    direction = tuple(float(v) for v in np.asarray(light.direction, dtype=np.float64))
    radius = math.degrees(float(light.angular_radius_rad))
    return BodyLight(direction, radius, tuple(float(max(v, 0.0)) for v in rgb))


def median_cut(energy: np.ndarray, n_regions: int) -> list[tuple[int, int, int, int]]:
    """Split an equirect map of pixel ``energy`` (H, W: luminance x solid angle) into
    ``n_regions`` rectangles (row0, row1, col0, col1) of about equal energy: first at the
    horizon, then the most energetic region is cut, at its energy median, across its longer
    side in angle (the columns' widths shrunk by the cosine of the latitude), until there
    are n."""
    h, w = energy.shape
    lat = (0.5 - (np.arange(h) + 0.5) / h) * math.pi
    # the first cut at the horizon: the sky and the ground apart, whatever their energies
    # (a dim ground would otherwise be lit from the horizon's lights, at grazing angles)
    regions = (
        [(0, h // 2, 0, w), (h // 2, h, 0, w)] if n_regions >= 2 and h >= 2 else [(0, h, 0, w)]
    )
    while len(regions) < n_regions:
        sums = [energy[r0:r1, c0:c1].sum() for r0, r1, c0, c1 in regions]
        order = np.argsort(sums)[::-1]
        for k in order:  # the most energetic region that can still be cut
            r0, r1, c0, c1 = regions[k]
            if r1 - r0 > 1 or c1 - c0 > 1:
                break
        else:
            break
        r0, r1, c0, c1 = regions.pop(k)
        block = energy[r0:r1, c0:c1]
        width = (c1 - c0) * math.cos(float(np.mean(lat[r0:r1]))) * 2.0  # 2 pi wide, pi high
        along_columns = (c1 - c0 > 1) and (width >= (r1 - r0) or r1 - r0 == 1)
        profile = block.sum(axis=0) if along_columns else block.sum(axis=1)
        cum = np.cumsum(profile)
        cut = int(np.searchsorted(cum, 0.5 * cum[-1])) + 1
        cut = min(max(cut, 1), len(profile) - 1)
        if along_columns:
            regions += [(r0, r1, c0, c0 + cut), (r0, r1, c0 + cut, c1)]
        else:
            regions += [(r0, r0 + cut, c0, c1), (r0 + cut, r1, c0, c1)]
    return regions


def directional_lights(frame: Frame, n_lights: int = DEFAULT_LIGHTS) -> tuple:
    """N directional lights for an equirect map in cd/m^2 (the module docstring's median
    cut and rescale)."""
    radiance, dirs, omega = map_samples(frame)
    h, w = frame.data.shape[:2]
    y = radiance @ SRGB_LUMINANCE
    energy = (np.maximum(y, 0.0) * omega).reshape(h, w)
    light_dirs, light_rgb = [], []
    for r0, r1, c0, c1 in median_cut(energy, n_lights):
        idx = (np.arange(r0, r1)[:, None] * w + np.arange(c0, c1)[None, :]).ravel()
        e = energy.ravel()[idx]
        if e.sum() <= 0.0:
            continue
        d = (e[:, None] * dirs[idx]).sum(axis=0)
        light_dirs.append(d / np.linalg.norm(d))
        light_rgb.append(radiance[idx].T @ omega[idx])
    d, rgb = np.array(light_dirs), np.array(light_rgb)
    # one non-negative scale per light: the map's irradiance on the axes (weight 10) and
    # the diagonals (1), in Y
    normals = np.vstack([AXES, DIAGONALS])
    weights = np.array([10.0] * len(AXES) + [1.0] * len(DIAGONALS))
    exact = sh.exact_irradiance(radiance, dirs, omega, normals) @ SRGB_LUMINANCE
    a = np.maximum(normals @ d.T, 0.0) * (rgb @ SRGB_LUMINANCE)[None, :]
    scale = nnls(a * weights[:, None], exact * weights)
    return tuple(
        DirectionalLight(tuple(float(v) for v in di), tuple(float(v) for v in s * c))
        for di, s, c in zip(d, scale, rgb, strict=True)
        if s > 0.0
    )


def sky_lighting(
    sky, size: tuple[int, int] = DEFAULT_SIZE, n_lights: int = DEFAULT_LIGHTS
) -> Lighting:
    """The lighting of ``sky`` (a :class:`skydome.Sky`) now, measured on equirect maps of
    ``size`` (width, height: 2:1, 16-4096 wide), with ``n_lights`` directional lights
    (1-64). The disk layers' on/off state is restored."""
    w, h = (int(v) for v in size)
    if not (16 <= w <= 4096 and w == 2 * h):
        raise ParameterError(f"lighting map size {size} must be 2:1 and 16-4096 pixels wide")
    if isinstance(n_lights, bool) or not isinstance(n_lights, int) or not 1 <= n_lights <= 64:
        raise ParameterError(f"lights {n_lights!r} must be an integer from 1 to 64")
    sun_layer, moon_layer = _disk_layer(sky, "sun"), _disk_layer(sky, "moon")
    was = {la: la.enabled for la in (sun_layer, moon_layer) if la is not None}
    try:
        for la in was:
            la.enabled = False
        alone = sky.render(EquirectCamera(), w, h, exposure=None)
        bodies = {}
        for name, la in (("sun", sun_layer), ("moon", moon_layer)):
            light = getattr(sky.state, name, None)
            bodies[name] = None if la is None or light is None else _body(sky, name, light, la)
    finally:
        for la, on in was.items():
            la.enabled = on
    radiance, dirs, omega = map_samples(alone)
    coefficients = sh.irradiance_coefficients(sh.project(radiance, dirs, omega))
    lights = directional_lights(alone, n_lights)
    return Lighting(bodies["sun"], bodies["moon"], coefficients, lights, alone)
