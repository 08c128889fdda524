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
