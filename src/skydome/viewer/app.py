"""The viewer's window: glfw, a moderngl context on it, the main loop and its frame timer.

::

    window = ViewerWindow(1280, 720)                   # the window and its GL context
    sky = Sky("Valletta", "2018-03-01T19:00Z", ctx=window.ctx)
    window.run(ViewerScene(sky))                        # until closed

``run(frames=N, screenshot=[...])`` draws N frames, saves the last one and returns the
timer (``skydome view --frames N --screenshot FILE``). Input reaches the scene's
``Controls`` through the glfw callbacks (``on_key``, ``on_mouse_button``, ``on_cursor``,
``on_scroll``), which the panel sees first: what the panel uses (a click on a slider,
typing in a field) does not move the camera.
"""

from __future__ import annotations

import time

from skydome.errors import GLError, ParameterError
from skydome.viewer import require
from skydome.viewer.frame_timer import FrameTimer

#: glfw key codes -> ``Controls`` key names (filled on first use: glfw is imported lazily).
_KEYS: dict[int, str] = {}
#: The largest window side (pixels): one tile of the frame graph (render.base.TILE_SIZE).
MAX_WINDOW_SIDE = 2048


def _key_names(glfw) -> dict[int, str]:
    if not _KEYS:
        for letter in "wasdqec":
            _KEYS[getattr(glfw, f"KEY_{letter.upper()}")] = letter
        _KEYS.update(
            {
                glfw.KEY_PAGE_UP: "page_up",
                glfw.KEY_PAGE_DOWN: "page_down",
                glfw.KEY_LEFT: "left",
                glfw.KEY_RIGHT: "right",
                glfw.KEY_UP: "up",
                glfw.KEY_DOWN: "down",
                glfw.KEY_EQUAL: "plus",
                glfw.KEY_KP_ADD: "plus",
                glfw.KEY_MINUS: "minus",
                glfw.KEY_KP_SUBTRACT: "minus",
                glfw.KEY_SPACE: "space",
                glfw.KEY_1: "1",
                glfw.KEY_2: "2",
            }
        )
    return _KEYS


def _use_egl() -> bool:
    """Whether the window's context should come from EGL rather than GLX: on Linux, where
    the headless contexts (``skydome.gpu``) are EGL ones, one process may hold both, and
    EGL and GLX contexts in one process do not mix (glXMakeCurrent fails with BadAccess
    while an EGL context is current). ``SKYDOME_VIEWER_EGL=0`` turns it off."""
    import os
    import sys

    return sys.platform.startswith("linux") and os.environ.get("SKYDOME_VIEWER_EGL", "1") != "0"


def _restore_headless() -> None:
    """Make this thread's shared headless context (``skydome.gpu.shared_context``), if one
    was made, current again: with the window gone no context is current, and code that
    draws headless afterwards (a script, the rest of a test session) expects its own."""
    from skydome.gpu import context as gpu_context

    ctx = getattr(gpu_context._shared, "ctx", None)
    if ctx is not None:
        ctx.__enter__()


def one_line(exc: BaseException) -> str:
    """An exception's message on one line."""
    return " ".join(str(exc).split()) or type(exc).__name__


class ViewerWindow:
    """A glfw window with an OpenGL 3.3 core context wrapped by moderngl.

    Args:
        width, height: the window's size in screen coordinates (on a HiDPI screen the
            framebuffer has more pixels; frames are drawn at the framebuffer's size).
        title: the window title.
        vsync: swap at the display's refresh rate (off: as fast as frames are drawn).
        visible: show the window (hidden windows still draw: for tests).
        panel: show the control panel (needs imgui-bundle).
        egl: make the context with EGL (default on Linux: see :func:`_use_egl`).
    Raises:
        ParameterError: glfw (or imgui-bundle for the panel) is not installed.
        GLError: no window or no OpenGL 3.3 context (no display, no driver).
    """

    def __init__(
        self,
        width: int = 1280,
        height: int = 720,
        *,
        title: str = "skydome",
        vsync: bool = False,
        visible: bool = True,
        panel: bool = True,
        egl: bool | None = None,
    ):
        glfw = require("glfw", "glfw")
        if egl is None:
            egl = _use_egl()
        self.glfw = glfw
        for name, v in (("width", width), ("height", height)):
            if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= MAX_WINDOW_SIDE:
                raise ParameterError(
                    f"window {name} {v} must be an integer from 1 to {MAX_WINDOW_SIDE}"
                )
        glfw.set_error_callback(None)
        if not glfw.init():
            raise GLError(
                "cannot open a window: glfw found no display (set DISPLAY, or run under "
                "xvfb-run for a virtual one)"
            )
        glfw.window_hint(glfw.CONTEXT_VERSION_MAJOR, 3)
        glfw.window_hint(glfw.CONTEXT_VERSION_MINOR, 3)
        glfw.window_hint(glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE)
        glfw.window_hint(glfw.OPENGL_FORWARD_COMPAT, True)
        glfw.window_hint(glfw.VISIBLE, bool(visible))
        glfw.window_hint(glfw.SCALE_TO_MONITOR, True)
        if egl:
            glfw.window_hint(glfw.CONTEXT_CREATION_API, glfw.EGL_CONTEXT_API)
        window = glfw.create_window(width, height, title, None, None)
        if not window:
            glfw.terminate()
            raise GLError(
                "cannot open an OpenGL 3.3 core window (the display has no such visual or "
                "driver; with Mesa: apt-get install libgl1-mesa-dri)"
            )
        self.window = window
        glfw.make_context_current(window)
        from skydome.gpu.context import wrap_context

        try:
            self.ctx = wrap_context(330)
        except GLError as exc:
            glfw.destroy_window(window)
            glfw.terminate()
            raise GLError(f"the window's OpenGL context: {exc}") from None
        self.vsync = bool(vsync)
        glfw.swap_interval(1 if self.vsync else 0)
        self.panel = None
        if panel:
            from skydome.viewer.panel import Panel

            self.panel = Panel(self)
        self.scene = None
        self.timer = FrameTimer(self.ctx)
        self._size: tuple[int, int] | None = None
        self._cursor = (0.0, 0.0)
        glfw.set_key_callback(window, lambda w, k, sc, action, mods: self.on_key(k, action))
        glfw.set_char_callback(window, lambda w, c: self.on_char(c))
        glfw.set_mouse_button_callback(
            window, lambda w, b, action, m: self.on_mouse_button(b, action)
        )
        glfw.set_cursor_pos_callback(window, lambda w, x, y: self.on_cursor(x, y))
        glfw.set_scroll_callback(window, lambda w, dx, dy: self.on_scroll(dx, dy))

    # ------------------------------------------------------------------ sizes

    def framebuffer_size(self) -> tuple[int, int]:
        """The framebuffer's size in pixels (HiDPI: more than the window's)."""
        return tuple(self.glfw.get_framebuffer_size(self.window))

    def window_size(self) -> tuple[int, int]:
        """The window's size in screen coordinates (the pointer's units)."""
        return tuple(self.glfw.get_window_size(self.window))

    def make_current(self) -> None:
        """Make the window's GL context current in this thread (moderngl draws in whichever
        context is current: a headless one made meanwhile, e.g. by a Sky without ctx=,
        would otherwise receive the window's draws). Unconditional: glfw does not see a
        context made current behind its back."""
        self.glfw.make_context_current(self.window)

    def set_vsync(self, on: bool) -> None:
        self.vsync = bool(on)
        self.glfw.swap_interval(1 if self.vsync else 0)

    # ------------------------------------------------------------------ input

    def _controls(self):
        return None if self.scene is None else self.scene.controls

    def on_key(self, key: int, action: int) -> None:
        """A glfw key event (``glfw.PRESS``, ``REPEAT`` or ``RELEASE``)."""
        glfw = self.glfw
        if self.panel is not None:
            self.panel.on_key(key, action)
            if self.panel.wants_keyboard() and action != glfw.RELEASE:
                return
        controls = self._controls()
        name = _key_names(glfw).get(key)
        if key == glfw.KEY_ESCAPE and action == glfw.PRESS:
            glfw.set_window_should_close(self.window, True)
        if controls is not None and name is not None and action != glfw.REPEAT:
            controls.key(name, action == glfw.PRESS)

    def on_char(self, codepoint: int) -> None:
        if self.panel is not None:
            self.panel.on_char(codepoint)

    def on_mouse_button(self, button: int, action: int) -> None:
        """A glfw mouse button event; the left button drags the view."""
        glfw = self.glfw
        if self.panel is not None:
            self.panel.on_mouse_button(button, action)
        controls = self._controls()
        if controls is None or button != glfw.MOUSE_BUTTON_LEFT:
            return
        if action == glfw.PRESS:
            if self.panel is not None and self.panel.wants_mouse():
                return
            controls.press(*self._cursor)
        else:
            controls.release()

    def on_cursor(self, x: float, y: float) -> None:
        """The pointer moved to (x, y) in screen coordinates."""
        self._cursor = (float(x), float(y))
        if self.panel is not None:
            self.panel.on_cursor(x, y)
        controls = self._controls()
        if controls is not None:
            controls.move(x, y, self.window_size()[0])

    def on_scroll(self, dx: float, dy: float) -> None:
        """Wheel: zoom (unless over the panel)."""
        if self.panel is not None:
            self.panel.on_scroll(dx, dy)
            if self.panel.wants_mouse():
                return
        controls = self._controls()
        if controls is not None:
            controls.scroll(dy)

    # ------------------------------------------------------------------ the loop

    def frame(self, dt_s: float, *, screenshot=None):
        """Draw one frame (input already polled): the sky, then the panel; returns the
        screen's pixels before the panel when ``screenshot`` is true."""
        scene, timer = self.scene, self.timer
        self.make_current()
        size = self.framebuffer_size()
        if size != self._size:
            scene.base.graph.release_targets(keep=size)
            self._size = size
        if self.panel is not None:
            with timer.cpu("panel"):
                self.panel.build(scene, timer, dt_s)
        with timer.cpu("input"):
            scene.controls.tick(dt_s, eye_altitude_m=scene.altitude_m())
            if self.panel is not None:
                self.panel.poll_rebuild(scene)
        if scene.controls.state.vsync != self.vsync:
            self.set_vsync(scene.controls.state.vsync)
        screen = self.ctx.screen
        screen.use()
        window_size = size
        if self.panel is not None:
            # the picture beside a docked panel (its left part: GL's origin is the corner)
            size = (self.panel.picture_width(size[0], self.window_size()[0]), size[1])
            if size != window_size:
                screen.viewport = (0, 0, *window_size)
                screen.clear(0.0, 0.0, 0.0, 1.0)
        screen.viewport = (0, 0, *size)
        if screenshot or (self.panel is not None and self.panel.screenshot_requested):
            scene.full_resolution_next = True  # a screenshot at full resolution
        with timer.cpu("sky"):
            scene.draw(screen, size, dt_s)
        pixels = None
        asked = self.panel is not None and self.panel.screenshot_requested
        with_panel = asked and self.panel.screenshot_with_panel
        if screenshot or (asked and not with_panel):
            from skydome.viewer.screenshot import read_screen

            pixels = read_screen(screen, size)
        if self.panel is not None:
            with timer.cpu("panel"), timer.section("panel"):
                self.panel.render(window_size)
        if with_panel:
            from skydome.viewer.screenshot import read_screen

            self._panel_screenshot(read_screen(screen, window_size))
        elif asked:
            self._panel_screenshot(pixels)
        with timer.cpu("swap"):
            self.glfw.swap_buffers(self.window)
        return pixels

    def _panel_screenshot(self, pixels) -> None:
        """Save the panel's screenshot (PNG of the screen, EXR of the frame in cd/m^2) in
        the working directory; the panel says where, or why not."""
        from skydome.viewer.screenshot import save

        stem = self.panel.screenshot_requested
        self.panel.screenshot_requested = None
        try:
            paths = save([f"{stem}.png", f"{stem}.exr"], pixels, self.scene,
                         metadata=self.describe(self.scene))  # fmt: skip
            self.panel.message = "saved " + ", ".join(str(p) for p in paths)
        except Exception as exc:  # an unwritable directory: said, the viewer goes on
            self.panel.message = f"screenshot: {exc}"

    def run(
        self,
        scene,
        *,
        frames: int | None = None,
        screenshot=(),
        on_frame=None,
        duration_s: float | None = None,
    ):
        """Show ``scene`` until the window closes, for ``frames`` frames or for
        ``duration_s`` seconds; save the last frame to the ``screenshot`` paths (with
        ``frames``). ``on_frame(window, i)`` runs before each frame (scripts and tests
        inject input there). Returns the FrameTimer."""
        if frames is not None and (isinstance(frames, bool) or not isinstance(frames, int)):
            raise ParameterError(f"frames {frames!r} must be a positive integer")
        if frames is not None and frames < 1:
            raise ParameterError(f"frames {frames} must be a positive integer")
        if scene.ctx is not self.ctx:
            raise ParameterError("the scene's Sky must be made with ctx=window.ctx")
        self.scene = scene
        self.make_current()
        scene.base.graph.profiler = self.timer
        # A flag left by work done before the loop is not this loop's failure: take it.
        self.ctx.error  # noqa: B018
        glfw = self.glfw
        last = time.perf_counter()
        stop_at = None if duration_s is None else last + float(duration_s)
        i = 0
        pixels = None
        try:
            while not glfw.window_should_close(self.window):
                if frames is not None and i >= frames:
                    break
                if stop_at is not None and time.perf_counter() >= stop_at:
                    break
                glfw.poll_events()
                if on_frame is not None:
                    on_frame(self, i)
                w, h = self.framebuffer_size()
                if w == 0 or h == 0:  # minimised: nothing to draw
                    glfw.wait_events_timeout(0.1)
                    last = time.perf_counter()
                    continue
                now = time.perf_counter()
                dt, last = now - last, now
                self.timer.begin_frame()
                is_last = frames is not None and i == frames - 1
                shot = self.frame(dt, screenshot=bool(screenshot) and is_last)
                if shot is not None:
                    pixels = shot
                self.timer.end_frame(redrawn=getattr(scene, "redrew", True))
                self.check_context()
                i += 1
        except GLError:
            raise
        except Exception as exc:
            import moderngl

            if isinstance(exc, moderngl.Error):
                raise GLError(
                    f"the OpenGL context failed ({one_line(exc)}); the viewer stops. Restart "
                    "it; if it happens again, the driver or the display lost the context"
                ) from None
            raise
        finally:
            scene.base.graph.profiler = None
        if screenshot and pixels is not None:
            from skydome.viewer.screenshot import save

            self.saved = save(list(screenshot), pixels, scene, metadata=self.describe(scene))
        return self.timer

    def describe(self, scene) -> dict:
        """What a screenshot's metadata says about the view."""
        s = scene.controls.state
        return {
            "viewer": True,
            "camera": s.projection,
            "yaw_deg": s.yaw_deg,
            "pitch_deg": s.pitch_deg,
            "fov_deg": s.fov_deg,
            "exposure_ev100": scene.last_ev100,
            "tonemap": s.tonemap,
        }

    def check_context(self) -> None:
        """Raise GLError with a clear message when the GL context reports an error (a lost
        or failing context), instead of drawing garbage."""
        err = self.ctx.error
        if err != "GL_NO_ERROR":
            raise GLError(
                f"the OpenGL context failed ({err}); the viewer stops. Restart it; if it "
                "happens again, the driver or the display lost the context"
            )

    def close(self) -> None:
        """Free the panel, the timer's queries and the window. GL objects of this context
        that nothing holds any more are collected first, while the context is current:
        collected later, their release would delete another context's objects of the
        same names (GL names are per context; glDelete* acts on the current one)."""
        import gc

        if self.panel is not None:
            self.panel.release()
            self.panel = None
        self.timer.release()
        self.scene = None
        if self.window is not None:
            self.glfw.make_context_current(self.window)
            gc.collect()
            self.glfw.destroy_window(self.window)
            self.window = None
            self.glfw.terminate()
            _restore_headless()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
