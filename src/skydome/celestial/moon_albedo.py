"""The Moon's albedo: a map of relative albedo over its surface and its spectral shape.

Map (``moon_albedo_map``, ``albedo_at``)
----------------------------------------
``skydome/data/moon_albedo.npz``, built by ``tools/build_moon_albedo.py`` from the colour map
of NASA's CGI Moon Kit (NASA Scientific Visualization Studio, 2019, https://svs.gsfc.nasa.gov/4720;
LRO LROC WAC Hapke-normalised mosaic and LOLA; public domain). The display encoding is undone,
the three channels are combined with Rec. 709 luminance weights (an albedo near 550 nm), and the
map is area-averaged to 1024 x 512. It is *relative*: its mean over the near side, weighted as
the full Moon's disk sees it (cos of the angle from the sub-Earth point (0, 0) times surface
area, i.e. each element of the projected disk counts alike), is 1. The maria are about 0.53 to
0.65, the southern highlands 1.1 to 1.4, Tycho's floor and rays near 2. See
``skydome/data/moon_albedo.txt`` for the source, licence, credit and processing.

Grid convention (module constants): selenographic latitude and east-positive longitude in an
equirectangular grid; column ``i`` is centred on longitude ``-180 + (i + 0.5) * 360 / W`` deg
(west edge at -180 deg), row ``j`` on latitude ``90 - (j + 0.5) * 180 / H`` deg (north at the
top). The sub-Earth point of the mean libration, (0, 0), is the centre of the map.

Spectral shape (``moon_spectral_albedo``)
-----------------------------------------
``skydome/data/moon_spectral_albedo.csv``: the disk-integrated equigonal albedo of the whole
Moon at phase angle 6 deg, 350-1050 nm (Velikodsky et al. 2011, Icarus 214, 30, Table 2),
divided by its value at 550 nm. The Moon is redder than the Sun: the albedo rises 1.55 times
from 443 to 700 nm, which makes its B-V about 0.25 mag redder than sunlight's
(tests/test_moon_albedo.py). The map times this shape is the albedo at any wavelength, with
the maria/highland colour differences (a few per cent) left out.
"""

from __future__ import annotations

import functools
import math
from importlib import resources
from typing import Any

import numpy as np

from skydome.errors import ParameterError
from skydome.io.packaged import read_packaged_npz

#: Longitude of the map's west edge and east edge, degrees (east-positive, selenographic).
MAP_LON_WEST_DEG = -180.0
MAP_LON_EAST_DEG = 180.0
#: Latitude of the map's top row edge and bottom row edge, degrees.
MAP_LAT_NORTH_DEG = 90.0
MAP_LAT_SOUTH_DEG = -90.0
#: Longitudes increase to the right (east), latitudes decrease downwards.
MAP_LON_EAST_POSITIVE = True
#: The map's normalisation: disk-weighted mean over the near side (cos(psi) x area) = 1.
MAP_NEAR_SIDE_DISK_MEAN = 1.0
#: Wavelength at which ``moon_spectral_albedo`` is 1, nm.
SPECTRAL_REFERENCE_NM = 550.0

_MAP_FILE = "moon_albedo.npz"
_SPECTRUM_FILE = "moon_spectral_albedo.csv"
_FORMAT_VERSION = 1


@functools.cache
def _map_and_meta() -> tuple[np.ndarray, dict]:
    q, meta = read_packaged_npz(
        _MAP_FILE, "albedo_u16", _FORMAT_VERSION, "Moon albedo map", "tools/build_moon_albedo.py"
    )
    a = np.ascontiguousarray(q.astype(np.float32) * np.float32(meta["albedo_scale"]))
    a.setflags(write=False)
    return a, meta


def moon_albedo_map() -> np.ndarray:
    """The Moon's relative albedo map, float32 (H, W) = (512, 1024), read-only, cached.

    Row 0 is the northernmost (centred on latitude 90 - 90/H deg), column 0 the westernmost
    (centred on longitude -180 + 180/W deg); see the module docstring. Dimensionless, with a
    near-side disk-weighted mean of 1.
    """
    return _map_and_meta()[0]


def moon_albedo_metadata() -> dict:
    """The map's metadata (source, SHA-256, licence, credit, convention, normalisation)."""
    return dict(_map_and_meta()[1])


def albedo_at(lon_rad: Any, lat_rad: Any) -> np.ndarray:
    """Relative albedo at selenographic longitude/latitude (radians), bilinear interpolation.

    Args:
        lon_rad: east-positive selenographic longitude, rad; any finite value (it wraps).
        lat_rad: selenographic latitude, rad, in [-pi/2, pi/2]. Within half a pixel of a pole
            the value of the outermost row is used.
    Both broadcast against each other.

    Returns:
        float64 array of the broadcast shape, dimensionless (near-side disk mean 1).
    """
    lon = np.asarray(lon_rad, dtype=np.float64)
    lat = np.asarray(lat_rad, dtype=np.float64)
    if not np.all(np.isfinite(lon)):
        raise ParameterError(f"lon_rad must be finite, got {lon_rad!r}")
    half_pi = 0.5 * math.pi
    if not np.all(np.isfinite(lat)) or np.any(np.abs(lat) > half_pi * (1.0 + 1e-12)):
        raise ParameterError(
            f"lat_rad = {lat_rad!r} is outside the valid range [{-half_pi:.6f}, {half_pi:.6f}] rad"
        )
    lon, lat = np.broadcast_arrays(lon, lat)
    a = moon_albedo_map()
    h, w = a.shape
    # Continuous pixel coordinates: x = 0 at the centre of column 0, y = 0 at that of row 0.
    x = (np.degrees(lon) - MAP_LON_WEST_DEG) * (w / 360.0) - 0.5
    y = (MAP_LAT_NORTH_DEG - np.degrees(lat)) * (h / 180.0) - 0.5
    y = np.clip(y, 0.0, h - 1.0)
    x0 = np.floor(x)
    fx = x - x0
    i0 = np.mod(x0.astype(np.int64), w)
    i1 = np.mod(i0 + 1, w)
    j0 = np.minimum(np.floor(y).astype(np.int64), h - 2)
    fy = y - j0
    j1 = j0 + 1
    top = a[j0, i0] * (1.0 - fx) + a[j0, i1] * fx
    bottom = a[j1, i0] * (1.0 - fx) + a[j1, i1] * fx
    return np.asarray(top * (1.0 - fy) + bottom * fy, dtype=np.float64)


@functools.cache
def _spectrum() -> tuple[np.ndarray, np.ndarray]:
    text = (resources.files("skydome.data") / _SPECTRUM_FILE).read_text()
    rows = [ln for ln in text.splitlines() if ln and not ln.startswith("#")][1:]
    t = np.array([[float(v) for v in r.split(",")] for r in rows])
    wl, rel = t[:, 0], t[:, 1]
    rel = rel / np.interp(SPECTRAL_REFERENCE_NM, wl, rel)  # exactly 1 at 550 nm
    wl.setflags(write=False)
    rel.setflags(write=False)
    return wl, rel


def moon_spectral_albedo(wavelengths_nm: Any) -> np.ndarray:
    """The Moon's disk-integrated spectral albedo relative to its value at 550 nm.

    Velikodsky et al. (2011) Table 2, whole Moon, phase 6 deg, tabulated 350-1050 nm; linear
    interpolation between the rows, the end values held constant outside them.

    Args:
        wavelengths_nm: wavelength(s), nm, finite and > 0 (any shape).

    Returns:
        float64 array of the same shape, dimensionless (1 at 550 nm).
    """
    lam = np.asarray(wavelengths_nm, dtype=np.float64)
    if not np.all(np.isfinite(lam)) or np.any(lam <= 0.0):
        raise ParameterError(
            f"wavelengths_nm = {wavelengths_nm!r} is outside the valid range (0, inf) nm"
        )
    wl, rel = _spectrum()
    return np.interp(lam, wl, rel)
