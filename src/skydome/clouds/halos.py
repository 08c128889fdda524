"""Ice halos: the cirrus's crystals' phase function by ray tracing, as the renderer reads it.

A cirrus's crystals scatter the light by their rays (skydome.physics.crystal_optics): the
22 and 46 deg halos from crystals at every orientation, the sun dogs, the circumzenithal
arc and the parhelic circle from plates falling flat, the tangent arcs from columns lying
horizontal. Where crystals float in order their light depends on the light's elevation and
on the direction seen, not on the angle between them alone: the table is two-dimensional,
over the direction seen (elevation; azimuth from the light's, folded to 0-180 deg: the
populations are symmetric about the light's vertical), for one elevation of the light.

:func:`halo_table` traces each population of a mixture (:func:`parse_halos`: e.g.
``"random:0.6,plates:0.25,columns:0.15"``) at the frame's wavelengths, bins the light per
output channel (the sunlight's share of each, as the rain's bows), smooths it over the Sun's
disk, cuts it flat within :data:`TRUNCATION_DEG` of the light as the droplets' (that light
counts as unscattered, with the crystals' diffraction) and normalises each channel over the
sphere (1/sr). Tables are computed at first use for the light's elevation to the nearest
:data:`ELEVATION_STEP_DEG` and kept (:data:`CACHE_SIZE` of them): tracing takes seconds and
depends on the wavelengths and the mixture too, so it is not shipped as data.
"""

from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np

from skydome.clouds.phase import TRUNCATION_DEG
from skydome.errors import ParameterError
from skydome.physics.crystal_optics import HexagonalPrism, Orientation, scatter

__all__ = [
    "CACHE_SIZE",
    "DEFAULT_HALOS",
    "ELEVATION_STEP_DEG",
    "GRID_DEG",
    "POPULATIONS",
    "RAYS",
    "TRACE_NM",
    "halo_table",
    "parse_halos",
    "table_angles_deg",
]

#: The crystal populations: shape and how they float. Random: compact columns at every
#: orientation (the 22 and 46 deg halos); plates: thin plates (length a fifth of their
#: width) with their bases horizontal within ~1 deg (sun dogs, the circumzenithal arc, the
#: parhelic circle); columns: long columns lying horizontal (tangent arcs, parhelic circle).
POPULATIONS = {
    "random": (HexagonalPrism(1.0), Orientation("random")),
    "plates": (HexagonalPrism(0.2), Orientation("plates", tilt_deg=1.0)),
    "columns": (HexagonalPrism(2.5), Orientation("columns", tilt_deg=1.0)),
}
#: A cirrus's crystals unless told otherwise: mostly at random (the 22 deg halo is by far the
#: commonest), some plates and columns in order.
DEFAULT_HALOS = "random:0.6,plates:0.25,columns:0.15"
#: The table's cell (deg) in elevation and in azimuth; elevations of the light it is traced
#: for (deg); how many tables are kept; rays per population.
GRID_DEG = 0.5
ELEVATION_STEP_DEG = 1.0
CACHE_SIZE = 8
RAYS = 60_000
#: The wavelengths traced (nm; every crystal at each): ice's dispersion moves the halos'
#: edges by ~0.1 deg between neighbours, under the smoothing; the frame's wavelengths are
#: interpolated between them. Rays are followed until MIN_WEIGHT of their light is left.
TRACE_NM = (400.0, 460.0, 520.0, 580.0, 640.0, 700.0, 760.0)
MIN_WEIGHT = 1e-4
#: The Gaussian the light is smoothed with (deg rms): the Sun's disk (a uniform disk of
#: radius R has R/2 rms along any axis: 0.13 deg for the Sun) and the rays' noise.
SMOOTH_DEG = 0.35

#: The random population's phase function: its bins (deg) and how many more rays it takes
#: than an oriented population's table (it is traced once per process).
RANDOM_BIN_DEG = 0.1
RANDOM_RAYS_FACTOR = 4

_CACHE: OrderedDict = OrderedDict()
_RANDOM: dict = {}


def parse_halos(spec: str) -> tuple[tuple[str, float], ...]:
    """The crystal mixture ``spec`` ("none", or populations of :data:`POPULATIONS` with
    optional weights, "random:0.6,plates:0.4" or "columns,plates") as (name, share) pairs
    whose shares add up to 1; () for "none"."""
    if not isinstance(spec, str) or not spec.strip():
        raise ParameterError(f"halos must be a string such as {DEFAULT_HALOS!r} or 'none'")
    text = spec.strip().lower()
    if text == "none":
        return ()
    shares: dict[str, float] = {}
    for part in text.split(","):
        name, _, weight = part.strip().partition(":")
        name = name.strip()
        if name not in POPULATIONS:
            raise ParameterError(
                f"halo crystals {name!r} must be one of {', '.join(POPULATIONS)} (or 'none')"
            )
        try:
            value = float(weight) if weight.strip() else 1.0
        except ValueError:
            raise ParameterError(f"halo crystals' weight {weight!r} is not a number") from None
        if not math.isfinite(value) or value < 0.0:
            raise ParameterError(f"halo crystals' weight must be >= 0, got {weight!r}")
        shares[name] = shares.get(name, 0.0) + value
    total = sum(shares.values())
    if total <= 0.0:
        raise ParameterError(f"halo crystals' weights add up to 0 in {spec!r}")
    return tuple((name, value / total) for name, value in shares.items() if value > 0.0)


def table_angles_deg() -> tuple[np.ndarray, np.ndarray]:
    """The table's cell centres (deg): elevations (-90 to 90) and azimuths from the light
    (0 to 180)."""
    el = -90.0 + GRID_DEG * (np.arange(round(180.0 / GRID_DEG)) + 0.5)
    az = GRID_DEG * (np.arange(round(180.0 / GRID_DEG)) + 0.5)
    return el, az


def _smooth(table: np.ndarray, el_deg: np.ndarray) -> np.ndarray:
    """``table`` (..., EL, AZ) smoothed by a Gaussian of SMOOTH_DEG rms in angle: along the
    elevation, and along the azimuth by SMOOTH_DEG / cos(elevation) (the azimuth's cells
    narrow towards the zenith), mirrored at 0 and 180 deg."""
    sigma = SMOOTH_DEG / GRID_DEG

    def along_last(rows: np.ndarray, s: float) -> np.ndarray:
        half = min(int(math.ceil(3.0 * s)), rows.shape[-1] - 1)
        x = np.arange(-half, half + 1)
        kernel = np.exp(-0.5 * (x / s) ** 2)
        kernel /= kernel.sum()
        padded = np.concatenate([rows[..., half:0:-1], rows, rows[..., -2 : -half - 2 : -1]], -1)
        return np.apply_along_axis(lambda r: np.convolve(r, kernel, mode="valid"), -1, padded)

    out = np.swapaxes(along_last(np.swapaxes(table, -1, -2), sigma), -1, -2)
    for i, el in enumerate(el_deg):
        s = min(sigma / max(math.cos(math.radians(el)), 1e-3), out.shape[-1] / 3.0)
        out[..., i, :] = along_last(out[..., i, :], s)
    return out


def _cell_solid_angles() -> np.ndarray:
    """The solid angle (sr) of the table's cells by elevation (EL,): GRID_DEG of azimuth on
    each side of the light's vertical (the table is folded) between two elevations."""
    el, _ = table_angles_deg()
    edges = np.radians(np.append(el - GRID_DEG / 2.0, 90.0))
    return 2.0 * math.radians(GRID_DEG) * np.diff(np.sin(edges))


def _angle_from_light_deg(light_elevation_deg: float) -> np.ndarray:
    """The angle (deg) between each cell's centre and the light (EL, AZ)."""
    el, az = table_angles_deg()
    elr, azr, e = (
        np.radians(el)[:, None],
        np.radians(az)[None, :],
        math.radians(light_elevation_deg),
    )
    cos_angle = np.sin(elr) * math.sin(e) + np.cos(elr) * math.cos(e) * np.cos(azr)
    return np.degrees(np.arccos(np.clip(cos_angle, -1.0, 1.0)))


def _random_phase(rays: int) -> tuple[np.ndarray, np.ndarray]:
    """Crystals at random orientations scatter by the angle from the light alone: their
    phase function (TRACE_NM, A) in 1/sr at RANDOM_BIN_DEG bins' centres (A,), traced once
    (for a light at the zenith) with far less noise than a table's cells would have."""
    key = ("random", rays)
    if key not in _RANDOM:
        body, orientation = POPULATIONS["random"]
        s = scatter(body, orientation, 90.0, TRACE_NM, rays, 1, min_weight=MIN_WEIGHT)
        edges = np.arange(0.0, 180.0 + RANDOM_BIN_DEG / 2.0, RANDOM_BIN_DEG)
        angle = 90.0 - s.elevation_deg
        bins = np.clip((angle / RANDOM_BIN_DEG).astype(int), 0, edges.size - 2)
        k = len(TRACE_NM)
        light = np.bincount(s.wavelength * (edges.size - 1) + bins, weights=s.weight,
                            minlength=k * (edges.size - 1)).reshape(k, -1)  # fmt: skip
        solid = 2.0 * math.pi * -np.diff(np.cos(np.radians(edges)))
        _RANDOM[key] = (0.5 * (edges[:-1] + edges[1:]), light / solid)
    return _RANDOM[key]


def _traced(name: str, light_elevation_deg: float, rays: int) -> np.ndarray:
    """One population's light (TRACE_NM, EL, AZ): per wavelength, the share scattered into
    each cell (adding up to ~1 over the cells)."""
    n = round(180.0 / GRID_DEG)
    if name == "random":
        centres, phase = _random_phase(RANDOM_RAYS_FACTOR * rays)
        angle = _angle_from_light_deg(light_elevation_deg)
        solid = _cell_solid_angles()[:, None]
        return np.stack([np.interp(angle, centres, row) * solid for row in phase])
    body, orientation = POPULATIONS[name]
    wl = np.asarray(TRACE_NM)
    seed = 1 + list(POPULATIONS).index(name)
    s = scatter(body, orientation, light_elevation_deg, wl, rays, seed, min_weight=MIN_WEIGHT)
    row = np.clip(((s.elevation_deg + 90.0) / GRID_DEG).astype(int), 0, n - 1)
    col = np.clip((np.abs(s.azimuth_deg) / GRID_DEG).astype(int), 0, n - 1)
    cell = (s.wavelength * n + row) * n + col
    return np.bincount(cell, weights=s.weight, minlength=wl.size * n * n).reshape(wl.size, n, n)


def halo_table(spec: str, light_elevation_deg: float, wavelengths_nm, to_output,
               rays: int = RAYS) -> np.ndarray:  # fmt: skip
    """The crystals' phase function per output channel (4, EL, AZ) in 1/sr, float32, for
    the light at ``light_elevation_deg`` (rounded to ELEVATION_STEP_DEG; azimuth 0): over
    the directions seen (:func:`table_angles_deg`), weighted as sunlight's share of each
    channel (``to_output`` (4, W) at ``wavelengths_nm``), smoothed over the Sun's disk, cut
    flat within TRUNCATION_DEG of the light and normalised over the sphere per channel."""
    mixture = parse_halos(spec)
    if not mixture:
        raise ParameterError("no halo crystals: nothing to tabulate")
    e = ELEVATION_STEP_DEG * round(float(light_elevation_deg) / ELEVATION_STEP_DEG)
    e = min(max(e, -90.0), 90.0)
    m = np.asarray(to_output, dtype=float)
    wl = np.asarray(wavelengths_nm, dtype=float)
    key = (mixture, e, wl.tobytes(), m.tobytes(), int(rays))
    if key in _CACHE:
        _CACHE.move_to_end(key)
        return _CACHE[key]
    traced = sum(share * _traced(name, e, rays) for name, share in mixture)
    # the frame's wavelengths between the traced ones (held beyond them)
    between = np.stack([np.interp(wl, TRACE_NM, row) for row in np.eye(len(TRACE_NM))], 1)
    light = np.einsum("wk,kij->wij", between, traced)
    el, _ = table_angles_deg()
    solid = _cell_solid_angles()
    channels = np.einsum("cw,wij->cij", m, light) / m.sum(axis=1)[:, None, None]
    channels = _smooth(np.maximum(channels, 0.0) / solid[:, None], el)
    # flat within TRUNCATION_DEG of the light: the mean of the ring a degree outside it
    angle = _angle_from_light_deg(e)
    ring = (angle >= TRUNCATION_DEG) & (angle < TRUNCATION_DEG + 1.0)
    area = solid[:, None] * np.ones_like(angle)
    for c in range(channels.shape[0]):
        channels[c][angle < TRUNCATION_DEG] = np.average(channels[c][ring], weights=area[ring])
        channels[c] /= max(float((channels[c] * area).sum()), 1e-30)
    table = channels.astype(np.float32)
    _CACHE[key] = table
    while len(_CACHE) > CACHE_SIZE:
        _CACHE.popitem(last=False)
    return table
