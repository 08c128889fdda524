"""Dynamic resolution in the viewer (issue 27): a moving view drawn at a reduced size chosen
to hold a frame budget and upsampled; a still view refined to the full-resolution frame.

The controller's law is plain arithmetic (no GL); the frames are drawn by a ViewerScene in
the shared headless context into an offscreen framebuffer (the window's path without the
window: ``ViewerScene.draw`` is what ``ViewerWindow.frame`` calls)."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from skydome import Sky
from skydome.errors import ParameterError
from skydome.viewer.dynamic_resolution import (
    MAX_SCALE,
    MIN_SCALE,
    SCALE_STEP,
    ResolutionController,
    check_frame_budget,
    quantise_scale,
    reduced_size,
)
from tests.viewer_support import x_display  # noqa: F401  (fixture)

W, H = 320, 180


# ---------------------------------------------------------------------- the law (no GL)


def _on_grid(scale: float) -> bool:
    return abs(scale / SCALE_STEP - round(scale / SCALE_STEP)) < 1e-12


def test_a_slow_frame_lowers_the_scale_a_fast_one_raises_it_quantised_and_bounded():
    c = ResolutionController(33.0)
    assert c.scale == MAX_SCALE
    c.observe(4 * 33.0, 1.0)  # 4x over budget at full size: s* = 0.5, half-way: 0.75
    assert c.scale == 0.75 and _on_grid(c.scale)
    for _ in range(20):
        c.observe(4 * 33.0, c.scale)  # always 4x over: down to the floor, not below
    assert c.scale == MIN_SCALE
    for _ in range(40):
        c.observe(1.0, c.scale)  # far under budget: up to full size, not above
    assert c.scale == MAX_SCALE
    for t in np.linspace(1.0, 500.0, 97):
        s = c.observe(float(t), 0.5)
        assert MIN_SCALE <= s <= MAX_SCALE and _on_grid(s)


def test_time_proportional_to_pixels_settles_on_the_budget_without_oscillating():
    # A frame of t = 20 + 200 s^2 ms (fixed costs + pixels): the budget of 33 ms is held
    # at s = sqrt(13 / 200) = 0.255 -> the scale settles at a step and stays there.
    c = ResolutionController(33.0)
    history = []
    s = c.scale
    for _ in range(60):
        s = c.observe(20.0 + 200.0 * s * s, s)
        history.append(s)
    assert len(set(history[-30:])) == 1
    assert history[-1] == 0.25
    # a budget that 0.5 holds: 20 + 200 * 0.25 = 70 ms
    c = ResolutionController(70.0)
    s = c.scale
    for _ in range(60):
        s = c.observe(20.0 + 200.0 * s * s, s)
    assert s == 0.5


def test_budget_zero_is_off_and_bad_budgets_are_refused():
    c = ResolutionController(0.0)
    assert c.observe(1000.0, 1.0) == MAX_SCALE
    assert quantise_scale(0.31) == 0.25 and quantise_scale(0.95) == 1.0
    assert quantise_scale(0.01) == MIN_SCALE and quantise_scale(7.0) == MAX_SCALE
    assert reduced_size((1280, 720), 0.25) == (320, 180)
    for bad in (-1.0, float("nan"), 1e9, "x"):
        with pytest.raises(ParameterError, match="frame budget"):
            check_frame_budget(bad)


def test_the_command_line_refuses_a_negative_budget_in_one_line():
    r = subprocess.run(
        [sys.executable, "-m", "skydome", "view", "--place", "Paris", "--frame-budget", "-5"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert r.returncode == 2
    assert "--frame-budget" in r.stderr and len(r.stderr.strip().splitlines()) == 1


# ---------------------------------------------------------------------- frames (GL)


def _scene(ctx, place, when, budget_ms, **fields):
    from skydome import Sky
    from skydome.viewer.controls import Controls
    from skydome.viewer.scene import ViewerScene, initial_state

    sky = Sky(place, when, ctx=ctx)
    scene = ViewerScene(sky, Controls(initial_state(sky, **fields)))
    scene.frame_budget_ms = budget_ms
    return scene


def _screen(ctx):
    tex = ctx.texture((W, H), 4)
    return tex, ctx.framebuffer(color_attachments=[tex])


def _pixels(fbo) -> np.ndarray:
    return np.frombuffer(fbo.read(viewport=(0, 0, W, H), components=3), np.uint8).copy()


def _float(texture) -> np.ndarray:
    w, h = texture.size
    return np.frombuffer(texture.read(), np.float32).reshape(h, w, 4).copy()  # GL rows


def _luminance(rgb) -> np.ndarray:
    return 0.2126 * rgb[..., 0] + 0.7152 * rgb[..., 1] + 0.0722 * rgb[..., 2]


def _solid_angles(camera, w: int, h: int) -> np.ndarray:
    """The solid angle (sr) of each pixel (GL rows) of a w x h frame of ``camera``."""
    x, y = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    d, _ = camera.directions(x, y, w, h)
    return camera.solid_angle(d, w, h)


def _moving(scene, fbo, frames: int, step_deg: float = 0.5, frame_ms: float = 400.0):
    """Turn the camera ``frames`` times, each frame reported ``frame_ms`` long (over the
    budget: the scale goes down); returns the scales drawn."""
    scales = []
    for _ in range(frames):
        scene.controls.set(yaw_deg=scene.controls.state.yaw_deg + step_deg)
        scene.draw(fbo, (W, H), dt_s=frame_ms / 1e3)
        scales.append(scene.render_scale)
    return scales


DUSK = ("Paris", "2024-07-05T20:30")


@pytest.mark.gl
def test_a_moving_view_is_reduced_and_a_still_one_refines_to_todays_frame_exactly(ctx):
    """Moving (a new view every frame, each over budget): the first frame at full size,
    then reduced, the kept float frame of the reduced size; when the view stops, the next
    frame is drawn at full size and the frame after it (kept) is bit-identical to the
    still frame of a scene without dynamic resolution at the same view."""
    from skydome.viewer.dynamic_resolution import reduced_size as rs

    fields = dict(yaw_deg=300.0, pitch_deg=3.0, fov_deg=90.0)
    scene = _scene(ctx, *DUSK, 33.0, **fields)
    _, fbo = _screen(ctx)
    scene.draw(fbo, (W, H))
    scales = _moving(scene, fbo, 4)
    assert scales[0] < 1.0 and scales[-1] <= scales[0]
    assert all(_on_grid(s) for s in scales)
    cache = scene._cache
    assert cache.reduced_size == rs((W, H), scales[-1])
    assert cache.texture.size == cache.reduced_size
    scene.draw(fbo, (W, H), dt_s=0.4)  # the view stopped: the refine
    assert scene.redrew and scene.render_scale == 1.0 and cache.reduced_size is None
    assert cache.texture.size == (W, H)
    scene.draw(fbo, (W, H), dt_s=0.4)
    assert not scene.redrew
    refined = _pixels(fbo)
    today = _scene(ctx, *DUSK, 0.0, **{**fields, "yaw_deg": scene.controls.state.yaw_deg})
    _, fbo0 = _screen(ctx)
    today.draw(fbo0, (W, H))
    today.draw(fbo0, (W, H))
    assert np.array_equal(refined, _pixels(fbo0))
    today.release()
    scene.release()


@pytest.mark.gl
def test_budget_zero_draws_every_moving_frame_as_before(ctx):
    """With the budget 0, a moving view is drawn at full size every frame, and each frame
    is bit-identical to the first frame of a fresh scene at that view (today's path: a new
    view drawn and tone-mapped straight to the screen)."""
    fields = dict(yaw_deg=300.0, pitch_deg=3.0, fov_deg=90.0)
    scene = _scene(ctx, *DUSK, 0.0, **fields)
    _, fbo = _screen(ctx)
    scene.draw(fbo, (W, H))
    assert _moving(scene, fbo, 3) == [1.0, 1.0, 1.0]
    assert scene._cache.reduced_size is None
    moved = _pixels(fbo)
    fresh = _scene(ctx, *DUSK, 0.0, **{**fields, "yaw_deg": scene.controls.state.yaw_deg})
    _, fbo0 = _screen(ctx)
    fresh.draw(fbo0, (W, H))
    assert np.array_equal(moved, _pixels(fbo0))
    fresh.release()
    scene.release()


@pytest.mark.gl
def test_a_reduced_frame_keeps_the_mean_luminance_and_the_horizon(ctx):
    """Looking east at dusk (the Sun behind: its disk, drawn per pixel and not conserved,
    would hold the scale up, ``disk_floor``), the reduced float frame's solid-angle-weighted
    mean luminance is within 2 % of the full frame's (the same radiance field sampled at
    1/16 of the pixels: a smooth sky's mean moves by its curvature over a pixel, and the
    ground's edge by up to half a reduced row of 45), and the upsampled screen keeps the
    horizon: the rows just above and below it differ as much as at full resolution
    (bilinear across the edge would spread the step over 4 rows at scale 0.25). Measured:
    the mean 0.6 % above the full frame's."""
    fields = dict(yaw_deg=120.0, pitch_deg=3.0, fov_deg=90.0)
    scene = _scene(ctx, *DUSK, 33.0, **fields)
    _, fbo = _screen(ctx)
    scene.resolution.level = scene.resolution.scale = 0.25
    scene.draw(fbo, (W, H))
    _moving(scene, fbo, 1, step_deg=0.01, frame_ms=1000.0)
    assert scene.render_scale == 0.25
    camera = scene.controls.state.camera()
    reduced = _float(scene._cache.texture)
    rw, rh = scene._cache.reduced_size
    shown_reduced = _pixels(fbo).reshape(H, W, 3)[::-1].astype(int)
    scene.draw(fbo, (W, H))  # refine
    full = _float(scene._cache.texture)
    shown_full = _pixels(fbo).reshape(H, W, 3)[::-1].astype(int)

    sun = np.asarray(scene.sky().state.sun.direction, float)

    def mean_y(img, w, h):
        x, y = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
        d, _ = camera.directions(x, y, w, h)
        omega = camera.solid_angle(d, w, h) * ((d @ sun) < np.cos(np.radians(1.5)))
        return float((_luminance(img) * omega).sum() / omega.sum())

    full_y, reduced_y = mean_y(full, W, H), mean_y(reduced, rw, rh)
    assert np.isfinite(reduced).all()
    assert abs(reduced_y / full_y - 1.0) < 0.02, (reduced_y, full_y)
    # the horizon's row in the middle column (top-first rows), and the step across it
    col = shown_full[:, W // 2].sum(-1)
    y = int(np.argmax(np.abs(np.diff(col))))
    step_full = abs(col[y + 1] - col[y])
    red_col = shown_reduced[:, W // 2].sum(-1)
    step_reduced = np.abs(np.diff(red_col[y - 2 : y + 3])).max()
    assert step_full > 30  # a visible edge at dusk
    assert step_reduced > 0.75 * step_full, (step_reduced, step_full)
    scene.release()


@pytest.mark.gl
def test_every_bright_star_keeps_its_light_in_a_reduced_frame(ctx):
    """A moonless night at Paranal at scale 0.5, the stars seen through the air alone (the
    glows off: a dark sky around them): the light of all the stars in view (luminance times
    pixel solid angle, summed over the frame, the air's faint glow included) is within 3 % of
    the full frame's, and each of the 4 brightest stars with no other peak within 10 px
    keeps its light (in a box of +-6 full, +-4 reduced pixels, less the box edge's median)
    within 10 %. The PSF is normalised over
    its quad in each frame's own pixels (celestial.point_sources), so a star's flux is the
    same at any size; what moves it: light falling off the frame's edges (3 sigma is 1.5
    full pixels more at half size), the air's transmittance at slightly other pixel
    centres, a neighbour's wing in a star's box (measured: stars 0.4-4.9 %; a fainter
    star's box at half size often holds a neighbour: not a test of the star)."""
    fields = dict(yaw_deg=180.0, pitch_deg=45.0, fov_deg=90.0,
                  layers_off=frozenset({"milky_way", "zodiacal_light", "airglow", "moon",
                                        "planets"}))  # fmt: skip
    scene = _scene(ctx, "Paranal", "2024-07-05T03:00Z", 33.0, **fields)
    _, fbo = _screen(ctx)
    scene.resolution.level = scene.resolution.scale = 0.5
    scene.draw(fbo, (W, H))
    _moving(scene, fbo, 1, step_deg=0.0001, frame_ms=4 * 33.0)  # s* = 0.5 from 1
    assert scene.render_scale == 0.5
    camera = scene.controls.state.camera()
    reduced = _luminance(_float(scene._cache.texture))
    rw, rh = scene._cache.reduced_size
    scene.draw(fbo, (W, H))
    full = _luminance(_float(scene._cache.texture))
    om_full, om_red = _solid_angles(camera, W, H), _solid_angles(camera, rw, rh)
    total = (reduced * om_red).sum() / (full * om_full).sum()
    assert abs(total - 1.0) < 0.03, total
    sky_full = np.median(full)
    local_max = np.lib.stride_tricks.sliding_window_view(np.pad(full, 4, mode="edge"), (9, 9)).max(
        axis=(-2, -1)
    )
    ys, xs = np.nonzero((full == local_max) & (full > 3.0 * sky_full))
    stars = [
        (full[y, x], y, x) for y, x in zip(ys, xs, strict=True)
        if 10 <= y < H - 10 and 10 <= x < W - 10
        and not any((abs(y - v) < 10 and abs(x - u) < 10) and (v, u) != (y, x)
                    for v, u in zip(ys, xs, strict=True))
    ]  # fmt: skip
    stars.sort(reverse=True)
    assert len(stars) >= 4, len(stars)

    def flux(img, omega, cy: float, cx: float, r: int) -> float:
        y0, x0 = int(round(cy)), int(round(cx))
        box = img[y0 - r : y0 + r + 1, x0 - r : x0 + r + 1]
        ring = np.concatenate([box[0], box[-1], box[1:-1, 0], box[1:-1, -1]])
        o = omega[y0 - r : y0 + r + 1, x0 - r : x0 + r + 1]
        return float(((box - np.median(ring)) * o).sum())

    ratios = []
    for _, y, x in stars[:4]:
        # the same point of the sky in the reduced frame's pixels
        cy, cx = (y + 0.5) * rh / H - 0.5, (x + 0.5) * rw / W - 0.5
        ratios.append(flux(reduced, om_red, cy, cx, 4) / flux(full, om_full, y, x, 6))
    assert np.all(np.abs(np.array(ratios) - 1.0) < 0.10), ratios
    scene.release()


def test_the_horizon_band_holds_the_ground_edge_and_only_it():
    """The guided pass's rectangle: a level perspective view's band is a few rows around
    the horizon's row (where camera.project puts the dipped horizon), none when the view
    looks up past it, all columns of an equirect frame, none for a fisheye."""
    from skydome.core.cameras import EquirectCamera, FisheyeCamera, PerspectiveCamera
    from skydome.viewer.dynamic_resolution import horizon_band

    cam = PerspectiveCamera(fov_deg=90.0, yaw_deg=300.0, pitch_deg=3.0)
    x, y, w, h = horizon_band(cam, (1280, 720), 0.0008, 8.0)
    d = np.array([[np.sin(np.radians(300.0)), np.cos(np.radians(300.0)), -0.0008]])
    _, row, _ = cam.project(d / np.linalg.norm(d), 1280, 720)
    assert (x, w) == (0, 1280) and y <= row[0] - 8 and row[0] + 8 <= y + h and h <= 24
    assert horizon_band(PerspectiveCamera(fov_deg=90.0, pitch_deg=60.0), (1280, 720),
                        0.0008, 8.0) is None  # fmt: skip
    assert horizon_band(EquirectCamera(), (1280, 640), 0.0008, 8.0)[2] == 1280
    assert horizon_band(FisheyeCamera(), (640, 640), 0.0008, 8.0) is None


@pytest.fixture()
def window(x_display):  # noqa: F811
    from skydome.viewer.app import ViewerWindow

    win = ViewerWindow(W, H, visible=False, panel=False)
    try:
        yield win
    finally:
        win.close()


def test_the_window_draws_a_turning_view_reduced_and_its_screenshot_in_full(
    window,
    tmp_path,
    x_display,  # noqa: F811
):
    """In the window (the user's path): turning every frame with a budget no frame meets,
    the frames after the first are drawn at a reduced scale; the screenshot's frame is
    drawn at full resolution and equals, bit for bit, the screenshot of a scene without
    dynamic resolution at that view. ``skydome view --turn --frames`` prints the scale."""
    from PIL import Image

    fields = dict(yaw_deg=120.0, pitch_deg=3.0, fov_deg=90.0)
    scene = _scene(window.ctx, *DUSK, 1.0, **fields)
    scales = []

    def turn(_win, _i):
        scene.controls.set(yaw_deg=scene.controls.state.yaw_deg + 0.5)
        scales.append(scene.render_scale)

    timer = window.run(scene, frames=6, screenshot=[tmp_path / "a.png"], on_frame=turn)
    scales.append(scene.render_scale)
    assert timer.redraws == 6
    assert scales[1] == 1.0 and min(scales) == MIN_SCALE and scales[-1] == 1.0
    today = _scene(window.ctx, *DUSK, 0.0, **{**fields, "yaw_deg": scene.controls.state.yaw_deg})
    window.run(today, frames=1, screenshot=[tmp_path / "b.png"])
    a, b = (np.asarray(Image.open(tmp_path / n)) for n in ("a.png", "b.png"))
    assert np.array_equal(a, b)
    today.release()
    scene.release()
    env = {**os.environ, "DISPLAY": x_display}
    r = subprocess.run(
        [sys.executable, "-m", "skydome", "view", "--place", "Paris", "--time",
         "2024-07-05T20:30", "--size", f"{W}x{H}", "--no-panel", "--no-night", "--frames",
         "6", "--turn", "1", "--frame-budget", "1"],
        capture_output=True, text=True, timeout=300, env=env,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert "6 of 6 frames drawn anew" in r.stdout, r.stdout
    scale = float(r.stdout.split("render scale ")[1].split()[0])
    assert scale < 1.0 and "(median, frame budget 1 ms)" in r.stdout, r.stdout


@pytest.mark.gl
def test_the_sun_and_moon_disks_keep_their_light_in_a_reduced_frame(ctx):
    """A turning view at scale 0.5 looking at the Sun 7 deg up (Valletta, 2018-03-09 06:00
    UTC), then at the full Moon 50 deg up at night (2018-03-01 21:00 UTC: the difference of
    two frames holds the Moon's light, not a bright sky's rounding), the window 320 x 180 and
    90 deg (a reduced pixel of 0.72 deg, twice the smallest reduced pixel of a 1280 x 720
    window at MIN_SCALE): the disk's light in the reduced float frame (the luminance it adds times each
    pixel's solid angle, against the same frame without the disk's layer) is within 2 % of
    the refined full frame's. The Sun's radius is 0.37 of a reduced pixel: each pixel
    averages 32 x 32 points (``core.cameras.disk_samples``); one point per pixel, as before,
    held up to 2.3 times the light or none. Measured: the Sun -0.6 %, the Moon +0.3 %."""
    for body, when in (("sun", "2018-03-09T06:00Z"), ("moon", "2018-03-01T21:00Z")):
        with Sky("Valletta", when, night=False, ctx=ctx) as sky:
            light = getattr(sky.state, body)
        fields = dict(yaw_deg=light.azimuth_deg, pitch_deg=light.elevation_deg, fov_deg=90.0)
        energies = []
        for off in (frozenset(), frozenset({body})):
            scene = _scene(ctx, "Valletta", when, 33.0, layers_off=off, **fields)
            _, fbo = _screen(ctx)
            scene.resolution.level = scene.resolution.scale = 0.5
            scene.draw(fbo, (W, H))
            _moving(scene, fbo, 1, step_deg=0.0001, frame_ms=4 * 33.0)
            assert scene.render_scale == 0.5
            camera = scene.controls.state.camera()
            rw, rh = scene._cache.reduced_size
            reduced = _luminance(_float(scene._cache.texture)) * _solid_angles(camera, rw, rh)
            scene.draw(fbo, (W, H))  # refine
            full = _luminance(_float(scene._cache.texture)) * _solid_angles(camera, W, H)
            energies.append((reduced.sum(), full.sum()))
            scene.release()
        (red_on, full_on), (red_off, full_off) = energies
        ratio = (red_on - red_off) / (full_on - full_off)
        assert abs(ratio - 1.0) < 0.02, (body, ratio)


def test_the_panel_sets_the_frame_budget_and_shows_the_scale(x_display):  # noqa: F811
    """The Display section's "frame budget" slider: a click at its middle sets 50 ms (range
    0-100, to within the slider's pixel); its left end turns dynamic resolution off. The
    speed line shows the render scale while it is below 1."""
    pytest.importorskip("imgui_bundle", reason="the panel needs imgui-bundle")
    from skydome.viewer.app import ViewerWindow
    from skydome.viewer.panel import redraw_line
    from tests.test_viewer_panel import _run_until_clicked

    win = ViewerWindow(640, 1000, visible=False, panel=True)  # tall: the slider in view
    try:
        scene = _scene(win.ctx, "Valletta", "2018-03-01T12:00Z", 33.0, yaw_deg=0.0)
        win.panel.configure(scene.base.description)
        _run_until_clicked(win, scene, ["header:Time", "header:Display", ("frame_budget", 0.5)])
        assert scene.frame_budget_ms == pytest.approx(50.0, abs=1.0)
        _run_until_clicked(win, scene, [("frame_budget", 0.001)])
        assert scene.frame_budget_ms == 0.0
        scene.release()
    finally:
        win.close()

    class Timer:
        def median_redraw_ms(self):
            return 40.0

    assert redraw_line(Timer(), True, 0.375) == "25.0 fps drawn (40 ms per redraw), scale 0.375"
    assert redraw_line(Timer(), True, 1.0) == "25.0 fps drawn (40 ms per redraw)"
    assert redraw_line(Timer(), False, 0.375) == "still (a redraw takes 40 ms)"
