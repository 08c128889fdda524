"""Directions in the observer's East-North-Up frame (x east, y north, z up; azimuth from
north through east, elevation from the horizon: DESIGN.md rule 5)."""

from __future__ import annotations

import math

import numpy as np

from skydome.errors import ParameterError, check_range


def horizontal_to_enu(alt_rad, az_rad) -> np.ndarray:
    """Unit ENU vectors (..., 3) from altitude and azimuth (rad)."""
    alt, az = np.broadcast_arrays(np.asarray(alt_rad, float), np.asarray(az_rad, float))
    ca = np.cos(alt)
    return np.stack([ca * np.sin(az), ca * np.cos(az), np.sin(alt)], axis=-1)


def direction_from_angles(elevation_deg: float, azimuth_deg: float) -> np.ndarray:
    """The unit ENU vector of an elevation (-90 to 90) and an azimuth (any finite value)
    in degrees; ParameterError for other values."""
    el = check_range("elevation_deg", elevation_deg, -90.0, 90.0, "deg")
    az = check_range("azimuth_deg", azimuth_deg, -math.inf, math.inf, "deg")
    if not math.isfinite(az):
        raise ParameterError(f"azimuth_deg = {azimuth_deg} deg must be a finite number")
    return horizontal_to_enu(math.radians(el), math.radians(az))


def elevation_deg(direction) -> float:
    """Elevation (deg) of a unit ENU direction."""
    return math.degrees(math.asin(max(-1.0, min(1.0, float(direction[2])))))


def azimuth_deg(direction) -> float:
    """Azimuth (deg, [0, 360)) of an ENU direction, from north through east."""
    return math.degrees(math.atan2(float(direction[0]), float(direction[1]))) % 360.0


# ---------------------------------------------------------------- rays in a spherical shell
# A ray starts at distance r from the centre of concentric spheres with direction cosine mu
# (the cosine of its zenith angle there); it is at distance sqrt(r^2 + 2 r mu t + t^2) from
# the centre after t (Bruneton 2017, sec. "Distance to the top/bottom atmosphere boundary").
# Any unit of length, the same for all arguments: metres in Python, km in the shaders.
# GLSL twins: shaders/common/atmosphere_common.glsl.


def distance_to_top(r, mu, top_radius) -> np.ndarray:
    """Distance along (r, mu) to where the ray leaves a sphere of ``top_radius`` around the
    centre (r <= top_radius): -r mu + sqrt(r^2 (mu^2 - 1) + top^2), never negative.
    GLSL twin: ``distance_to_top``."""
    r, mu = np.asarray(r, float), np.asarray(mu, float)
    disc = r * r * (mu * mu - 1.0) + top_radius**2
    return np.maximum(-r * mu + np.sqrt(np.maximum(disc, 0.0)), 0.0)


def distance_to_bottom(r, mu, bottom_radius) -> np.ndarray:
    """Distance along (r, mu) to where the ray first meets a sphere of ``bottom_radius``
    (r >= bottom_radius): -r mu - sqrt(r^2 (mu^2 - 1) + bottom^2), never negative (meaningful
    where :func:`ray_hits_ground`).
    GLSL twin: ``distance_to_bottom``."""
    r, mu = np.asarray(r, float), np.asarray(mu, float)
    disc = r * r * (mu * mu - 1.0) + bottom_radius**2
    return np.maximum(-r * mu - np.sqrt(np.maximum(disc, 0.0)), 0.0)


def ray_hits_ground(r, mu, bottom_radius) -> np.ndarray:
    """Whether the ray (r, mu) meets the sphere of ``bottom_radius``: it goes down (mu < 0)
    and its perigee, r sqrt(1 - mu^2), lies inside it.
    GLSL twin: ``ray_hits_ground``."""
    r, mu = np.asarray(r, float), np.asarray(mu, float)
    return (mu < 0.0) & (r * r * (mu * mu - 1.0) + bottom_radius**2 >= 0.0)


def horizon_dip_rad(r: float, radius: float) -> float:
    """Angle (rad) by which the horizon of a sphere of ``radius`` lies below the horizontal
    seen from distance ``r`` >= radius from its centre: acos(radius / r) (0 on the sphere)."""
    return math.acos(min(float(radius) / float(r), 1.0))


def ray_sphere(origin, direction, radius) -> np.ndarray:
    """Distances (..., 2) along the rays origin + t direction (unit, (..., 3)) to their two
    intersections with a sphere of ``radius`` around the origin of coordinates, nearer first
    (negative behind the ray's start); both -1 where the line misses the sphere. The roots of
    t^2 + 2 b t + c = 0 with b = o.d, c = |o|^2 - radius^2.
    GLSL twin: ``ray_sphere``."""
    o, d = np.asarray(origin, float), np.asarray(direction, float)
    b = np.sum(o * d, axis=-1)
    c = np.sum(o * o, axis=-1) - radius * radius
    disc = b * b - c
    s = np.sqrt(np.maximum(disc, 0.0))
    t = np.stack([-b - s, -b + s], axis=-1)
    return np.where((disc < 0.0)[..., None], -1.0, t)


# ---------------------------------------------------------------- spheres seen from outside
# A sphere (the Sun, the Moon, a planet) towards the unit vector ``centre`` with sin_radius
# the sine of its angular radius, and unit view rays ``direction`` (..., 3). Small angles go
# through cross products as in the shaders, where 1 - cos(theta) at 5 mrad keeps 2 float32
# digits and the sine 7. GLSL twins: shaders/common/sphere_disk.glsl.


def sin_offset(direction, centre) -> np.ndarray:
    """sin(theta) of the angle theta between each ray and the centre: |direction x centre|.
    GLSL twin: ``sin_offset``."""
    return np.linalg.norm(
        np.cross(np.asarray(direction, float), np.asarray(centre, float)), axis=-1
    )


def ray_meets_sphere(direction, centre, sin_radius) -> np.ndarray:
    """Whether each ray meets the sphere: the centre is in front (direction . centre > 0) and
    sin(theta) < sin_radius.
    GLSL twin: ``ray_meets_sphere``."""
    d = np.asarray(direction, float)
    front = np.sum(d * np.asarray(centre, float), axis=-1) > 0.0
    return front & (sin_offset(d, centre) < sin_radius)


def sphere_normal(direction, centre, sin_radius) -> np.ndarray:
    """Outward unit normals (..., 3) where the rays first meet the sphere (they must meet it).
    Lengths in units of the centre's distance: the sphere's radius is sin_radius and the hit
    is at t = cos(theta) - sqrt(sin_radius^2 - sin^2(theta)); n = (t d - centre) / sin_radius.
    GLSL twin: ``sphere_normal``."""
    d, c = np.asarray(direction, float), np.asarray(centre, float)
    s2 = np.sum(np.cross(d, c) ** 2, axis=-1)
    t = np.sum(d * c, axis=-1) - np.sqrt(np.maximum(sin_radius * sin_radius - s2, 0.0))
    return (t[..., None] * d - c) / np.asarray(sin_radius, float)[..., None]
