"""A narrow vertical strip of view along the antisolar vertical, for the bows' tests: a camera
4 pixels wide whose 44 deg of height run from 10 to 54 deg up, opposite a Sun in the west
(azimuth 270 deg, ``sun_deg`` up), and each row's angle from the Sun."""

from __future__ import annotations

import math

import numpy as np


def antisolar_strip(h: int = 240, sun_deg: float = 10.0):
    """(the camera, its width, its height, each row's angle from the Sun in deg, top row
    first as the frames' rows are)."""
    from skydome.core.cameras import PerspectiveCamera

    w = 4
    camera = PerspectiveCamera(
        fov_deg=2 * math.degrees(math.atan(math.tan(math.radians(22.0)) * w / h)),
        yaw_deg=90.0, pitch_deg=32.0,
    )  # fmt: skip
    dirs, _ = camera.directions(np.full(h, 2.0), np.arange(h) + 0.5, w, h)
    e = math.radians(sun_deg)
    sun = np.array([-math.cos(e), 0.0, math.sin(e)])
    theta = np.degrees(np.arccos(np.asarray(dirs) @ sun))[::-1]
    return camera, w, h, theta
