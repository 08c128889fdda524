"""The notebook widget: a Sky you can look around in, in Jupyter (``jupyter_rfb``).

>>> from skydome import Sky
>>> from skydome.viewer.widget import SkyWidget
>>> SkyWidget(Sky("Valletta", "2018-03-01T19:00Z"))      # doctest: +SKIP

The same camera controls as the window (``viewer.controls``): drag to look, the wheel to
zoom, W/A/S/D to walk, Q/E to climb, Space to play the time, C for the next projection,
1/2 to look at the Sun/Moon. Frames are rendered headless (``Sky.render``) at the widget's
size times its pixel ratio and sent as images; while keys are held or the time plays the
widget keeps asking for frames.
"""

from __future__ import annotations

import time

import numpy as np

from skydome.viewer import require

require("jupyter_rfb", "jupyter-rfb")

from jupyter_rfb import RemoteFrameBuffer  # noqa: E402

from skydome.viewer.controls import Controls  # noqa: E402
from skydome.viewer.scene import ViewerScene  # noqa: E402

#: Browser key names (KeyboardEvent.key) -> ``Controls`` key names.
BROWSER_KEYS = {
    "ArrowLeft": "left", "ArrowRight": "right", "ArrowUp": "up", "ArrowDown": "down",
    "PageUp": "page_up", "PageDown": "page_down", " ": "space", "+": "plus", "=": "plus",
    "-": "minus",
}  # fmt: skip
#: Largest frame side the widget renders (pixels).
MAX_FRAME_SIDE = 2048
#: Pixels one wheel notch is in the browser's ``dy`` (a line of 100 px).
WHEEL_PIXELS_PER_NOTCH = 100.0


class SkyWidget(RemoteFrameBuffer):
    """A Jupyter widget showing ``sky`` through the viewer's controls.

    Args:
        sky: the Sky to show (drawn in its own context: the headless one by default).
        controls: the view's state (default: :func:`skydome.viewer.scene.initial_state`).
        **kwargs: RemoteFrameBuffer traits (``css_width="640px"``, ``css_height``...).
    """

    _event_compatibility = 3  # accept the old and the new event names

    def __init__(self, sky, controls: Controls | None = None, **kwargs):
        kwargs.setdefault("css_width", "640px")
        kwargs.setdefault("css_height", "360px")
        super().__init__(**kwargs)
        self.scene = ViewerScene(sky, controls)
        self.size_px = (640, 360)
        self._width_css = 640.0
        self._last = None

    @property
    def controls(self) -> Controls:
        return self.scene.controls

    def handle_event(self, event: dict) -> None:
        """Map a jupyter_rfb event (pointer, wheel, key, resize) onto the controls, then
        ask for a frame."""
        kind = event.get("type") or event.get("event_type")
        c = self.controls
        if kind == "resize":
            ratio = float(event.get("ratio", event.get("pixel_ratio", 1.0)) or 1.0)
            w, h = float(event.get("width", 0)), float(event.get("height", 0))
            if w > 0 and h > 0:
                self._width_css = w
                self.size_px = (
                    int(min(max(round(w * ratio), 1), MAX_FRAME_SIDE)),
                    int(min(max(round(h * ratio), 1), MAX_FRAME_SIDE)),
                )
        elif kind == "pointer_down" and event.get("button", 1) == 1:
            c.press(float(event.get("x", 0.0)), float(event.get("y", 0.0)))
        elif kind == "pointer_move":
            c.move(float(event.get("x", 0.0)), float(event.get("y", 0.0)), self._width_css)
        elif kind == "pointer_up":
            c.release()
        elif kind == "wheel":
            c.scroll(-float(event.get("dy", 0.0)) / WHEEL_PIXELS_PER_NOTCH)
        elif kind in ("key_down", "key_up"):
            key = str(event.get("key", ""))
            name = BROWSER_KEYS.get(key, key.lower())
            c.key(name, kind == "key_down")
        else:
            return
        self.request_draw()

    def get_frame(self) -> np.ndarray:
        """The frame for the current state: uint8 (h, w, 3), rendered headless."""
        now = time.perf_counter()
        dt = 0.0 if self._last is None else now - self._last
        self._last = now
        c = self.controls
        c.tick(dt, eye_altitude_m=self.scene.altitude_m())
        w, h = self.size_px
        frame = self.scene.render(w, h)
        if c.held or c.state.playing:
            self.request_draw()  # keep moving while a key is held or the time runs
        else:
            self._last = None  # the next interaction starts a fresh time step
        return frame.image
