"""Float64 oracles for the Sun's and the Moon's disks: pixel geometry, a ray-traced sphere,
the Moon's photometry and the refracted limbs. Slow and obvious, for tests only (the laws
themselves, and the Lommel-Seeliger disk integral in closed form, are production's:
skydome.celestial.surface_laws).

- Pixel directions and exact pixel solid angles of the perspective and equirectangular
  cameras (the mappings of ``shaders/common/camera.glsl``, row 0 at the top of a frame);
- :func:`sphere_hit`: where view rays meet a sphere seen from a finite distance (the
  quadratic solved in float64, not the shader's small-angle form);
- :func:`moon_disk_radiance`: the Moon layer's photometry (Lommel-Seeliger sunlit law, the
  earthlit term, the albedo map) for given directions, from its own ray tracer;
- :func:`disk_integral_brute_force`: the Moon layer's two disk integrals on a fine
  tangent-plane grid (the obvious method, to check the production quadrature);
- :func:`true_elevation_deg`: the airless elevation whose Saemundsson-refracted image is a
  given apparent elevation (bisection).

Units: radians unless a name says ``_deg``; directions are unit ENU vectors; solid angles
in sr.
"""

from __future__ import annotations

import math

import numpy as np

from skydome.astro import frames
from skydome.celestial.moon_albedo import albedo_at
from skydome.celestial.surface_laws import lommel_seeliger_law
from skydome.core.cameras import PerspectiveCamera
from skydome.errors import ParameterError


def _check_size(width: int, height: int) -> None:
    if width < 1 or height < 1:
        raise ParameterError(f"frame size {width}x{height} must be at least 1x1 pixels")


def perspective_pixel_directions(camera: PerspectiveCamera, width: int, height: int):
    """Unit ENU view direction of each pixel centre (H, W, 3), row 0 at the top.

    The pinhole of camera.glsl: the image plane at unit distance spans
    x in [-tan(fov/2), tan(fov/2)] and y in the same over the aspect ratio.
    """
    _check_size(width, height)
    t = math.tan(math.radians(camera.fov_deg) / 2.0)
    ty = t / (width / height)
    x = ((np.arange(width) + 0.5) / width * 2.0 - 1.0) * t
    y = ((np.arange(height) + 0.5) / height * 2.0 - 1.0) * ty
    xx, yy = np.meshgrid(x, y[::-1])  # row 0 at the top
    local = np.stack([xx, yy, np.ones_like(xx)], axis=-1)
    d = local @ camera.basis().T
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def perspective_pixel_solid_angles(camera: PerspectiveCamera, width: int, height: int):
    """Exact solid angle (sr) of each pixel (H, W) of a perspective frame, row 0 at the top.

    A rectangle [x0, x1] x [y0, y1] of the image plane at unit distance subtends
    F(x1, y1) - F(x0, y1) - F(x1, y0) + F(x0, y0) with F(x, y) = atan(x y / sqrt(1 + x^2
    + y^2)) (the integral of dx dy / (1 + x^2 + y^2)^(3/2)).
    """
    _check_size(width, height)
    t = math.tan(math.radians(camera.fov_deg) / 2.0)
    ty = t / (width / height)
    xe = (np.arange(width + 1) / width * 2.0 - 1.0) * t
    ye = (np.arange(height + 1) / height * 2.0 - 1.0) * ty
    xx, yy = np.meshgrid(xe, ye)
    f = np.arctan(xx * yy / np.sqrt(1.0 + xx * xx + yy * yy))
    omega = f[1:, 1:] - f[1:, :-1] - f[:-1, 1:] + f[:-1, :-1]
    return omega[::-1]


def equirect_pixel_directions(width: int, height: int) -> np.ndarray:
    """Unit ENU direction of each pixel centre (H, W, 3) of an equirectangular frame:
    azimuth (i + 0.5) 2 pi / W from north through east, elevation pi/2 - (j + 0.5) pi / H."""
    _check_size(width, height)
    az = (np.arange(width) + 0.5) / width * 2.0 * math.pi
    el = 0.5 * math.pi - (np.arange(height) + 0.5) / height * math.pi
    a, e = np.meshgrid(az, el)
    return np.stack([np.sin(a) * np.cos(e), np.cos(a) * np.cos(e), np.sin(e)], axis=-1)


def equirect_pixel_solid_angles(width: int, height: int) -> np.ndarray:
    """Exact solid angle (sr) of each pixel (H, W) of an equirectangular frame: the band
    integral (2 pi / W)(sin e_top - sin e_bottom)."""
    _check_size(width, height)
    edges = 0.5 * math.pi - np.arange(height + 1) / height * math.pi
    band = (2.0 * math.pi / width) * (np.sin(edges[:-1]) - np.sin(edges[1:]))
    return np.broadcast_to(band[:, None], (height, width)).copy()


def sphere_hit(directions, centre, sin_radius: float):
    """Where rays from the observer meet a sphere: (mask, normals, mu).

    ``directions`` (..., 3) unit rays; ``centre`` the unit vector to the sphere's centre;
    ``sin_radius`` its radius over its distance. Solves |t d - c| = s for the nearer t
    (units of the centre's distance). ``normals`` (..., 3) are the outward unit normals at
    the hits (NaN off the sphere) and ``mu`` the cosine of the emission angle towards the
    observer, -n . d.
    """
    d = np.asarray(directions, dtype=np.float64)
    c = np.asarray(centre, dtype=np.float64)
    c = c / np.linalg.norm(c)
    s = float(sin_radius)
    b = d @ c
    disc = b * b - (1.0 - s * s)  # t^2 - 2 b t + 1 - s^2 = 0
    mask = (disc >= 0.0) & (b > 0.0)
    t = b - np.sqrt(np.where(mask, disc, np.nan))
    n = (t[..., None] * d - c) / s
    mu = -np.sum(n * d, axis=-1)
    return mask, n, mu


def moon_disk_radiance(
    directions,
    moon_true: np.ndarray,
    sin_radius: float,
    to_sun: np.ndarray,
    enu_to_moon: np.ndarray,
    sunlit_scale: float,
    earthlit_scale: float,
    use_map: bool = True,
) -> np.ndarray:
    """Luminance (cd/m^2) of the Moon towards airless ``directions`` (..., 3), 0 off it:
    A (k_sun mu0 / (mu0 + mu) + k_earth), the Moon layer's law (Lommel-Seeliger; Hapke
    2012, eq. 9.4), with A the albedo map at the hit point turned by ``enu_to_moon`` (3x3,
    ENU -> Moon-fixed) or 1 for ``use_map=False``."""
    mask, n, mu = sphere_hit(directions, moon_true, sin_radius)
    n = np.where(mask[..., None], n, 0.0)
    mu0 = n @ np.asarray(to_sun, dtype=np.float64)
    law = lommel_seeliger_law(mu0, mu)
    albedo = np.ones(mask.shape)
    if use_map:
        m = n[mask] @ np.asarray(enu_to_moon, dtype=np.float64).T
        lon = np.arctan2(m[:, 1], m[:, 0])
        lat = np.arctan2(m[:, 2], np.hypot(m[:, 0], m[:, 1]))
        albedo[mask] = albedo_at(lon, lat)
    out = albedo * (sunlit_scale * law + earthlit_scale)
    return np.where(mask, out, 0.0)


def disk_integral_brute_force(
    moon_dir, sin_radius: float, to_sun, enu_to_moon, grid: int = 2000, use_map: bool = True
) -> tuple[float, float]:
    """The integrals over the disk (sr) of A mu0/(mu0+mu) and of A/2, on a grid x grid
    tangent-plane grid over the disk's bounding square: each cell centre's ray is traced
    with :func:`sphere_hit` and weighted by its solid angle dx dy / (1 + x^2 + y^2)^(3/2).
    First order in the cell size at the limb (the disk's edge cuts cells): for a crescent of
    phase 150 deg the error is about 0.3 / grid of its integral (measured from 384 to 1536
    cells), so 2.5e-4 at 1200 cells; a full disk's is smaller."""
    u = np.asarray(moon_dir, dtype=np.float64)
    u = u / np.linalg.norm(u)
    e1 = np.cross(u, [0.0, 0.0, 1.0] if abs(u[2]) < 0.9 else [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    half = sin_radius / math.sqrt(1.0 - sin_radius**2)
    c = ((np.arange(grid) + 0.5) / grid * 2.0 - 1.0) * half
    sunlit = opposition = 0.0
    for row in np.array_split(np.arange(grid), max(1, grid // 250)):  # bounded memory
        x, y = np.meshgrid(c, c[row])
        cell = (2.0 * half / grid) ** 2 / (1.0 + x * x + y * y) ** 1.5
        d = u + x[..., None] * e1 + y[..., None] * e2
        d /= np.linalg.norm(d, axis=-1, keepdims=True)
        law = moon_disk_radiance(d, u, sin_radius, to_sun, enu_to_moon, 1.0, 0.0, use_map)
        half_albedo = moon_disk_radiance(d, u, sin_radius, to_sun, enu_to_moon, 0.0, 0.5, use_map)
        sunlit += float(np.sum(law * cell))
        opposition += float(np.sum(half_albedo * cell))
    return sunlit, opposition


def true_elevation_deg(
    apparent_deg: float, pressure_hPa: float = 1010.0, temperature_C: float = 10.0
) -> float:
    """The airless elevation h (deg) with h + R_S(h) = ``apparent_deg``, R_S the
    Saemundsson refraction of skydome.astro.frames (Meeus eq. 16.4), by bisection to 1e-12
    deg. ``apparent_deg`` in [-1, 90] (where the law is defined)."""
    if not -1.0 <= apparent_deg <= 90.0:
        raise ParameterError(f"apparent elevation {apparent_deg} deg is outside [-1, 90] deg")

    def image(h: float) -> float:
        return h + float(frames.refraction_saemundsson(h, pressure_hPa, temperature_C)) / 60.0

    lo, hi = apparent_deg - 1.0, apparent_deg  # refraction < 1 deg above -1.9 deg
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if image(mid) < apparent_deg:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)
