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
    window.panel.configure(sky.description)
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


def _clicks(*targets, log=None):
    """An on_frame script clicking panel widgets one after the other, through the window's
    glfw callbacks (and so imgui's input path): each target, a rects name or (name, at),
    is hovered, pressed and released on three frames once the panel has laid it out in the
    same place twice (the layout moves when e.g. the status line gains the EV; a combo's
    items appear the frame after its box is clicked). ``log`` collects the names clicked,
    in order."""
    queue = [t if isinstance(t, tuple) else (t, 0.5) for t in targets]
    step = {"i": 0, "phase": 0, "rect": None}

    def script(win, frame):
        import glfw

        if step["i"] >= len(queue):
            return
        name, at = queue[step["i"]]
        rect = win.panel.rects.get(name)
        if rect is None or rect != step["rect"]:  # not laid out yet, or moved: hover again
            step["rect"], step["phase"] = rect, 0
            return
        x0, y0, x1, y1 = rect
        phase = step["phase"]
        if phase == 0:
            win.on_cursor(x0 + at * (x1 - x0), 0.5 * (y0 + y1))
        elif phase == 1:
            win.on_mouse_button(glfw.MOUSE_BUTTON_LEFT, glfw.PRESS)
        else:
            win.on_mouse_button(glfw.MOUSE_BUTTON_LEFT, glfw.RELEASE)
            if log is not None:
                log.append(name)
            step["i"] += 1
            step["rect"] = None
        step["phase"] = (phase + 1) % 3

    return script


def _run_until_clicked(window, scene, targets, *, frames=60):
    log: list[str] = []
    window.run(scene, frames=frames, on_frame=_clicks(*targets, log=log))
    assert log == [t if isinstance(t, str) else t[0] for t in targets], log


def test_the_projection_combo_picks_a_projection(window):
    scene = _scene(window, yaw_deg=123.0)
    _run_until_clicked(window, scene, ["projection", "projection:fisheye"])
    s = scene.controls.state
    assert s.projection == "fisheye"
    assert s.yaw_deg == pytest.approx(123.0, abs=1e-12)  # the clicks went to the panel
    scene.release()


def test_the_exposure_mode_and_the_ev_slider(window):
    """The "ev" radio button sets the EV mode; a click at the middle of the EV100 slider
    (range -20..40) sets 10 EV, to within the slider's pixel (60 EV over ~200 px: 0.3 EV;
    0.5 allowed). The shown frame follows (last_ev100 is the EV applied)."""
    scene = _scene(window)
    _run_until_clicked(
        window, scene, ["header:Time", "header:Display", "exposure:ev", ("ev100", 0.5)]
    )
    s = scene.controls.state
    assert s.exposure_mode == "ev"
    assert s.ev100 == pytest.approx(10.0, abs=0.5)
    assert scene.last_ev100 == pytest.approx(s.ev100, abs=1e-9)
    scene.release()


def test_the_sunrise_button_jumps_to_the_next_sunrise(window):
    """From Valletta at noon, "sunrise" moves the time to the next morning, where the Sun's
    centre is at the standard geometric altitude of a sunrise, -0.8333 deg (34' refraction +
    16' semidiameter: Explanatory Supplement to the Astronomical Almanac, 1992, sec. 9.331),
    to 0.01 deg (the Sun climbs ~0.2 deg/min there: a root found to ~3 s)."""
    import math

    scene = _scene(window)
    jd0 = scene.controls.state.jd_utc
    _run_until_clicked(window, scene, ["jump_sunrise"])
    jd = scene.controls.state.jd_utc
    assert 0.6 < jd - jd0 < 0.8  # 12:00Z to the next morning's ~05:30Z (UTC+1 in Malta)
    sun = scene.sky().state.sun
    assert math.degrees(math.asin(sun.direction_true[2])) == pytest.approx(-0.8333, abs=0.01)
    assert sun.direction_true[0] > 0.5  # rising in the east
    # and the camera turned to it: its azimuth, the horizon in view (pitch 2 deg)
    state = scene.controls.state
    assert state.projection == "perspective"
    assert abs((state.yaw_deg - sun.azimuth_deg + 180.0) % 360.0 - 180.0) < 0.01
    assert state.pitch_deg == pytest.approx(2.0)
    scene.release()


def test_the_preset_combo_rebuilds_the_atmosphere(window):
    """Opening the Atmosphere section and picking "hazy" starts the background rebuild; the
    hazy tables are swapped in when ready (the preset's AOD, 0.272, not earth's 0.1)."""
    from skydome.atmosphere import preset

    scene = _scene(window)
    old = scene.base
    _run_until_clicked(window, scene, ["header:Time", "header:Atmosphere", "preset", "preset:hazy"])
    panel = window.panel
    assert panel.knobs.preset == "hazy"
    deadline = time.monotonic() + 120.0
    while scene.base is old and time.monotonic() < deadline:
        window.run(scene, frames=1)
    assert scene.base is not old, panel.rebuild.status
    params = scene.base.layer("atmosphere").params
    assert params.aod_550 == pytest.approx(preset("hazy").aod_550)
    assert params.aod_550 > 2.0 * preset("earth").aod_550  # hazier than the start's air
    window.run(scene, frames=2)
    scene.release()


def test_the_weather_combo_builds_a_foggy_sky(window):
    """Opening the Weather section and picking "fog" builds the sky with the fog preset (its
    air's tables in the background first); the foggy sky draws finite frames, and its
    visibility is the preset's 200 m."""
    scene = _scene(window)
    old = scene.base
    _run_until_clicked(window, scene, ["header:Time", "header:Weather", "weather", "weather:fog"])
    deadline = time.monotonic() + 120.0
    while scene.base is old and time.monotonic() < deadline:
        window.run(scene, frames=1)
    assert scene.base is not old, (window.panel.rebuild.status, window.panel.message)
    description = scene.base.description
    assert description.weather is not None and description.weather.preset == "fog"
    assert description.visibility_km == pytest.approx(0.2, rel=1e-6)
    assert window.panel.message == "weather: fog"
    window.run(scene, frames=2)
    scene.release()


@pytest.fixture()
def wide_window(x_display):  # noqa: F811
    """A 1280 x 720 window: at a mocked scale of 2, 640 x 360 units, room beside the panel."""
    from skydome.viewer.app import ViewerWindow

    win = ViewerWindow(1280, 720, visible=False, panel=True)
    try:
        yield win
    finally:
        win.close()


def test_hidpi_pointer_in_window_units_and_screenshots_in_pixels(
    wide_window, monkeypatch, tmp_path
):
    """A HiDPI screen, mocked: the window reports half the framebuffer's size (scale 2).
    The pointer's coordinates are window units: a click at a panel rectangle hits its
    widget, and a drag turns by fov / (window width in units) per unit. The panel is drawn
    at twice its size in framebuffer pixels (ImGui's framebuffer scale), and a screenshot
    has the framebuffer's pixels, equal to the headless render at that size."""
    import glfw
    from PIL import Image

    from skydome.viewer.screenshot import read_screen

    fw, fh = wide_window.framebuffer_size()
    monkeypatch.setattr(glfw, "get_window_size", lambda _w: (fw // 2, fh // 2))
    assert wide_window.window_size() == (fw // 2, fh // 2)
    scene = _scene(wide_window, yaw_deg=100.0, pitch_deg=10.0, exposure_mode="ev", ev100=14.0)
    _run_until_clicked(wide_window, scene, ["play"])
    assert scene.controls.state.playing
    scene.controls.set(playing=False)

    def drag(win, i):
        if i == 0:  # right of the panel (340 units wide, at x 10): ImGui lets go of the
            win.on_cursor(400.0, 150.0)  # mouse at its next frame
        elif i == 1:
            win.on_mouse_button(glfw.MOUSE_BUTTON_LEFT, glfw.PRESS)
            win.on_cursor(432.0, 134.0)
            win.on_mouse_button(glfw.MOUSE_BUTTON_LEFT, glfw.RELEASE)

    panel = wide_window.panel.rects["panel"]
    assert panel[2] < 400.0  # the drag starts outside the panel
    s0 = scene.controls.state
    wide_window.run(scene, frames=2, on_frame=drag)
    s = scene.controls.state
    k = s0.fov_deg / (fw // 2)  # deg per window unit
    assert s.yaw_deg == pytest.approx(s0.yaw_deg + 32 * k, abs=1e-9)
    assert s.pitch_deg == pytest.approx(s0.pitch_deg + 16 * k, abs=1e-9)

    # The panel over the frame, read before the swap: a point inside the panel only when
    # it is drawn at scale 2 is the panel's dark background there.
    wide_window.make_current()
    wide_window.panel.build(scene, wide_window.timer, 0.016)
    screen = wide_window.ctx.screen
    screen.use()
    scene.draw(screen, (fw, fh))
    sky_only = read_screen(screen, (fw, fh)).astype(int)
    wide_window.panel.render((fw, fh))
    with_panel = read_screen(screen, (fw, fh)).astype(int)
    x0, y0, x1, y1 = panel
    ux, uy = x1 - 10.0, y1 - 10.0  # near the panel's lower right corner, in window units
    assert ux > fw / 4 and uy > fh / 4  # beyond the panel's extent at scale 1
    px, py = int(2 * ux), int(2 * uy)
    assert with_panel[py, px].max() < 60, with_panel[py, px]  # ImGui's dark window
    assert sky_only[py, px].sum() > with_panel[py, px].sum() + 60  # the sky was brighter
    assert np.abs(with_panel[fh - 5, fw - 5] - sky_only[fh - 5, fw - 5]).max() == 0

    png = tmp_path / "hidpi.png"
    wide_window.run(scene, frames=1, screenshot=[png])
    shown = np.asarray(Image.open(png).convert("RGB")).astype(int)
    assert shown.shape == (fh, fw, 3)
    from skydome import Sky
    from skydome.gpu import shared_context

    ctx = shared_context()
    ctx.__enter__()
    try:
        from skydome.astro.time import Time

        st = scene.controls.state  # the time ran while "play" was on
        when = Time.from_utc(st.jd_utc)
        headless = Sky(scene.observer(), when, night=False, config=TINY_TABLES, ctx=ctx)
        frame = headless.render(st.camera(), fw, fh, exposure=14.0, tonemap=st.tonemap)
        headless.graph.release()
    finally:
        ctx.__exit__(None, None, None)
        wide_window.make_current()
    assert np.abs(shown - frame.image.astype(int)).max() <= 1
    scene.release()


def test_a_wide_window_docks_the_panel_beside_the_picture(x_display, tmp_path, monkeypatch):  # noqa: F811
    """At 1024 x 600 the panel is a column at the right edge, the full height, and the
    picture is the rest: the screen's left 1024 - 340 px are the sky, never the panel, and
    a screenshot is that picture; "with the panel" saves the whole window instead."""
    from PIL import Image

    from skydome.viewer.app import ViewerWindow
    from skydome.viewer.panel import PANEL_WIDTH

    monkeypatch.chdir(tmp_path)
    win = ViewerWindow(1024, 600, visible=False, panel=True)
    try:
        scene = _scene(win)
        shots = [tmp_path / "view.png"]
        win.run(scene, frames=4, screenshot=shots)
        x0, y0, x1, y1 = win.panel.rects["panel"]
        assert (x0, y0) == (1024 - PANEL_WIDTH, 0.0) and (x1, y1) == (1024.0, 600.0)
        assert Image.open(shots[0]).size == (1024 - int(PANEL_WIDTH), 600)
        # what the "with the panel" box and the screenshot button set (both at the foot of
        # the "Frame times" section, below the fold of a 600 px column)
        win.panel.screenshot_with_panel = True
        win.panel.screenshot_requested = "skydome-test"
        win.run(scene, frames=2)
        saved = sorted(tmp_path.glob("skydome-*.png"))
        assert len(saved) == 1 and Image.open(saved[0]).size == (1024, 600)
        scene.release()
    finally:
        win.close()


def test_the_clouds_and_the_bortle_class_from_the_panel(window):
    """The Weather section's "clouds" combo builds the sky with a cloud preset, and its
    Bortle slider (0-9, a click at its middle: 4 or 5) with that light pollution."""
    scene = _scene(window)
    old = scene.base
    _run_until_clicked(window, scene, ["header:Time", "header:Weather", "clouds", "clouds:fair"])
    assert scene.base is not old, window.panel.message
    clouds = scene.base.description.clouds
    assert clouds is not None and clouds.preset == "fair"
    _run_until_clicked(window, scene, [("bortle", 0.5)])
    assert scene.base.description.light_pollution in (4, 5), window.panel.message
    window.run(scene, frames=2)
    scene.release()


def test_the_time_in_the_places_clock_and_the_glare_from_the_panel(window):
    """Valletta's 12:00 UTC shows as its local 13:00 (CET, UTC+1); a local time typed in is
    read in the place's zone; the Display section's glare combo sets the scene's glare."""
    import glfw

    scene = _scene(window)
    window.run(scene, frames=2)
    assert window.panel.time_text == "2018-03-01T13:00:00"
    jd0 = scene.controls.state.jd_utc
    window.panel.time_text = "2018-03-01T15:30"

    def enter(win, i):  # Enter in the time field, focused by a click
        if i == 2:
            rect = win.panel.rects["time_text"]
            win.on_cursor(0.5 * (rect[0] + rect[2]), 0.5 * (rect[1] + rect[3]))
        elif i == 3:
            win.on_mouse_button(glfw.MOUSE_BUTTON_LEFT, glfw.PRESS)
        elif i == 4:
            win.on_mouse_button(glfw.MOUSE_BUTTON_LEFT, glfw.RELEASE)
        elif i == 6:
            win.on_key(glfw.KEY_ENTER, glfw.PRESS)
        elif i == 7:
            win.on_key(glfw.KEY_ENTER, glfw.RELEASE)

    window.run(scene, frames=10, on_frame=enter)
    assert scene.controls.state.jd_utc - jd0 == pytest.approx(2.5 / 24.0, abs=1e-6)  # 14:30Z
    _run_until_clicked(window, scene, ["header:Time", "header:Display", "glare", "glare:off"])
    assert scene.glare == "off"
    scene.release()
