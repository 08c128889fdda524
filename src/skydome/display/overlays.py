"""Overlays: constellation lines, labels and the altitude/azimuth grid over the display image.

Overlays are not light. They are drawn over the tone-mapped 8-bit image (sRGB-encoded RGBA8,
GL rows), never into a frame's cd/m^2, and are off unless asked for:

>>> ov = Overlays(ctx, parse_overlays("lines,labels,grid"))
>>> ov.update(state)                       # a SkyState: positions for its time and place
>>> ov.draw(fbo, camera, (width, height))  # over the image in fbo, alpha blended

- ``lines``: the stick figures of the 88 constellations (d3-celestial, BSD-3-Clause:
  ``skydome/data/constellations.json`` and ``constellations.txt``), as pairs of Hipparcos
  stars of skydome's catalogue. The ends sit where the stars layer draws the stars: the
  apparent place of date (:func:`skydome.astro.stars.apparent_unit_vectors`) turned to the
  observer's East-North-Up frame with the apparent sidereal time, refracted with the
  state's weather (:func:`skydome.astro.frames.refraction_saemundsson`, the state's pressure
  and temperature, as :class:`skydome.astro.Observer` does). Each segment is a great circle,
  cut into pieces of at most ``SUBDIVISION_DEG`` so that it curves as it should in the
  fisheye and equirect frames; pieces are refracted point by point, split at the equirect
  seam (drawn on both sides), split at the cube's edges, dropped behind a perspective
  camera, and clipped at the horizon.
- ``labels``: the IAU names of the stars brighter than ``STAR_LABEL_MAG`` (V), the planets
  (positions from :meth:`skydome.astro.Observer.sky`) and the Moon, beside their objects,
  and the constellations' names at their label points (d3-celestial's), none below the
  horizon. Text comes from an atlas of the labels drawn at run time with Pillow's built-in
  font (Aileron Regular, CC0-1.0, bundled with Pillow >= 10.1; Pillow's bitmap font where
  FreeType is missing), with a dark outline.
- ``grid``: altitude circles every ``ALT_STEP_DEG``, azimuth lines every ``AZ_STEP_DEG``
  (up to ``AZ_MAX_ALT_DEG``), the horizon brighter, N, E, S, W marked above it. Lines are
  antialiased per pixel from the pixel's direction (``common/camera.glsl``), their width
  in pixels from the local pixel scale.

In the abstract mode (``state.observer`` None) only the grid is drawn. A
:class:`~skydome.core.cameras.DirectionsCamera` has no image plane: nothing is drawn.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import unicodedata
from collections.abc import Iterable
from dataclasses import dataclass
from importlib import resources

import moderngl
import numpy as np

from skydome.astro import frames, planets, stars
from skydome.astro.time import gast
from skydome.core.cameras import Camera, CameraInputs, CubemapCamera
from skydome.errors import ParameterError, check_range
from skydome.gpu import shared_context
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.passes import ShaderProgram
from skydome.physics.refraction import refract_enu

__all__ = [
    "OVERLAYS",
    "DEFAULT_COLOURS",
    "Constellation",
    "Overlays",
    "constellations",
    "parse_overlays",
]

#: The overlays, in the order they are drawn (lowest first is the grid: see draw()).
OVERLAYS = ("lines", "labels", "grid")
#: Display (sRGB-encoded, 0-1) colours of each overlay.
DEFAULT_COLOURS = {
    "lines": (0.40, 0.58, 0.95),
    "labels": (0.92, 0.93, 0.97),
    "grid": (0.86, 0.48, 0.36),
}
#: Grid spacing (deg): altitude circles, azimuth lines, and where azimuth lines stop.
ALT_STEP_DEG = 10.0
AZ_STEP_DEG = 30.0
AZ_MAX_ALT_DEG = 80.0
#: Longest piece (deg) of a constellation line's great circle drawn as one straight quad.
SUBDIVISION_DEG = 2.0
#: Stars brighter than this (V) get their IAU name.
STAR_LABEL_MAG = 1.5
#: The stars' apparent places of date are recomputed when the time moves by more than this
#: (days of TT): precession, nutation and aberration move a star by < 0.01" per hour.
STAR_REFRESH_DAYS = 1.0 / 24.0
#: The planets' places are recomputed after this (days): Mercury, the fastest, moves
#: < 0.05 deg in 10 minutes (a label's position, not a drawn disk).
PLANET_REFRESH_DAYS = 10.0 / 1440.0
#: The lines' coverage target is drawn in tiles of at most this many pixels a side.
MAX_TILE = 2048
#: Opacities: constellation lines; the grid above and below the horizon; the horizon; the
#: labels' outline.
LINE_OPACITY = 0.75
GRID_OPACITY = 0.5
GRID_BELOW_OPACITY = 0.25
HORIZON_OPACITY = 0.95
OUTLINE_OPACITY = 0.8
#: Gap (px) between an object and its label's box.
LABEL_GAP_PX = 4.0
#: Where a label would overlap one placed before it, it may move up or down by these many
#: times its height (in this order), else it is left out.
LABEL_SHIFTS = (0.0, 1.2, -1.2, 2.4, -2.4)

_DATA_FILE = "constellations.json"
_FORMAT_VERSION = 1
_PLANET_NAMES = {
    "mercury": "Mercury",
    "venus": "Venus",
    "mars": "Mars",
    "jupiter": "Jupiter",
    "saturn": "Saturn",
    "uranus": "Uranus",
    "neptune": "Neptune",
}
_CARDINALS = (("N", 0.0), ("E", 90.0), ("S", 180.0), ("W", 270.0))


def parse_overlays(text: str | list[str] | tuple[str, ...]) -> tuple[str, ...]:
    """The overlays named in a comma-separated list, e.g. ``"lines,labels"`` ->
    ``("lines", "labels")``, in the given order without repeats (or in names, e.g.
    ``["lines", "labels"]``). ``""`` or ``"none"`` gives ``()``, ``"all"`` every overlay.
    Raises ParameterError naming an unknown name, or a value that is neither."""
    if not isinstance(text, str):
        names = list(text) if hasattr(text, "__iter__") else None
        if names is None or not all(isinstance(name, str) for name in names):
            raise ParameterError(
                f"overlays must be a comma-separated string or names, got {text!r}"
            )
        text = ",".join(names)
    out: list[str] = []
    for part in text.split(","):
        name = part.strip().lower()
        if name in ("", "none"):
            continue
        if name == "all":
            names = OVERLAYS
        elif name in OVERLAYS:
            names = (name,)
        else:
            raise ParameterError(
                f"overlay {part.strip()!r} is unknown; choose from {', '.join(OVERLAYS)} "
                "(comma-separated), all or none"
            )
        out.extend(n for n in names if n not in out)
    return tuple(out)


# ---------------------------------------------------------------------------- data


@dataclass(frozen=True)
class Constellation:
    """One constellation of the packaged figures.

    ``abbr``: IAU abbreviation; ``name``, ``genitive``: IAU names; ``rank``: 1 (prominent)
    to 3 (faint), d3-celestial's; ``label_j2000``: unit vector (ICRS, J2000) of its label
    point; ``segments``: the figure's segments, each a pair of ends, an end being a HIP
    number (int) or a J2000 (ra_deg, dec_deg) pair where the catalogue lacks the star.
    """

    abbr: str
    name: str
    genitive: str
    rank: int
    label_j2000: np.ndarray
    segments: tuple


def _unit_radec(ra_deg, dec_deg) -> np.ndarray:
    ra, dec = np.radians(ra_deg), np.radians(dec_deg)
    return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], -1)


@functools.lru_cache(maxsize=1)
def constellations() -> tuple[Constellation, ...]:
    """The packaged constellation figures (89 entries: Serpens has two parts)."""
    text = resources.files("skydome.data").joinpath(_DATA_FILE).read_text(encoding="utf-8")
    doc = json.loads(text)
    if doc.get("format_version") != _FORMAT_VERSION:
        raise ParameterError(
            f"{_DATA_FILE} has format {doc.get('format_version')}, expected {_FORMAT_VERSION}; "
            "rebuild it with tools/build_constellations.py"
        )
    out = []
    for c in doc["constellations"]:
        segs = tuple(
            tuple(e if isinstance(e, int) else (float(e[0]), float(e[1])) for e in seg)
            for seg in c["segments"]
        )
        out.append(
            Constellation(
                abbr=c["abbr"],
                name=c["name"],
                genitive=c["genitive"],
                rank=int(c["rank"]),
                label_j2000=_unit_radec(c["label_ra_deg"], c["label_dec_deg"]),
                segments=segs,
            )
        )
    return tuple(out)


@dataclass(frozen=True)
class _Figures:
    """The figures as arrays: star rows and fixed J2000 points, and segments between them."""

    star_rows: np.ndarray  # (S,) catalogue rows of the stars that end segments
    fixed_j2000: np.ndarray  # (F, 3) unit vectors of the ends not in the catalogue
    ends: np.ndarray  # (N, 2) indices into concat(stars, fixed)


@functools.lru_cache(maxsize=1)
def _figures() -> _Figures:

    cat = stars.catalog()
    rows: dict[int, int] = {}
    fixed: dict[tuple, int] = {}
    pairs = []
    for c in constellations():
        for seg in c.segments:
            pair = []
            for end in seg:
                if not isinstance(end, int):
                    pair.append(("f", fixed.setdefault(end, len(fixed))))
                elif cat.index_of_hip(end) is not None:
                    pair.append(("s", rows.setdefault(end, len(rows))))
                else:  # a HIP number not in the catalogue: the segment is left out
                    break
            if len(pair) == 2:
                pairs.append(pair)
    n_s = len(rows)
    ends = np.array([[i if k == "s" else n_s + i for k, i in p] for p in pairs], dtype=np.int64)
    star_rows = np.array([cat.index_of_hip(h) for h in rows], dtype=np.int64)
    fixed_pts = (
        _unit_radec(np.array([k[0] for k in fixed]), np.array([k[1] for k in fixed]))
        if fixed
        else np.zeros((0, 3))
    )
    return _Figures(star_rows, fixed_pts.reshape(-1, 3), ends.reshape(-1, 2))


@functools.lru_cache(maxsize=1)
def _bright_named_stars() -> tuple[np.ndarray, tuple[str, ...]]:
    """Catalogue rows and IAU names of the named stars brighter than STAR_LABEL_MAG."""

    cat = stars.catalog()
    names = stars._names().proper  # HIP -> IAU proper name (stars_names.csv)
    picked = sorted(
        (int(cat.index_of_hip(h)), n)
        for h, n in names.items()
        if cat.index_of_hip(h) is not None and cat.vmag[cat.index_of_hip(h)] < STAR_LABEL_MAG
    )
    return np.array([r for r, _ in picked], dtype=np.int64), tuple(n for _, n in picked)


def _slerp_pieces(a: np.ndarray, b: np.ndarray, counts: np.ndarray):
    """Great-circle points between unit vectors a (N, 3) and b (N, 3), arc i cut into
    ``counts[i]`` equal pieces: returns points (M, 3) and pieces (K, 2) indexing them."""
    ang = np.arccos(np.clip(np.sum(a * b, axis=-1), -1.0, 1.0))
    n = np.maximum(np.asarray(counts, dtype=np.int64), 1)
    seg = np.repeat(np.arange(len(a)), n + 1)
    start = np.concatenate([[0], np.cumsum(n + 1)[:-1]])
    t = ((np.arange(seg.size) - np.repeat(start, n + 1)) / np.repeat(n, n + 1))[:, None]
    s, w = np.sin(ang)[seg][:, None], ang[seg][:, None]
    tiny = s < 1e-12  # coincident ends: a straight blend
    safe = np.where(tiny, 1.0, s)
    wa = np.where(tiny, 1.0 - t, np.sin((1.0 - t) * w) / safe)
    wb = np.where(tiny, t, np.sin(t * w) / safe)
    pts = wa * a[seg] + wb * b[seg]
    pts /= np.linalg.norm(pts, axis=-1, keepdims=True)
    last = np.cumsum(n + 1) - 1
    first = np.setdiff1d(np.arange(seg.size), last)
    return pts, np.stack([first, first + 1], axis=-1)


def _arc_counts(a: np.ndarray, b: np.ndarray, max_rad: float) -> np.ndarray:
    """Pieces per arc so that none is longer than ``max_rad``."""
    ang = np.arccos(np.clip(np.sum(a * b, axis=-1), -1.0, 1.0))
    return np.maximum(np.ceil(ang / max_rad).astype(np.int64), 1)


def refine_in_azimuth(a: np.ndarray, b: np.ndarray, max_rad: float, max_split: int = 90):
    """Pieces (a, b) (N, 3) of ENU great circles cut again where their azimuth turns by more
    than ``max_rad``: near the zenith a short piece can sweep far in azimuth, and the
    equirect frame, linear in azimuth and altitude, needs the curve followed there."""
    daz = np.abs(
        np.angle(np.exp(1j * (np.arctan2(b[:, 0], b[:, 1]) - np.arctan2(a[:, 0], a[:, 1]))))
    )
    k = np.clip(np.ceil(daz / max_rad).astype(np.int64), 1, max_split)
    big = k > 1
    if not np.any(big):
        return a, b
    pts, pieces = _slerp_pieces(a[big], b[big], k[big])
    return (
        np.concatenate([a[~big], pts[pieces[:, 0]]]),
        np.concatenate([b[~big], pts[pieces[:, 1]]]),
    )


def refract(enu: np.ndarray, pressure_hPa: float, temperature_C: float) -> np.ndarray:
    """Apparent unit ENU vectors of airless ones (..., 3): the altitude raised by
    Saemundsson's refraction (Meeus eq. 16.4) for the weather, the azimuth kept, as
    :class:`skydome.astro.Observer` places every body."""
    return refract_enu(enu, pressure_hPa, temperature_C)[0]


def _cube_face(d: np.ndarray) -> np.ndarray:
    ax = np.argmax(np.abs(d), axis=-1)
    comp = np.take_along_axis(d, ax[..., None], axis=-1)[..., 0]
    return 2 * ax + (comp < 0)


def split_at_cube_edges(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pieces (a, b) (N, 3) cut where they cross from one cube face to another (the
    cubemap camera's faces): each crossing found by bisection along the great circle
    (2^-40 of the piece), the two parts ending 2e-6 rad either side of it."""
    for _ in range(3):  # a short piece crosses at most two edges (near a corner)
        fa, fb = _cube_face(a), _cube_face(b)
        cross = np.flatnonzero(fa != fb)
        if cross.size == 0:
            break
        lo = np.zeros(cross.size)
        hi = np.ones(cross.size)
        aa, bb = a[cross], b[cross]

        def point(t, aa=aa, bb=bb):
            p = (1.0 - t)[:, None] * aa + t[:, None] * bb  # same great circle, monotone in t
            return p / np.linalg.norm(p, axis=-1, keepdims=True)

        for _ in range(40):
            mid = 0.5 * (lo + hi)
            same = _cube_face(point(mid)) == fa[cross]
            lo = np.where(same, mid, lo)
            hi = np.where(same, hi, mid)
        # Ends 2e-6 rad either side of the edge: clear of it in float32 (6e-8 rad steps).
        ang = np.arccos(np.clip(np.sum(aa * bb, axis=-1), -1.0, 1.0))
        margin = np.minimum(2e-6 / np.maximum(ang, 1e-9), 0.01)
        p_lo, p_hi = point(np.maximum(lo - margin, 0.0)), point(np.minimum(hi + margin, 1.0))
        keep = np.ones(len(a), bool)
        keep[cross] = False
        a = np.concatenate([a[keep], aa, p_hi])
        b = np.concatenate([b[keep], p_lo, bb])
    return a, b


# ---------------------------------------------------------------------------- text atlas


def _font(font_px: int):
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=font_px), True  # Aileron Regular (FreeType)
    except (TypeError, OSError, ImportError):  # Pillow without FreeType: the bitmap font
        return ImageFont.load_default(), False


def _displayable(text: str, font) -> str:
    """``text`` with each character the font lacks (drawn as its "missing glyph" box)
    replaced by its base letter (Unicode NFKD without the accents): Pillow's built-in
    Aileron has a limited character set, e.g. no "o" with diaeresis for Bootes."""

    missing = np.asarray(font.getmask("\uffff"))
    out = []
    for ch in text:
        if ch.isascii() or not np.array_equal(np.asarray(font.getmask(ch)), missing):
            out.append(ch)
        else:
            base = unicodedata.normalize("NFKD", ch)
            out.append("".join(c for c in base if not unicodedata.combining(c)) or "?")
    return "".join(out)


@dataclass
class _Atlas:
    """Label bitmaps packed in one image: R = glyph coverage, G = glyphs + outline."""

    image: np.ndarray  # (H, W, 2) uint8, row 0 at the top
    boxes: dict  # text -> (x, y_gl, w, h): origin in GL texel rows (row 0 = bottom)


def build_atlas(texts: Iterable[str], font_px: int, width: int = 1024) -> _Atlas:
    """Draw each text once with Pillow (fill, and fill widened by an outline of
    ~font_px / 7 px) and pack the bitmaps in rows ("shelf" packing) of ``width`` texels."""
    from PIL import Image, ImageDraw, ImageFilter

    font, freetype = _font(font_px)
    stroke = max(1, round(font_px / 7))
    bitmaps = {}
    for key in dict.fromkeys(texts):
        text = _displayable(key, font)
        if freetype:
            l, t, r, b = font.getbbox(text, stroke_width=stroke)
        else:
            l, t, r, b = font.getbbox(text)
            l, t, r, b = l - stroke, t - stroke, r + stroke, b + stroke
        w, h = max(r - l, 1), max(b - t, 1)
        fill = Image.new("L", (w, h), 0)
        ImageDraw.Draw(fill).text((-l, -t), text, font=font, fill=255)
        if freetype:
            ring = Image.new("L", (w, h), 0)
            ImageDraw.Draw(ring).text(
                (-l, -t), text, font=font, fill=255, stroke_width=stroke, stroke_fill=255
            )
        else:
            ring = fill.filter(ImageFilter.MaxFilter(2 * stroke + 1))
        bitmaps[key] = np.stack([np.asarray(fill), np.maximum(np.asarray(ring), fill)], -1)
    pad = 1
    width = max([width] + [bm.shape[1] + 2 * pad for bm in bitmaps.values()])
    x = y = row_h = 0
    places = {}
    for text, bm in bitmaps.items():
        h, w = bm.shape[:2]
        if x + w + pad > width:
            x, y, row_h = 0, y + row_h + pad, 0
        places[text] = (x + pad, y + pad)
        x += w + pad
        row_h = max(row_h, h + pad)
    total_h = max(y + row_h + pad, 1)
    image = np.zeros((total_h, width, 2), np.uint8)
    boxes = {}
    for text, bm in bitmaps.items():
        px, py = places[text]
        h, w = bm.shape[:2]
        image[py : py + h, px : px + w] = bm
        boxes[text] = (px, total_h - py - h, w, h)
    return _Atlas(image, boxes)


# ---------------------------------------------------------------------------- overlays


@dataclass(frozen=True)
class _Label:
    """A label: its text, anchor and "up" directions (apparent unit ENU), placement mode
    (0 beside the anchor, 1 centred above it towards ``up``), offset (px), alignment
    (fractions of its box), colour (an overlay's name) and priority (lower first)."""

    text: str
    anchor: np.ndarray
    up: np.ndarray
    mode: int
    offset: tuple
    align: tuple
    kind: str
    priority: int


def _check_colour(kind: str, value) -> tuple[float, float, float]:
    c = np.asarray(value, dtype=float).ravel()
    if c.size != 3 or not np.all((c >= 0) & (c <= 1)):
        raise ParameterError(
            f"overlay colour for {kind} = {value!r} must be three numbers in [0, 1] (display RGB)"
        )
    return tuple(float(x) for x in c)


@dataclass(frozen=True)
class GridInputs(ShaderInputs):
    """``post/overlay_grid.glsl``: the line width (px), the grid's steps in altitude and
    azimuth (rad) and the altitude above which azimuth lines stop, the colours and
    opacities of the grid, of the horizon and below it."""

    u_line_width: float
    u_alt_step: float
    u_az_step: float
    u_az_max_alt: float
    u_colour: tuple[float, ...]
    u_horizon_colour: tuple[float, ...]
    u_opacity: float
    u_below_opacity: float
    u_horizon_opacity: float


@dataclass(frozen=True)
class LineInputs(ShaderInputs):
    """``post/overlay_lines*.glsl``: the coverage tile's size (px), the quads' half extent
    and the line width (px), the lowest view z drawn, which copy of a wrapped map."""

    u_viewport: tuple[float, float]
    u_half_extent: float
    u_line_width: float
    u_min_z: float
    u_copy: int


@dataclass(frozen=True)
class CompositeInputs(ShaderInputs):
    """``post/overlay_composite.glsl``: the lines' coverage (a texture), the tile's origin
    in the frame (px), the lines' colour and opacity."""

    u_coverage: object
    u_origin: tuple[float, float]
    u_colour: tuple[float, ...]
    u_opacity: float


@dataclass(frozen=True)
class TextInputs(ShaderInputs):
    """``post/overlay_text*.glsl``: the frame's size (px), which copy of a wrapped map, the
    glyph atlas (a texture), the outline's colour and opacity."""

    u_viewport: tuple[float, float]
    u_copy: int
    u_atlas: object
    u_outline_colour: tuple[float, float, float]
    u_outline_opacity: float


_INPUTS = {
    "post/overlay_grid.glsl": (CameraInputs, GridInputs),
    "post/overlay_lines.glsl": (CameraInputs, LineInputs),
    "post/overlay_composite.glsl": (CompositeInputs,),
    "post/overlay_text.glsl": (CameraInputs, TextInputs),
}


class Overlays:
    """Constellation lines, labels and the alt/az grid, drawn over a tone-mapped image.

    Args:
        ctx: a moderngl context (None: the shared headless one).
        kinds: overlays to draw, names from :data:`OVERLAYS` (see :func:`parse_overlays`).
        colour: display RGB (0-1, sRGB-encoded) for every overlay, or a dict per overlay
            name; None gives :data:`DEFAULT_COLOURS`.
        line_width_px: width of the lines (px); the horizon is 1.5 times wider.
        font_px: size of the labels' font (px).
    """

    def __init__(
        self,
        ctx,
        kinds: Iterable[str],
        *,
        colour=None,
        line_width_px: float = 1.5,
        font_px: int = 14,
    ):

        if isinstance(kinds, str):
            kinds = parse_overlays(kinds)
        kinds = tuple(kinds)
        for k in kinds:
            if k not in OVERLAYS:
                raise ParameterError(f"overlay {k!r} is unknown; choose from {', '.join(OVERLAYS)}")
        self.kinds = tuple(k for k in OVERLAYS if k in kinds)
        self.line_width_px = check_range("overlay line width", line_width_px, 0.25, 32.0, "px")
        if not isinstance(font_px, (int, np.integer)) or not 6 <= font_px <= 128:
            raise ParameterError(f"overlay font size {font_px!r} must be an integer in [6, 128] px")
        self.font_px = int(font_px)
        colours = dict(DEFAULT_COLOURS)
        if isinstance(colour, dict):
            for k, v in colour.items():
                if k not in OVERLAYS:
                    raise ParameterError(
                        f"overlay colour for {k!r}: unknown overlay; choose from "
                        f"{', '.join(OVERLAYS)}"
                    )
                colours[k] = _check_colour(k, v)
        elif colour is not None:
            c = _check_colour("all overlays", colour)
            colours = {k: c for k in OVERLAYS}
        self.colours = colours
        self.ctx = ctx if ctx is not None or not self.kinds else shared_context()
        self._programs: dict = {}
        self._vaos: dict = {}
        self._buffers: dict = {}
        self._targets: dict = {}
        self._atlas_tex = None
        self._atlas: _Atlas | None = None
        self._pieces = np.zeros((0, 6), np.float32)
        self._labels: list = []
        self._dirty = True
        self._star_cache = None  # (jd_tt, star dirs of date, fixed dirs, label dirs, names)
        self._planet_cache = None  # (jd_tt, {name: unit vector of date})
        if self.kinds:
            self._atlas = build_atlas(self._texts(), self.font_px)

    # ------------------------------------------------------------------ positions

    def _texts(self) -> list[str]:
        texts = []
        if "grid" in self.kinds:
            texts += [c for c, _ in _CARDINALS]
        if "labels" in self.kinds:
            texts += list(_bright_named_stars()[1])
            texts += list(_PLANET_NAMES.values()) + ["Moon"]
            texts += [c.name for c in constellations()]
        return texts

    def _date_places(self, jd_tt: float):
        """Unit vectors, true equator and equinox of date, of the line ends (catalogue stars
        apparent, fixed points precessed), the labelled stars and the constellation labels."""

        cache = self._star_cache
        if cache is not None and abs(cache[0] - jd_tt) <= STAR_REFRESH_DAYS:
            return cache[1]
        fig = _figures()
        rows, _ = _bright_named_stars()
        both = np.concatenate([fig.star_rows, rows])
        dirs = stars.apparent_unit_vectors(jd_tt, both)
        m = (
            frames.nutation_matrix(np.atleast_1d(jd_tt))
            @ frames.precession_matrix(np.atleast_1d(jd_tt))
        )[0]
        fixed = fig.fixed_j2000 @ m.T
        labels = np.array([c.label_j2000 for c in constellations()]) @ m.T
        n_s = len(fig.star_rows)
        ends_date = np.concatenate([dirs[:n_s], fixed])
        ea, eb = ends_date[fig.ends[:, 0]], ends_date[fig.ends[:, 1]]
        pts, pieces = _slerp_pieces(ea, eb, _arc_counts(ea, eb, math.radians(SUBDIVISION_DEG)))
        places = {"points": pts, "pieces": pieces, "stars": dirs[n_s:], "labels": labels}
        self._star_cache = (jd_tt, places)
        return places

    def _planet_places(self, state, jd_tt: float) -> dict:

        cache = self._planet_cache
        if cache is not None and abs(cache[0] - jd_tt) <= PLANET_REFRESH_DAYS:
            return cache[1]
        sky = state.observer.sky(state.time, bodies=planets.PLANETS)
        out = {}
        for name in planets.PLANETS:
            b = sky[name]
            ra, dec = float(np.ravel(b.ra)[0]), float(np.ravel(b.dec)[0])
            out[name] = np.array(
                [math.cos(dec) * math.cos(ra), math.cos(dec) * math.sin(ra), math.sin(dec)]
            )
        self._planet_cache = (jd_tt, out)
        return out

    def update(self, state) -> None:
        """Positions for the state's time and place (cheap between refreshes: the places of
        date are cached, each update turns them to ENU with one 3x3 matrix and refracts)."""

        self._dirty = True
        self._pieces = np.zeros((0, 6), np.float32)
        self._labels = []
        if "grid" in self.kinds:
            for text, az in _CARDINALS:
                a = frames.horizontal_to_enu(0.0, math.radians(az))
                up = frames.horizontal_to_enu(math.radians(1.0), math.radians(az))
                self._labels.append(_Label(text, a, up, 1, (0.0, 3.0), (0.5, 0.5), "grid", 0))
        if (
            state.observer is None
            or state.time is None
            or not ({"lines", "labels"} & set(self.kinds))
        ):
            return
        obs = state.observer
        jd_tt = float(np.ravel(state.time.jd_tt)[0])
        jd_ut1 = float(np.ravel(state.time.jd_ut1)[0])
        lst = float(gast(jd_ut1, jd_tt)) + math.radians(float(obs.longitude))
        enu_m = frames.equatorial_to_enu_matrix(lst, math.radians(float(obs.latitude)))
        p, t = float(state.pressure_hPa), float(state.temperature_C)
        places = self._date_places(jd_tt)
        # Diurnal aberration (<= 0.32"), as the stars layer applies it: the observer moves
        # east at the Earth's rotation rate times its distance from the axis.
        speed = frames.diurnal_speed_au_per_day(
            math.radians(float(obs.latitude)), float(obs.elevation_m)
        )
        v_east = np.array([speed, 0.0, 0.0])

        def apparent(date_dirs: np.ndarray) -> np.ndarray:
            return refract(frames.aberrate(date_dirs @ enu_m.T, v_east), p, t)

        if "lines" in self.kinds:
            pts = apparent(places["points"])
            a, b = pts[places["pieces"][:, 0]], pts[places["pieces"][:, 1]]
            up = (a[:, 2] >= 0) | (b[:, 2] >= 0)  # the rest lies below the horizon
            a, b = refine_in_azimuth(a[up], b[up], math.radians(SUBDIVISION_DEG))
            self._pieces = np.concatenate([a, b], axis=1).astype(np.float32)

        if "labels" in self.kinds:
            _, star_names = _bright_named_stars()
            star_enu = apparent(places["stars"])
            objects = list(zip(star_names, star_enu, strict=True))
            for name, u in self._planet_places(state, jd_tt).items():
                objects.append((_PLANET_NAMES[name], refract(enu_m @ u, p, t)))
            if state.moon is not None:
                objects.append(("Moon", np.asarray(state.moon.direction, float)))
            offset = (LABEL_GAP_PX + 1.0, LABEL_GAP_PX - 1.0)
            for i, (name, u) in enumerate(objects):
                prio = 2 if i < len(star_names) else 1  # planets and the Moon first
                if u[2] > 0:
                    self._labels.append(_Label(name, u, u, 0, offset, (0.0, 0.0), "labels", prio))
            con_enu = apparent(places["labels"])
            for c, u in zip(constellations(), con_enu, strict=True):
                if u[2] > 0:
                    self._labels.append(
                        _Label(c.name, u, u, 0, (0.0, 0.0), (0.5, 0.5), "lines", 2 + c.rank)
                    )

    def info(self) -> dict:
        """What the last update placed: the overlays, line pieces and labels."""
        return {
            "overlays": list(self.kinds),
            "line_pieces": int(len(self._pieces)),
            "labels": int(len(self._labels)),
        }

    # ------------------------------------------------------------------ GPU

    def _program(self, name: str, model: int, vertex: str | None = None) -> ShaderProgram:
        key = (name, model)
        if key not in self._programs:
            self._programs[key] = ShaderProgram(
                self.ctx, name, {"CAMERA_MODEL": model}, inputs=_INPUTS[name], vertex=vertex
            )
        return self._programs[key]

    def _fullscreen(self, name: str, model: int):
        prog = self._program(name, model)
        key = ("fs", name, model)
        if key not in self._vaos:
            self._vaos[key] = self.ctx.vertex_array(prog.program, [])
        return self._vaos[key], prog

    def _buffer(self, key: str, data: np.ndarray):
        data = np.ascontiguousarray(data, dtype="f4")
        buf = self._buffers.get(key)
        if buf is None or buf.size < max(data.nbytes, 4):
            if buf is not None:
                buf.release()
            buf = self._buffers[key] = self.ctx.buffer(reserve=max(data.nbytes, 64))
        if data.nbytes:
            buf.write(data.tobytes())
        return buf

    def _coverage_target(self, w: int, h: int):
        if (w, h) not in self._targets:
            for tex, fbo in self._targets.values():
                fbo.release()
                tex.release()
            self._targets.clear()
            tex = self.ctx.texture((w, h), 1, dtype="f1")
            tex.filter = (self.ctx.NEAREST, self.ctx.NEAREST)
            self._targets[(w, h)] = (tex, self.ctx.framebuffer(color_attachments=[tex]))
        return self._targets[(w, h)]

    def _atlas_texture(self):
        if self._atlas_tex is None:
            img = self._atlas.image
            tex = self.ctx.texture(
                (img.shape[1], img.shape[0]), 2, np.ascontiguousarray(img[::-1]).tobytes()
            )
            tex.filter = (self.ctx.NEAREST, self.ctx.NEAREST)
            self._atlas_tex = tex
        return self._atlas_tex

    def draw(self, fbo, camera: Camera, size: tuple[int, int]) -> None:
        """Draw the overlays over the image in ``fbo`` (RGBA8, GL rows, the whole frame of
        ``size`` = (width, height) px seen by ``camera``): grid, then lines, then labels,
        alpha blended (premultiplied), antialiased. Pixels no overlay touches keep their
        value bit for bit; so does the target's alpha channel. Nothing for a camera without
        a forward mapping (DirectionsCamera)."""
        if not self.kinds or not camera.has_projection:
            return

        ctx = self.ctx
        w, h = (int(v) for v in size)
        saved_viewport = fbo.viewport
        view = camera.inputs(w, h)
        try:
            ctx.enable(moderngl.BLEND)
            ctx.blend_equation = moderngl.FUNC_ADD
            ctx.blend_func = (
                moderngl.ONE,
                moderngl.ONE_MINUS_SRC_ALPHA,
                moderngl.ZERO,
                moderngl.ONE,
            )
            if "grid" in self.kinds:
                self._draw_grid(fbo, camera, w, h, view)
            if "lines" in self.kinds and len(self._pieces):
                self._draw_lines(fbo, camera, w, h)
            if self._labels:
                self._draw_labels(fbo, camera, w, h, view)
        finally:
            ctx.blend_equation = moderngl.FUNC_ADD
            ctx.blend_func = moderngl.ONE, moderngl.ZERO
            ctx.disable(moderngl.BLEND)
            fbo.viewport = saved_viewport

    def _draw_grid(self, fbo, camera, w, h, view: CameraInputs) -> None:

        vao, prog = self._fullscreen("post/overlay_grid.glsl", camera.model)
        c = np.asarray(self.colours["grid"])
        prog.apply(
            view,
            GridInputs(
                u_line_width=float(self.line_width_px),
                u_alt_step=math.radians(ALT_STEP_DEG),
                u_az_step=math.radians(AZ_STEP_DEG),
                u_az_max_alt=math.radians(AZ_MAX_ALT_DEG),
                u_colour=tuple(float(v) for v in c),
                u_horizon_colour=tuple(float(v) for v in np.minimum(c * 1.25 + 0.1, 1.0)),
                u_opacity=GRID_OPACITY,
                u_below_opacity=GRID_BELOW_OPACITY,
                u_horizon_opacity=HORIZON_OPACITY,
            ),
        )
        fbo.viewport = (0, 0, w, h)
        fbo.use()
        vao.render(moderngl.TRIANGLES, vertices=3)

    def _draw_lines(self, fbo, camera, w, h) -> None:

        ctx = self.ctx
        pieces = self._pieces
        if isinstance(camera, CubemapCamera):
            a, b = split_at_cube_edges(pieces[:, :3].astype(float), pieces[:, 3:].astype(float))
            pieces = np.concatenate([a, b], axis=1)
        prog = self._program("post/overlay_lines.glsl", camera.model, "post/overlay_lines_vs.glsl")
        buf = self._buffer("lines", pieces)
        key = ("lines_vao", camera.model)
        if key not in self._vaos or self._vaos[key][1] is not buf:
            if key in self._vaos:
                self._vaos[key][0].release()
            vao = ctx.vertex_array(
                prog.program, [(buf, "3f 3f/i", "in_a", "in_b")], skip_errors=True
            )
            self._vaos[key] = (vao, buf)
        vao = self._vaos[key][0]
        comp_vao, comp = self._fullscreen("post/overlay_composite.glsl", camera.model)
        tile = min(MAX_TILE, max(w, h))
        tex, cov_fbo = self._coverage_target(min(tile, w), min(tile, h))
        tw_max, th_max = tex.size
        copies = 2 if camera.model == 2 else 1
        for y0 in range(0, h, th_max):
            for x0 in range(0, w, tw_max):
                tw, th = min(tw_max, w - x0), min(th_max, h - y0)
                cov_fbo.viewport = (0, 0, tw, th)
                cov_fbo.clear(0.0, 0.0, 0.0, 0.0, viewport=(0, 0, tw, th))
                cov_fbo.use()
                ctx.blend_equation = moderngl.MAX
                ctx.blend_func = moderngl.ONE, moderngl.ONE
                tile_view = camera.inputs(w, h, (x0, y0))
                for copy in range(copies):
                    prog.apply(
                        tile_view,
                        LineInputs(
                            u_viewport=(float(tw), float(th)),
                            u_half_extent=0.5 * float(self.line_width_px) + 1.0,
                            u_line_width=float(self.line_width_px),
                            u_min_z=0.0,
                            u_copy=copy,
                        ),
                    )
                    vao.render(moderngl.TRIANGLE_STRIP, vertices=4, instances=len(pieces))
                ctx.blend_equation = moderngl.FUNC_ADD
                ctx.blend_func = (
                    moderngl.ONE,
                    moderngl.ONE_MINUS_SRC_ALPHA,
                    moderngl.ZERO,
                    moderngl.ONE,
                )
                fbo.viewport = (x0, y0, tw, th)
                fbo.use()
                comp.apply(
                    CompositeInputs(
                        u_coverage=tex,
                        u_origin=(float(x0), float(y0)),
                        u_colour=tuple(float(v) for v in self.colours["lines"]),
                        u_opacity=LINE_OPACITY,
                    )
                )
                comp_vao.render(moderngl.TRIANGLES, vertices=3)

    @staticmethod
    def _above_horizon(camera, box, w: int, h: int) -> bool:
        """True where the corners of a label's box (frame px) all see the sky above the
        horizon (the camera's directions): a label never hangs below it."""

        x0, y0, x1, y1 = box
        d, ok = camera.directions([x0, x1, x0, x1], [y0, y0, y1, y1], w, h)
        return bool(np.all(ok) and np.all(d[:, 2] >= 0.0))

    def _placed_labels(self, camera, w: int, h: int) -> list:
        """The labels to draw: those the camera sees, in order of priority (the horizon's
        marks, the planets and the Moon, the stars, the constellations by rank), each left
        out where its box would overlap one already placed. Boxes as the vertex shader
        places them (the camera's project, the float64 twin of its projection)."""

        labels = sorted(self._labels, key=lambda lab: lab.priority)
        if not labels:
            return []
        anchors = np.array([lab.anchor for lab in labels])
        ups = np.array([lab.up for lab in labels])
        x, y, seen = camera.project(anchors, w, h)
        xu, yu, _ = camera.project(ups, w, h)
        placed: list = []
        boxes: list = []
        for i, lab in enumerate(labels):
            if not seen[i]:
                continue
            bw, bh = self._atlas.boxes[lab.text][2:]
            size = np.array([bw, bh], float)
            p = np.array([x[i], y[i]])
            if lab.mode == 1:
                up = np.array([xu[i] - x[i], yu[i] - y[i]])
                n = np.linalg.norm(up)
                up = up / n if n > 1e-6 else np.array([0.0, 1.0])
                box = np.floor(p + up * (0.5 * bh + lab.offset[1]) - 0.5 * size + 0.5)
                shifts = [0.0]
            else:
                box = np.floor(p + np.asarray(lab.offset) - np.asarray(lab.align) * size + 0.5)
                shifts = LABEL_SHIFTS
            for shift in shifts:
                dy = math.floor(shift * bh + 0.5)
                b = (box[0] - 1, box[1] + dy - 1, box[0] + bw + 1, box[1] + dy + bh + 1)
                if lab.mode == 0 and not self._above_horizon(camera, b, w, h):
                    continue
                if not any(
                    b[0] < q[2] and q[0] < b[2] and b[1] < q[3] and q[1] < b[3] for q in boxes
                ):
                    boxes.append(b)
                    off = (float(lab.offset[0]), float(lab.offset[1] + dy))
                    placed.append(dataclasses.replace(lab, offset=off))
                    break
        return placed

    def _draw_labels(self, fbo, camera, w, h, view: CameraInputs) -> None:

        atlas = self._atlas
        rows = []
        for lab in self._placed_labels(camera, w, h):
            x, y, bw, bh = atlas.boxes[lab.text]
            colour = self.colours[lab.kind]
            rows.append(
                [*lab.anchor, *lab.up, *lab.offset, *lab.align, bw, bh, x, y, *colour, 1.0]
                + [float(lab.mode)]
            )
        if not rows:
            return
        data = np.asarray(rows, dtype="f4")
        prog = self._program("post/overlay_text.glsl", camera.model, "post/overlay_text_vs.glsl")
        buf = self._buffer("labels", data)
        key = ("labels_vao", camera.model)
        if key not in self._vaos or self._vaos[key][1] is not buf:
            if key in self._vaos:
                self._vaos[key][0].release()
            vao = self.ctx.vertex_array(
                prog.program,
                [
                    (
                        buf,
                        "3f 3f 2f 2f 2f 2f 4f 1f/i",
                        "in_anchor",
                        "in_up",
                        "in_offset",
                        "in_align",
                        "in_size",
                        "in_atlas",
                        "in_colour",
                        "in_mode",
                    )
                ],
                skip_errors=True,
            )
            self._vaos[key] = (vao, buf)
        vao = self._vaos[key][0]
        fbo.viewport = (0, 0, w, h)
        fbo.use()
        copies = 2 if camera.model == 2 else 1
        for copy in range(copies):
            prog.apply(
                view,
                TextInputs(
                    u_viewport=(float(w), float(h)),
                    u_copy=copy,
                    u_atlas=self._atlas_texture(),
                    u_outline_colour=(0.0, 0.0, 0.0),
                    u_outline_opacity=OUTLINE_OPACITY,
                ),
            )
            vao.render(moderngl.TRIANGLE_STRIP, vertices=4, instances=len(data))

    def release(self) -> None:
        """Free the GPU objects (programs, buffers, targets, the atlas texture)."""
        for vao in self._vaos.values():
            vao[0].release() if isinstance(vao, tuple) else vao.release()
        self._vaos.clear()
        for prog in self._programs.values():
            prog.release()
        self._programs.clear()
        for buf in self._buffers.values():
            buf.release()
        self._buffers.clear()
        for tex, fbo in self._targets.values():
            fbo.release()
            tex.release()
        self._targets.clear()
        if self._atlas_tex is not None:
            self._atlas_tex.release()
            self._atlas_tex = None
