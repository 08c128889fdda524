"""Shared loaders for the independent ephemerides used as test oracles (test-only deps).

skyfield with the DE421 kernel bundled in skyfield-data (1900-2050) and its built-in
time scale data; nothing is fetched from the network.
"""

from __future__ import annotations

import functools
import warnings


@functools.lru_cache(maxsize=1)
def skyfield():
    warnings.filterwarnings("ignore", message=".*has expired.*")
    from skyfield.api import Loader
    from skyfield_data import get_skyfield_data_path

    load = Loader(get_skyfield_data_path())
    return load.timescale(builtin=True), load("de421.bsp")


SKYFIELD_NAMES = {
    "sun": "sun",
    "moon": "moon",
    "mercury": "mercury",
    "venus": "venus",
    "mars": "mars",
    "jupiter": "jupiter barycenter",
    "saturn": "saturn barycenter",
    "uranus": "uranus barycenter",
    "neptune": "neptune barycenter",
}

ARCSEC = 206264.80624709636  # arcseconds per radian
