"""The viewer's window under X (Xvfb when there is no display): what it shows equals the
headless render of the same state, and scripted input moves the camera and the time as
stated."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from PIL import Image

from tests.viewer_support import x_display  # noqa: F401  (fixture)

pytest.importorskip("glfw", reason="the viewer's window needs glfw (pip install glfw)")

W, H = 320, 180


@pytest.fixture()
def window(x_display):  # noqa: F811
    from skydome.viewer.app import ViewerWindow

    win = ViewerWindow(W, H, visible=False, panel=False)
    try:
        yield win
    finally:
        win.close()  # collects the test's GL objects while the window's context is current


def _headless(place, when, *, night=True):
    """A Sky in the shared headless context (made current for it: moderngl draws in the
    current context, and the window's was current)."""
    from skydome import Sky
    from skydome.gpu import shared_context

    ctx = shared_context()
    ctx.__enter__()
    return Sky(place, when, night=night, ctx=ctx), ctx


def _scene(window, place, when, *, night=True, **fields):
    from skydome import Sky
    from skydome.viewer.controls import Controls
    from skydome.viewer.scene import ViewerScene, initial_state

    sky = Sky(place, when, ctx=window.ctx, night=night)
    return ViewerScene(sky, Controls(initial_state(sky, **fields)))


@pytest.mark.parametrize(
    "place, when, night, fields",
    [
        # noon, a fixed EV, the filmic curve
        ("Valletta", "2018-03-01T12:00Z", False, dict(yaw_deg=170.0, pitch_deg=20.0,
                                                      fov_deg=80.0, exposure_mode="ev",
                                                      ev100=14.0)),
        # the full Moon at night with every night layer, auto exposure, Reinhard
        ("Valletta", "2018-03-01T23:00Z", True, dict(fov_deg=60.0, tonemap="reinhard")),
        # dusk, all-sky fisheye, auto exposure, compensation
        ("Paranal", "2024-07-05T00:00Z", True, dict(projection="fisheye",
                                                    compensation_ev=1.0)),
    ],
)  # fmt: skip
def test_screenshot_equals_the_headless_render(window, tmp_path, place, when, night, fields):
    """The PNG from the window (drawn by Sky.draw into the window's framebuffer) equals
    Sky.render(...).image of the same camera, time and exposure in the headless context to
    within 1 code value (the window's pass leaves the 8-bit rounding to the driver; the
    headless one snaps it in the shader)."""
    scene = _scene(window, place, when, night=night, **fields)
    png = tmp_path / "shot.png"
    window.run(scene, frames=2, screenshot=[png])
    shown = np.asarray(Image.open(png).convert("RGB")).astype(int)
    assert shown.shape == (H, W, 3)
    s = scene.controls.state
    exposure, comp = scene.exposure()
    headless, ctx = _headless(place, when, night=night)
    try:
        frame = headless.render(
            s.camera(), W, H, exposure=exposure, compensation_ev=comp, tonemap=s.tonemap
        )
        headless.graph.release()
    finally:
        ctx.__exit__(None, None, None)
        window.make_current()
    diff = np.abs(shown - frame.image.astype(int))
    assert diff.max() <= 1, f"max difference {diff.max()} code values"
    assert shown.std() > 2.0  # not a flat (black or blank) image
    scene.release()


def test_exr_screenshot_is_the_frame_in_cd_m2(window, tmp_path):
    """An EXR screenshot holds the same state's frame in cd/m^2: its tone map at the EV in
    use is the PNG to within 1 code value, and a daylit sky is thousands of cd/m^2."""
    from skydome.display import ev100_to_scale, gpu_tonemap
    from skydome.io.exr import read_exr

    scene = _scene(window, "Valletta", "2018-03-01T12:00Z", night=False, exposure_mode="ev",
                   ev100=14.5, yaw_deg=180.0, pitch_deg=30.0)  # fmt: skip
    scene.glare = "off"  # the image alone is glared (the Sun is in view); the EXR never is
    png, exr = tmp_path / "s.png", tmp_path / "s.exr"
    window.run(scene, frames=1, screenshot=[png, exr])
    data, _ = read_exr(exr)
    assert data.shape[:2] == (H, W) and np.isfinite(data).all()
    y = float(np.median(data[: H // 2, :, 1]))
    assert 1e3 < y < 3e4, y  # the daytime sky 30 deg up: a few thousand cd/m^2
    from skydome.gpu import shared_context

    ctx = shared_context()
    ctx.__enter__()  # the headless context current for the tone map (see _headless)
    try:
        image = gpu_tonemap(data, "filmic", ev100_to_scale(14.5), ctx=ctx)
    finally:
        ctx.__exit__(None, None, None)
        window.make_current()
    shown = np.asarray(Image.open(png).convert("RGB")).astype(int)
    assert np.abs(shown - image.astype(int)).max() <= 1
    scene.release()


def test_scripted_input_moves_the_camera_and_the_time(window):
    """Pointer drags turn by fov / width per pixel, the wheel zooms by 0.9 a notch, Space
    starts the time at its speed, E climbs at exp(2 t); every frame stays finite."""
    import glfw

    scene = _scene(window, "Valletta", "2018-03-01T12:00Z", night=False, yaw_deg=100.0,
                   pitch_deg=10.0, fov_deg=90.0, speed=3600.0)  # fmt: skip
    c = scene.controls
    marks: dict = {}

    def script(win, i):
        marks[i] = time.perf_counter()  # before this frame's dt is taken (after the input)
        if i == 1:  # drag 64 px right and 32 px up
            win.on_cursor(100.0, 100.0)
            win.on_mouse_button(glfw.MOUSE_BUTTON_LEFT, glfw.PRESS)
            win.on_cursor(164.0, 68.0)
            win.on_mouse_button(glfw.MOUSE_BUTTON_LEFT, glfw.RELEASE)
            win.on_cursor(10.0, 10.0)  # a move without the button: no turn
        elif i == 2:
            win.on_scroll(0.0, 2.0)
        elif i == 3:
            marks["jd0"] = c.state.jd_utc
            win.on_key(glfw.KEY_SPACE, glfw.PRESS)
            win.on_key(glfw.KEY_SPACE, glfw.RELEASE)
        elif i == 6:
            marks["jd1"] = c.state.jd_utc
            win.on_key(glfw.KEY_SPACE, glfw.PRESS)
            marks["alt0"] = scene.altitude_m()
            win.on_key(glfw.KEY_E, glfw.PRESS)
        elif i == 9:
            win.on_key(glfw.KEY_E, glfw.RELEASE)
            marks["alt1"] = scene.altitude_m()

    window.run(scene, frames=10, on_frame=script)
    s = c.state
    k = 90.0 / W  # deg per pixel at fov 90 over a W-pixel-wide window
    assert s.yaw_deg == pytest.approx(100.0 + 64 * k, abs=1e-9)
    assert s.pitch_deg == pytest.approx(10.0 + 32 * k, abs=1e-9)
    assert s.fov_deg == pytest.approx(90.0 * 0.81, abs=1e-9)
    # The time ran at 3600 s/s in the ticks of frames 3, 4 and 5: their dt sum lies between
    # the wall time of frames 3..5 alone and that from the input of frame 2 to that of 6.
    ran_s = (marks["jd1"] - marks["jd0"]) * 86400.0
    assert 3600.0 * (marks[5] - marks[3]) * 0.999 <= ran_s <= 3600.0 * (marks[6] - marks[2]) * 1.001
    assert not s.playing
    # Climbing in the ticks of frames 6, 7 and 8: (alt + 10 m) grows as exp(2 dt).
    grow = (marks["alt1"] + 10.0) / (marks["alt0"] + 10.0)
    lo, hi = math.exp(2.0 * (marks[8] - marks[6])), math.exp(2.0 * (marks[9] - marks[5]))
    assert lo * 0.999 <= grow <= hi * 1.001
    frame = scene.render(W // 2, H // 2)
    assert np.isfinite(frame.data).all()
    scene.release()


def test_a_resize_keeps_one_set_of_targets(window):
    """After the window's size changes, the frame graph keeps the targets of the new size
    only (a window that resizes does not pile up GPU memory)."""
    scene = _scene(window, "Valletta", "2018-03-01T12:00Z", night=False)
    window.run(scene, frames=1)
    window.glfw.set_window_size(window.window, W // 2, H // 2)
    for _ in range(20):  # the X server applies the size asynchronously
        window.glfw.poll_events()
        if window.framebuffer_size() == (W // 2, H // 2):
            break
        time.sleep(0.05)
    assert window.framebuffer_size() == (W // 2, H // 2)
    window.run(scene, frames=1)
    sizes = {k for k in scene.base.graph._targets if k[0] != "smooth"}
    assert sizes == {(W // 2, H // 2)}
    scene.release()


def test_a_failing_context_stops_with_a_clear_message(window):
    """A GL error during the loop (here the flag a read of the default framebuffer's
    absent COLOR_ATTACHMENT0 sets, as a failing driver would) stops the viewer with one
    GLError naming the context; a moderngl error from a pass becomes one too."""
    from skydome.errors import GLError

    scene = _scene(window, "Valletta", "2018-03-01T12:00Z", night=False)

    def flag(win, i):
        if i == 1:
            win.ctx.screen.read(viewport=(0, 0, 4, 4))  # sets GL_INVALID_OPERATION

    with pytest.raises(GLError, match="OpenGL context failed .GL_INVALID_OPERATION"):
        window.run(scene, frames=3, on_frame=flag)

    def fail(win, i):
        win.ctx.program(vertex_shader="not GLSL")  # moderngl.Error: a compile error

    with pytest.raises(GLError, match="OpenGL context failed"):
        window.run(scene, frames=2, on_frame=fail)
    scene.release()


def test_a_still_view_is_kept_and_a_display_change_reruns_only_the_post_passes(window, tmp_path):
    """While nothing moves, frames are the kept image (no layer draws: the graph's
    generation stays put) and equal the first; a new EV reruns the tone map alone (the
    same generation) and the screen then equals the headless render at that EV to within 1
    code value; a turn of the camera draws the layers again."""
    scene = _scene(window, "Valletta", "2018-03-01T12:00Z", night=False, yaw_deg=170.0,
                   pitch_deg=20.0, exposure_mode="ev", ev100=14.0)  # fmt: skip
    graph = scene.base.graph

    def shot(name):
        png = tmp_path / name
        window.run(scene, frames=1, screenshot=[png])
        return np.asarray(Image.open(png).convert("RGB")).astype(int)

    first = shot("a.png")
    g = graph.generation
    window.run(scene, frames=3)
    again = shot("b.png")
    assert graph.generation == g  # no tile drawn for four frames
    assert np.array_equal(again, first)
    scene.controls.set(ev100=13.0)  # one stop brighter
    brighter = shot("c.png")
    assert graph.generation == g  # the float frame kept; the post passes ran
    assert brighter.mean() > first.mean() + 10.0
    headless, ctx = _headless("Valletta", "2018-03-01T12:00Z", night=False)
    try:
        s = scene.controls.state
        frame = headless.render(s.camera(), W, H, exposure=13.0, tonemap=s.tonemap)
        headless.graph.release()
    finally:
        ctx.__exit__(None, None, None)
        window.make_current()
    assert np.abs(brighter - frame.image.astype(int)).max() <= 1
    scene.controls.set(yaw_deg=171.0)
    shot("d.png")
    assert graph.generation > g  # a new view: the layers drawn again
    scene.controls.set(ev100=13.5)
    reference = shot("e.png")
    scene.controls.set(ev100=13.0)
    shot("f.png")
    g = graph.generation
    from skydome.core.cameras import EquirectCamera

    scene.base.render(EquirectCamera(), W, H)  # another view into the targets of this size
    assert graph.generation > g
    scene.controls.set(ev100=13.5)
    assert np.array_equal(shot("g.png"), reference)  # drawn again, not the equirect's
    g = graph.generation
    scene.invalidate()  # e.g. after a script changed a layer's parameters
    assert np.array_equal(shot("h.png"), reference)
    assert graph.generation > g
    scene.release()
