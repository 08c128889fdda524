"""The view-direction table of a fog alone (``shaders/clouds/direction_table.glsl``).

With no clouds over it, the fog under them is the same everywhere: what a ray from the
camera meets in it depends on the ray's direction only, never on where on the frame it is.
The cloud layer then marches a table of directions once for the camera's height and the
lights (kept while they stay) and each pixel looks its direction up, instead of marching
every pixel. The table spans every direction, in "diamond angles" (ratios of a direction's
components, monotonic in the true angles: a pixel finds its texel without trigonometry):

- x: the azimuth from the key light's, a quarter turn per quarter of the table, the light's
  on texel 0's centre (the texture wraps around);
- y: the elevation's q = z / (h + |z|) (h the horizontal part: q = tan e / (1 + |tan e|)),
  split at the ground's horizon q_h seen from the camera, like the atmosphere's sky-view
  table (``atmosphere/sky_view_mapping.glsl``): the upper half the rays that miss the
  ground, the lower half those that meet it, each with the square root of q's distance from
  q_h linear in the texels (they crowd at the horizon, where a fog's top and the ground's
  far edge are).
"""

from __future__ import annotations

import math

import numpy as np

#: Texels (azimuth, elevation) of the table at each cloud quality.
TABLE_SIZE = {"best": (512, 256), "full": (256, 128), "interactive": (128, 64)}
#: Diamond dust's tables are this many times finer each way: its halos' edges are a fraction
#: of a degree sharp, the droplets' table's texels 1.4 deg across the horizon (full quality);
#: twice as fine (0.7 deg) draws them as the per-pixel march does, 4 times costs 4 times as
#: much again (a fresh table at full quality: 0.24 s, 0.83 s, 3.2 s on a 2-core CPU).
ICE_TABLE_SCALE = 2


def _diamond(t) -> np.ndarray:
    """q = tan / (1 + |tan|): the diamond angle of an elevation of tangent ``t``."""
    return t / (1.0 + np.abs(t))


def table_frame(key_direction, view_radius_km: float, bottom_radius_km: float):
    """The table's frame (u_table_frame): the cos and sin of the key light's azimuth (unit
    ENU ``key_direction``, from east towards north; east for a light at the zenith) and the
    ground horizon's q_h seen from ``view_radius_km``."""
    x, y = float(key_direction[0]), float(key_direction[1])
    norm = math.hypot(x, y)
    cos_a, sin_a = (x / norm, y / norm) if norm > 1e-12 else (1.0, 0.0)
    horizon_rad = -math.acos(min(bottom_radius_km / view_radius_km, 1.0))
    return cos_a, sin_a, float(_diamond(math.tan(horizon_rad)))


def table_directions(size: tuple[int, int], frame) -> np.ndarray:
    """The unit ENU directions (H, W, 3) of the table's texels, row 0 the lowest (GL rows),
    in the table's ``frame`` (:func:`table_frame`). Each half's texel nearest the horizon
    sits a hair (1e-6 in q) off it, on its own side."""
    width, height = size
    cos_a, sin_a, q_h = frame
    half = height // 2
    x = np.arange(half) / (half - 1.0)  # the warped distance from the horizon, 0..1
    below = q_h - 1e-6 - x**2 * (q_h + 1.0 - 1e-6)
    above = q_h + 1e-6 + x**2 * (1.0 - q_h - 1e-6)
    q = np.concatenate([below[::-1], above])
    t = q / (1.0 - np.minimum(np.abs(q), 1.0 - 1e-12))  # tan of the elevation
    horizontal = 1.0 / np.sqrt(1.0 + t * t)
    # the azimuth's diamond angle p in [0, 4): quadrant k, (1 - f, f) within it
    p = 4.0 * np.arange(width) / width
    k = np.floor(p).astype(int)
    f = p - k
    a = np.choose(k, [1.0 - f, -f, f - 1.0, f])
    b = np.choose(k, [f, 1.0 - f, -f, f - 1.0])
    n = np.hypot(a, b)
    a, b = a / n, b / n
    # back from the light's frame to east, north
    east, north = a * cos_a - b * sin_a, a * sin_a + b * cos_a
    d = np.empty((height, width, 3))
    d[..., 0] = horizontal[:, None] * east[None, :]
    d[..., 1] = horizontal[:, None] * north[None, :]
    d[..., 2] = (t * horizontal)[:, None]
    return d


def _diamond_angle(x, y) -> np.ndarray:
    """The diamond angle of (x, y) in (-1, 3] (direction_table.glsl's diamond_angle)."""
    r = y / (np.abs(x) + np.abs(y) + 1e-300)
    return np.where(x < 0.0, 2.0 - r, r)


def table_texcoords(directions, size: tuple[int, int], frame) -> np.ndarray:
    """Texture coordinates (..., 2) of unit ENU ``directions`` in the table of ``frame`` (the
    float64 twin of ``direction_table_uv``), each in the half of its side of the ground's
    horizon (q < q_h: the ground's): texel (i, j)'s own direction falls on its centre."""
    d = np.asarray(directions, dtype=np.float64)
    width, height = size
    cos_a, sin_a, q_h = frame
    half = height // 2
    a = d[..., 0] * cos_a + d[..., 1] * sin_a
    b = d[..., 1] * cos_a - d[..., 0] * sin_a
    u = np.mod(0.25 * _diamond_angle(a, b) + 0.5 / width, 1.0)
    h = np.hypot(d[..., 0], d[..., 1])
    q = d[..., 2] / (h + np.abs(d[..., 2]))
    hits_ground = q < q_h
    x = np.where(hits_ground, (q_h - q) / (q_h + 1.0), (q - q_h) / (1.0 - q_h))
    x = np.sqrt(np.clip(x, 0.0, 1.0))
    v_half = (0.5 + x * (half - 1.0)) / half
    v = 0.5 + 0.5 * np.where(hits_ground, -v_half, v_half)
    return np.stack([u, v], axis=-1)
