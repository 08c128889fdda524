"""The relative optical air mass: how much more air a slanted ray crosses than a vertical one.
GLSL twin: ``airmass`` in ``shaders/night/light_pollution.glsl``."""

from __future__ import annotations

import numpy as np


def kasten_young_airmass(zenith_rad) -> np.ndarray:
    """Relative optical air mass (Kasten & Young 1989, Appl. Opt. 28, 4735):
    X = 1 / (cos z + 0.50572 (96.07995 - z_deg)^-1.6364); 37.92 at the horizon (their
    tabulated value for the model atmosphere is 38.0868), 0.99971 at the zenith. Zenith
    angles beyond 90 deg are taken as 90 deg.
    GLSL twin: ``airmass``."""
    z = np.minimum(np.asarray(zenith_rad, dtype=np.float64), 0.5 * np.pi)
    return 1.0 / (np.cos(z) + 0.50572 * (96.07995 - np.degrees(z)) ** -1.6364)
