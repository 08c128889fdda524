"""The control panel in the window (Xvfb when there is no display): clicks on its widgets
act on the state, clamped; an atmosphere change rebuilds the tables in the background
while the old ones stay on screen."""

from __future__ import annotations

import time

import numpy as np
import pytest

from tests.conftest import TINY_TABLES
from tests.viewer_support import x_display  # noqa: F401  (fixture)

pytest.importorskip("glfw", reason="the viewer's window needs glfw")
pytest.importorskip("imgui_bundle", reason="the panel needs imgui-bundle")

W, H = 640, 480


@pytest.fixture()
def window(x_display):  # noqa: F811
    from skydome.viewer.app import ViewerWindow

    win = ViewerWindow(W, H, visible=False, panel=True)
    try:
        yield win
    finally:
        win.close()


def _scene(window, **fields):
    from skydome import Sky
    from skydome.viewer.controls import Controls
    from skydome.viewer.scene import ViewerScene, initial_state

    sky = Sky("Valletta", "2018-03-01T12:00Z", ctx=window.ctx, night=False, config=TINY_TABLES)
    window.panel.configure(
        atmosphere=sky.layer("atmosphere").params, config=TINY_TABLES, night=False
    )
    return ViewerScene(sky, Controls(initial_state(sky, **fields)))


def _click(name, *, at=0.5):
    """An on_frame script clicking the panel widget ``name`` at a fraction ``at`` of its
    width: hover, press, release on three frames after the panel's first layout."""

    def script(win, i):
        rect = win.panel.rects.get(name)
        if rect is None:
            return
        x0, y0, x1, y1 = rect
        x, y = x0 + at * (x1 - x0), 0.5 * (y0 + y1)
        import glfw

        if i == 2:
            win.on_cursor(x, y)
        elif i == 3:
            win.on_mouse_button(glfw.MOUSE_BUTTON_LEFT, glfw.PRESS)
        elif i == 4:
            win.on_mouse_button(glfw.MOUSE_BUTTON_LEFT, glfw.RELEASE)

    return script


def test_clicking_play_starts_the_time_and_does_not_turn_the_camera(window):
    scene = _scene(window, yaw_deg=123.0, speed=60.0)
    jd0 = scene.controls.state.jd_utc
    window.run(scene, frames=8, on_frame=_click("play"))
    s = scene.controls.state
    assert s.playing
    assert s.jd_utc > jd0
    assert s.yaw_deg == pytest.approx(123.0, abs=1e-12)  # the press went to the panel
    scene.release()


def test_a_click_at_the_end_of_a_slider_holds_the_value_in_range(window):
    scene = _scene(window, fov_deg=60.0)
    window.run(scene, frames=8, on_frame=_click("fov", at=0.999))
    fov = scene.controls.state.fov_deg
    assert 160.0 < fov <= 170.0  # the slider's end: its range's top, never beyond
    scene.release()


def test_an_atmosphere_change_rebuilds_in_the_background(window):
    """The new tables come from a child process; until they are ready the old sky draws
    every frame; then the new one (Mie g 0.9) is swapped in and draws finite frames."""
    from skydome.viewer.rebuild import clamp_knobs

    scene = _scene(window)
    old = scene.base
    panel = window.panel
    panel.knobs = clamp_knobs(panel.knobs, mie_g=0.9)
    panel._start_rebuild()
    assert panel.rebuild.status.running
    frames_before = 0
    deadline = time.monotonic() + 120.0
    while scene.base is old and time.monotonic() < deadline:
        window.run(scene, frames=1)
        frames_before += 1
    assert scene.base is not old, panel.rebuild.status
    assert frames_before >= 2  # the window kept drawing the old sky meanwhile
    assert scene.base.layer("atmosphere").params.mie_g == pytest.approx(0.9)
    assert old.graph._targets == {}  # the old graph was released
    window.run(scene, frames=2)
    assert np.isfinite(scene.render(64, 48).data).all()
    scene.release()
