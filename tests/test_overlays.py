"""Overlays (skydome.display.overlays): the grid where the camera puts altitudes, line ends on
the stars, labels beside their objects, the equirect seam and the cube's edges, tiling,
nothing touched when off, the option parser and the data's licence."""

from __future__ import annotations

import json
import math
from importlib import resources

import numpy as np
import pytest

from skydome.astro import Observer, frames
from skydome.astro.stars import catalog, find_star
from skydome.core.cameras import (
    CubemapCamera,
    EquirectCamera,
    FisheyeCamera,
    PerspectiveCamera,
)
from skydome.display import overlays as ov
from skydome.errors import ParameterError
from skydome.scene.state import abstract_state, state_at

WHITE = {"lines": (1.0, 1.0, 1.0), "labels": (1.0, 1.0, 1.0), "grid": (1.0, 1.0, 1.0)}
# Orion on a winter evening at Valletta (Orion ~50 deg up in the south).
OBSERVER = Observer(latitude=35.8989, longitude=14.5146, elevation_m=10.0)
TIME = "2018-01-20T20:00Z"


@pytest.fixture(scope="module")
def state():
    return state_at(OBSERVER, TIME)


def target(ctx, w, h, rgba=None):
    """An RGBA8 framebuffer (GL rows) holding ``rgba`` (h, w, 4 uint8, GL rows) or black."""
    data = np.zeros((h, w, 4), np.uint8) if rgba is None else rgba
    tex = ctx.texture((w, h), 4, np.ascontiguousarray(data).tobytes())
    return tex, ctx.framebuffer(color_attachments=[tex])


def read(fbo, w, h) -> np.ndarray:
    """(h, w, 4) uint8 in GL row order: row j has its pixel centres at y = j + 0.5."""
    return np.frombuffer(fbo.read(viewport=(0, 0, w, h), components=4), np.uint8).reshape(h, w, 4)


def render(ctx, overlay, camera, w, h, rgba=None):
    tex, fbo = target(ctx, w, h, rgba)
    try:
        overlay.draw(fbo, camera, (w, h))
        return read(fbo, w, h)
    finally:
        fbo.release()
        tex.release()


# ---------------------------------------------------------------------------- options, data


def test_parse_overlays():
    assert ov.parse_overlays("lines,labels") == ("lines", "labels")
    assert ov.parse_overlays(" Grid , lines,grid") == ("grid", "lines")
    assert ov.parse_overlays("all") == ov.OVERLAYS
    assert ov.parse_overlays("") == () == ov.parse_overlays("none")
    with pytest.raises(ParameterError) as err:
        ov.parse_overlays("lines,stars")
    msg = str(err.value)
    assert "'stars'" in msg and "lines, labels, grid" in msg and "\n" not in msg
    with pytest.raises(ParameterError):
        ov.Overlays(None, ("grid", "nope"))
    with pytest.raises(ParameterError):
        ov.Overlays(None, ("grid",), line_width_px=0.0)
    with pytest.raises(ParameterError):
        ov.Overlays(None, ("grid",), colour=(2.0, 0.0, 0.0))


def test_data_file_and_licence():
    data = resources.files("skydome.data")
    text = data.joinpath("constellations.txt").read_text(encoding="utf-8")
    for needle in ("BSD-3-Clause", "Copyright (c) 2015, Olaf Frohn", "ofrohn/d3-celestial"):
        assert needle in text
    doc = json.loads(data.joinpath("constellations.json").read_text(encoding="utf-8"))
    assert doc["sha256"]["constellations.lines.json"] in text  # the same source file
    cons = ov.constellations()
    # The IAU's 88 constellations (Serpens in two parts: 89 entries).
    assert len({c.abbr for c in cons}) == 88 and len(cons) == 89
    # Betelgeuse is HIP 27989 and Bellatrix HIP 25336 (SIMBAD); Orion's figure joins them.
    orion = next(c for c in cons if c.abbr == "Ori")
    pair = {find_star("Betelgeuse").hip, find_star("Bellatrix").hip}
    assert pair == {27989, 25336}
    assert any(set(s) == pair for s in orion.segments)
    ends = [e for c in cons for s in c.segments for e in s]
    hips = [e for e in ends if isinstance(e, int)]
    assert all(catalog().index_of_hip(h) is not None for h in hips)
    assert len(hips) >= 0.99 * len(ends)


# ---------------------------------------------------------------------------- nothing drawn


def test_off_leaves_the_image_bit_identical(ctx, state):
    w, h = 360, 180
    rng = np.random.default_rng(3)
    image = rng.integers(0, 256, (h, w, 4), dtype=np.uint8)
    off = ov.Overlays(ctx, ())
    off.update(state)
    assert np.array_equal(render(ctx, off, EquirectCamera(), w, h, image), image)
    # Lines and labels need a place and a time: nothing in the abstract mode.
    abstract = ov.Overlays(ctx, ("lines", "labels"))
    abstract.update(abstract_state(20.0, 180.0))
    square = np.ascontiguousarray(image[:, :h])
    assert np.array_equal(render(ctx, abstract, FisheyeCamera(), h, h, square), square)
    # The grid: pixels away from its lines keep their value bit for bit, alpha everywhere.
    grid = ov.Overlays(ctx, ("grid",))
    grid.update(abstract_state(20.0, 180.0))
    out = render(ctx, grid, EquirectCamera(), w, h, image)
    assert np.array_equal(out[..., 3], image[..., 3])
    assert 0.5 < np.mean(np.all(out == image, axis=-1)) < 0.95
    for o in (off, abstract, grid):
        o.release()


# ---------------------------------------------------------------------------- grid


def _grid_image(ctx, camera, w, h):
    grid = ov.Overlays(ctx, ("grid",), colour=WHITE, line_width_px=2.0)
    grid.update(abstract_state(20.0, 180.0))
    img = render(ctx, grid, camera, w, h)[..., 1].astype(float)
    grid.release()
    return img


def test_grid_equirect_horizon_and_30_deg_circle(ctx):
    """Horizon: elevation 0 is the frame's middle (y = H/2); the 30-deg circle lies where
    render.projection puts altitude 30. The coverage is symmetric about a line's centre,
    so the coverage-weighted mean row is its centre; tolerance 0.05 px (8-bit steps)."""
    w, h = 720, 360
    img = _grid_image(ctx, EquirectCamera(), w, h)
    cols = [30 + 60 * k for k in range(12)]  # azimuth 15 + 30 k deg: between azimuth lines
    rows = np.arange(h) + 0.5

    def centre(y0):
        sel = np.abs(rows - y0) < 6
        prof = img[sel][:, cols].mean(axis=1)
        return float(np.sum(prof * rows[sel]) / np.sum(prof))

    assert abs(centre(h / 2) - h / 2) < 0.05
    _, y30, _ = EquirectCamera().project(frames.horizontal_to_enu(math.radians(30), 0.3), w, h)
    assert abs(centre(float(y30)) - float(y30)) < 0.05
    assert abs(float(y30) - (h / 2 + h / 6)) < 1e-9
    # The horizon is brighter than the other circles.
    assert img[h // 2, cols].mean() > 1.5 * img[int(y30), cols].mean()


def test_grid_fisheye_horizon_is_the_rim(ctx):
    """Fisheye: the horizon is the disk's rim (radius = half the side, drawn whole: the
    mapping is continued past the rim), the 30-deg circle at 60/90 of it (equidistant)."""
    n = 512
    img = _grid_image(ctx, FisheyeCamera(), n, n)
    yy, xx = np.mgrid[0:n, 0:n] + 0.5
    r = np.hypot(xx - n / 2, yy - n / 2)
    az = np.degrees(np.arctan2(-(xx - n / 2), yy - n / 2)) % 360
    between = np.abs((az - 15.0) % 30.0 - 15.0) > 10.0  # > 5 deg from every azimuth line
    between &= np.abs((az + 45.0) % 90.0 - 45.0) > 20.0  # and away from the N/E/S/W marks

    def mean_radius(r0):
        sel = between & (np.abs(r - r0) < 6)
        return float(np.sum(img[sel] * r[sel]) / np.sum(img[sel]))

    # Ring area grows with r: the weighted mean of a ring w px wide sits w^2 / (12 r) out
    # (0.003 px here); 8-bit steps and the finite-difference pixel scale: < 0.1 px.
    assert abs(mean_radius(n / 2) - n / 2) < 0.1
    x, y, _ = FisheyeCamera().project(frames.horizontal_to_enu(math.radians(30), 1.0), n, n)
    r30 = float(np.hypot(x - n / 2, y - n / 2))
    assert abs(r30 - n / 2 * 60 / 90) < 1e-9
    assert abs(mean_radius(r30) - r30) < 0.1
    # Outside the extended rim nothing is drawn.
    assert img[r > n / 2 + 5].max() == 0


# ---------------------------------------------------------------------------- lines


def _only(monkeypatch, *names):
    """Replace the packaged figures by the segments between the named stars."""
    rows = np.array([find_star(n).index for n in names])
    fig = ov._Figures(rows, np.zeros((0, 3)), np.array([[0, 1]]))
    monkeypatch.setattr(ov, "_figures", lambda: fig)


def _truth(names):
    """Apparent (refracted) ENU directions from Observer.sky: the astronomy's own chain."""
    sky = OBSERVER.sky(TIME, bodies=names)
    return np.array([np.asarray(sky[n].enu).reshape(3) for n in names])


def test_line_ends_are_the_stars_apparent_places(ctx, state, monkeypatch):
    """The pieces' ends (CPU) are the stars as Observer.sky places them (apparent,
    refracted, diurnal aberration): 0.05" (its gast and our gast agree to 1e-4")."""
    _only(monkeypatch, "Betelgeuse", "Bellatrix")
    lines = ov.Overlays(ctx, ("lines",))
    lines.update(state)
    p = lines._pieces.astype(float)
    truth = _truth(("Betelgeuse", "Bellatrix"))
    first, last = p[0, :3], p[-1, 3:]
    for got, want in ((first, truth[0]), (last, truth[1])):
        sep = math.atan2(np.linalg.norm(np.cross(got, want)), float(np.dot(got, want)))
        assert math.degrees(sep) * 3600 < 0.05
    # The pieces follow the great circle: no piece longer than SUBDIVISION_DEG.
    ang = np.degrees(np.arccos(np.clip(np.sum(p[:, :3] * p[:, 3:], -1), -1, 1)))
    assert ang.max() <= ov.SUBDIVISION_DEG + 1e-6 and len(p) >= 4
    lines.release()


def test_betelgeuse_bellatrix_ends_land_on_the_stars(ctx, state, monkeypatch):
    """In a perspective frame (great circles are straight lines) the drawn segment's ends
    lie on the stars' projected positions (render.projection of Observer.sky's places)
    within 0.5 px. The ends are measured from the image: the coverage-weighted centroid of
    a capsule is its midpoint, its principal axis its direction, and its area
    L w + pi w^2 / 4 gives its length L."""
    _only(monkeypatch, "Betelgeuse", "Bellatrix")
    truth = _truth(("Betelgeuse", "Bellatrix"))
    mid = truth.sum(0) / np.linalg.norm(truth.sum(0))
    alt, az = frames.enu_to_horizontal(mid)
    cam = PerspectiveCamera(fov_deg=15.0, yaw_deg=math.degrees(az), pitch_deg=math.degrees(alt))
    w, h, lw = 960, 640, 4.0
    lines = ov.Overlays(ctx, ("lines",), colour=WHITE, line_width_px=lw)
    lines.update(state)
    img = render(ctx, lines, cam, w, h)[..., 1].astype(float)
    lines.release()
    x, y, seen = cam.project(truth, w, h)
    assert seen.all()
    cov = img / (255.0 * ov.LINE_OPACITY)
    yy, xx = np.mgrid[0:h, 0:w] + 0.5
    total = cov.sum()
    cx, cy = (cov * xx).sum() / total, (cov * yy).sum() / total
    m = np.cov(np.stack([xx.ravel() - cx, yy.ravel() - cy]), aweights=cov.ravel())
    axis = np.linalg.eigh(m)[1][:, -1]
    length = (total - math.pi * lw**2 / 4) / lw
    ends = [np.array([cx, cy]) + s * 0.5 * length * axis for s in (1, -1)]
    stars = [np.array([x[0], y[0]]), np.array([x[1], y[1]])]
    err = min(
        max(np.linalg.norm(ends[0] - stars[0]), np.linalg.norm(ends[1] - stars[1])),
        max(np.linalg.norm(ends[0] - stars[1]), np.linalg.norm(ends[1] - stars[0])),
    )
    assert length > 300  # 7.5 deg at 64 px per deg
    assert err < 0.5


def test_equirect_seam_and_cube_edges(ctx, state):
    """A piece across azimuth 0 is drawn at both edges of the equirect frame and nowhere
    between; a piece across the cube's north/east edge on both faces, without a gap."""
    lines = ov.Overlays(ctx, ("lines",), colour=WHITE, line_width_px=2.0)
    lines.update(state)
    a = frames.horizontal_to_enu(math.radians(20.0), math.radians(-4.0))
    b = frames.horizontal_to_enu(math.radians(20.0), math.radians(4.0))
    lines._pieces = np.concatenate([a, b])[None].astype(np.float32)
    w, h = 720, 360
    img = render(ctx, lines, EquirectCamera(), w, h)[..., 1]
    lit = np.flatnonzero(img.max(axis=0))
    assert lit.min() == 0 and lit.max() == w - 1
    assert not np.any((lit > 12) & (lit < w - 12))  # 4 deg = 8 px each side, + width
    # Cube: az 40 -> 50 deg at altitude 10 crosses from the north face to the east face.
    a = frames.horizontal_to_enu(math.radians(10.0), math.radians(40.0))
    b = frames.horizontal_to_enu(math.radians(10.0), math.radians(50.0))
    lines._pieces = np.concatenate([a, b])[None].astype(np.float32)
    side = 128
    img = render(ctx, lines, CubemapCamera(), 6 * side, side)[..., 1]
    east_left, north_right = img[:, 0:2], img[:, 3 * side - 2 : 3 * side]
    assert east_left.max() > 0 and north_right.max() > 0
    # Continuous: the rows the line occupies at the edge agree on both faces.
    assert abs(np.argmax(east_left.max(1)) - np.argmax(north_right.max(1))) <= 1
    pa, pb = ov.split_at_cube_edges(a[None], b[None])
    assert len(pa) == 2 and np.all(ov._cube_face(pa) == ov._cube_face(pb))
    lines.release()


def test_behind_a_perspective_camera_nothing(ctx, state):
    lines = ov.Overlays(ctx, ("lines",), colour=WHITE)
    lines.update(state)
    a = frames.horizontal_to_enu(math.radians(20.0), math.radians(178.0))
    b = frames.horizontal_to_enu(math.radians(20.0), math.radians(182.0))
    lines._pieces = np.concatenate([a, b])[None].astype(np.float32)
    img = render(ctx, lines, PerspectiveCamera(fov_deg=120.0, yaw_deg=0.0), 160, 90)
    assert img.max() == 0
    lines.release()


def test_tiles_make_the_same_lines(ctx, state, monkeypatch):
    """The coverage target drawn in 100-px tiles gives the image of one 512-px tile."""
    lines = ov.Overlays(ctx, ("lines",), line_width_px=2.0)
    lines.update(state)
    whole = render(ctx, lines, FisheyeCamera(), 512, 512)
    monkeypatch.setattr(ov, "MAX_TILE", 100)
    tiled = render(ctx, lines, FisheyeCamera(), 512, 512)
    assert whole.max() > 0
    assert np.array_equal(whole, tiled)
    lines.release()


# ---------------------------------------------------------------------------- labels


def test_labels_beside_their_objects(ctx, state):
    """Betelgeuse's and Rigel's names start within a few px right of and above the stars;
    the planets' names beside them; no label below the horizon (equirect: the lower half)."""
    labels = ov.Overlays(ctx, ("labels",), colour=WHITE, font_px=14)
    labels.update(state)
    n = 768
    cam = FisheyeCamera()
    img = render(ctx, labels, cam, n, n)[..., 1]
    names = ("Betelgeuse", "Rigel")
    x, y, _ = cam.project(_truth(names), n, n)
    for name, xi, yi in zip(names, x, y, strict=True):
        bw, bh = labels._atlas.boxes[name][2:]
        # The box's lower-left corner is LABEL_GAP_PX + (1, -1) px from the star (rounded).
        x0, y0 = int(round(xi + ov.LABEL_GAP_PX + 1)), int(round(yi + ov.LABEL_GAP_PX - 1))
        box = img[y0 : y0 + bh, x0 : x0 + bw]
        assert (box > 128).sum() > 40, name  # the glyphs
        around = img[y0 - 12 : y0 + bh + 12, x0 - 12 : x0 + bw + 12]
        assert (around > 0).sum() == (box > 0).sum(), name  # nothing of it outside the box
    w, h = 1024, 512
    img = render(ctx, labels, EquirectCamera(), w, h)[..., 1]
    assert img[: h // 2].max() == 0  # every box lies above the horizon
    assert img[h // 2 :].max() > 0
    info = labels.info()
    assert info["labels"] >= 30
    # A planet: Jupiter is below the horizon at 20:00 UTC; at 05:00 UTC it is up.
    morning = state_at(OBSERVER, "2018-01-21T05:00Z")
    labels.update(morning)
    jup = np.asarray(OBSERVER.sky("2018-01-21T05:00Z", bodies=("jupiter",))["jupiter"].enu)
    assert jup.reshape(3)[2] > 0
    img = render(ctx, labels, cam, n, n)[..., 1]
    xj, yj, _ = cam.project(jup.reshape(1, 3), n, n)
    bw, bh = labels._atlas.boxes["Jupiter"][2:]
    x0, y0 = int(round(xj[0] + ov.LABEL_GAP_PX + 1)), int(round(yj[0] + ov.LABEL_GAP_PX - 1))
    # Mars is 5 deg away (their conjunction of 2018-01-07): Jupiter's name may have moved
    # up or down a line to make room (LABEL_SHIFTS).
    shifts = [math.floor(k * bh + 0.5) for k in ov.LABEL_SHIFTS]
    lit = [(img[y0 + dy : y0 + dy + bh, x0 : x0 + bw] > 128).sum() for dy in shifts]
    assert max(lit) > 30
    labels.release()


def test_atlas_outline_is_wider_than_the_glyphs():
    atlas = ov.build_atlas(["Sirius", "N"], 14)
    x, y, bw, bh = atlas.boxes["Sirius"]
    rows = atlas.image.shape[0]
    tile = atlas.image[rows - y - bh : rows - y, x : x + bw]
    fill, ring = tile[..., 0].astype(int), tile[..., 1].astype(int)
    assert np.all(ring >= fill) and (ring > 0).sum() > 1.5 * (fill > 0).sum()


def test_letters_the_font_lacks_become_their_base_letters():
    """Pillow's Aileron has no o-diaeresis: Bootes is written without it, not with a box."""
    font, _ = ov._font(14)
    assert ov._displayable("Boötes", font) in ("Boötes", "Bootes")
    missing = np.asarray(font.getmask("\uffff"))
    shown = ov._displayable("Boötes", font)
    assert all(not np.array_equal(np.asarray(font.getmask(c)), missing) for c in shown)
    assert ov._displayable("Sirius", font) == "Sirius"
