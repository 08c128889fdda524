"""The notebook widget, driven without a browser: events through ``handle_event``, frames
from ``get_frame``; and ``Sky._repr_png_``."""

from __future__ import annotations

import io

import numpy as np
import pytest

pytest.importorskip("jupyter_rfb", reason="the widget needs jupyter-rfb")


@pytest.fixture(scope="module")
def sky():
    from skydome import Sky

    return Sky("Valletta", "2018-03-01T12:00Z", night=False)


def _widget(sky, **fields):
    from skydome.viewer.controls import Controls
    from skydome.viewer.scene import initial_state
    from skydome.viewer.widget import SkyWidget

    return SkyWidget(sky, Controls(initial_state(sky, **fields)))


def test_events_move_the_camera_as_in_the_window(sky):
    w = _widget(sky, yaw_deg=100.0, pitch_deg=10.0, fov_deg=90.0)
    w.handle_event({"type": "resize", "width": 320, "height": 180, "ratio": 2.0})
    assert w.size_px == (640, 360)
    w.handle_event({"type": "pointer_down", "x": 10, "y": 100, "button": 1})
    w.handle_event({"type": "pointer_move", "x": 42, "y": 84})
    w.handle_event({"type": "pointer_up", "x": 42, "y": 84, "button": 1})
    k = 90.0 / 320.0  # deg per CSS pixel over the 320 px wide widget
    assert w.controls.state.yaw_deg == pytest.approx(100.0 + 32 * k, abs=1e-9)
    assert w.controls.state.pitch_deg == pytest.approx(10.0 + 16 * k, abs=1e-9)
    w.handle_event({"event_type": "wheel", "dx": 0, "dy": -100})  # old-style name: one notch in
    assert w.controls.state.fov_deg == pytest.approx(81.0, abs=1e-9)
    w.handle_event({"type": "key_down", "key": " "})
    assert w.controls.state.playing
    w.handle_event({"type": "key_down", "key": "c"})
    assert w.controls.state.projection == "fisheye"


def test_get_frame_is_the_render_of_the_state(sky):
    w = _widget(sky, yaw_deg=180.0, pitch_deg=20.0, exposure_mode="ev", ev100=14.0)
    w.handle_event({"type": "resize", "width": 160, "height": 90, "ratio": 1.0})
    image = w.get_frame()
    assert image.shape == (90, 160, 3) and image.dtype == np.uint8
    s = w.controls.state
    direct = sky.render(s.camera(), 160, 90, exposure=14.0, tonemap="filmic").image
    assert np.array_equal(image, direct)
    assert image.std() > 2.0
    w.handle_event({"type": "key_down", "key": "ArrowUp"})  # held: the widget keeps drawing
    w.get_frame()
    w.get_frame()
    assert w.controls.state.pitch_deg > 20.0
    assert np.isfinite(w.scene.render(32, 18).data).all()


def test_repr_png_is_a_png_image(sky):
    from PIL import Image

    data = sky._repr_png_()
    img = Image.open(io.BytesIO(data))
    assert img.format == "PNG" and img.size == (512, 256)


def test_a_slowly_playing_time_keeps_the_drawn_state_within_half_a_pixel(sky):
    """While the time plays, a step that moves the Sun and the Moon by less than half a
    pixel (here 0.5 * 90 deg / 1280 px = 0.035 deg; one second moves them ~0.004 deg)
    keeps the drawn state (no re-aim); a minute (~0.25 deg) draws the new one; paused,
    the exact time is drawn."""
    from skydome.viewer.controls import Controls
    from skydome.viewer.scene import ViewerScene, initial_state

    scene = ViewerScene(sky, Controls(initial_state(sky, playing=True, speed=1.0)))
    scene.view_width_px = 1280
    first = scene.sky()
    jd = scene.controls.state.jd_utc
    scene.controls.set(jd_utc=jd + 1.0 / 86400.0)
    assert scene.sky() is first
    scene.controls.set(jd_utc=jd + 60.0 / 86400.0)
    moved = scene.sky()
    assert moved is not first
    assert float(moved.state.time.jd_utc) == pytest.approx(jd + 60.0 / 86400.0, abs=1e-9)
    scene.controls.set(playing=False, jd_utc=jd + 61.0 / 86400.0)
    assert float(scene.sky().state.time.jd_utc) == pytest.approx(jd + 61.0 / 86400.0, abs=1e-9)
