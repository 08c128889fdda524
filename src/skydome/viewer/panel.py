"""The viewer's control panel (Dear ImGui through ``imgui-bundle``): time, place, camera,
atmosphere, display, frame times and screenshots.

Every widget writes through ``Controls.set`` (which clamps to the viewer's ranges) or the
atmosphere knobs' clamp (:func:`skydome.viewer.rebuild.clamp_knobs`), and sliders are
``always_clamp``: a value typed in (Ctrl+click) outside the range is held at the range's
end. A change of the atmosphere starts a background rebuild (``viewer.rebuild``) with a
progress bar; the old tables stay on screen until the new ones are ready.

``Panel.rects`` holds the screen rectangle (window units: the pointer's, not framebuffer
pixels on a HiDPI screen) of the last frame's named widgets, so that scripts and tests can
click them: "panel" (the whole panel), "header:NAME" (a section's header), "play",
"jump_KIND", "projection" and "preset" (combo boxes; while one is open, each item as
"projection:fisheye", "preset:hazy"), "fov" and "ev100" (slider frames),
"exposure:MODE" (radio buttons), "screenshot".
"""

from __future__ import annotations

import math
import time as _time
from datetime import datetime, timedelta, timezone

from skydome.astro.places import search, time_zone
from skydome.astro.time import UNIX_EPOCH_JD, Time, to_time
from skydome.atmosphere.presets import PRESETS
from skydome.clouds import PRESETS as CLOUD_PRESETS
from skydome.display import TONEMAPS
from skydome.display.exposure import METERINGS
from skydome.display.glare import GLARES
from skydome.display.overlays import OVERLAYS
from skydome.sky import Sky
from skydome.viewer import require
from skydome.viewer.controls import (
    COMPENSATION_RANGE,
    ELEVATION_RANGE_M,
    EV_RANGE,
    EXPOSURE_MODES,
    LAT_RANGE,
    LON_RANGE,
    PROJECTIONS,
    SPEED_PRESETS,
    SPEED_RANGE,
    VIEW_ALTITUDE_RANGE_M,
    VIEW_FOV_RANGE_DEG,
    VIEW_PITCH_RANGE_DEG,
)
from skydome.viewer.imgui_gl import ImguiPlatform, ImguiRenderer
from skydome.viewer.rebuild import KNOB_RANGES, AtmosphereRebuild, Knobs, build_sky, clamp_knobs
from skydome.weather import PRESETS as WEATHER_PRESETS
from skydome.weather import Weather

#: The panel has started no change of the weather.
_NO_WEATHER_CHANGE = object()

#: Panel width (window units) and where it sits in a narrow window (over the picture).
PANEL_WIDTH = 340.0
PANEL_POS = (10.0, 10.0)
#: Windows at least this wide (window units) dock the panel at the right edge and draw the
#: picture beside it (the panel never covers it); narrower ones float it over the picture.
DOCK_MIN_WIDTH = 2.0 * PANEL_WIDTH


class Panel:
    """The panel of a :class:`~skydome.viewer.app.ViewerWindow`."""

    def __init__(self, window):
        imgui = require("imgui_bundle", "imgui-bundle").imgui

        self.imgui = imgui
        self.context = imgui.create_context()
        imgui.get_io().set_ini_filename("")  # no imgui.ini in the working directory
        self.platform = ImguiPlatform(window.glfw, window.window)
        self.renderer = ImguiRenderer(window.ctx)
        self.window = window
        self.rebuild = AtmosphereRebuild()
        self.knobs: Knobs | None = None
        self.config = None
        self.weather = None  # the Weather shown (None: none)
        self._pending_weather = _NO_WEATHER_CHANGE
        self.rects: dict[str, tuple[float, float, float, float]] = {}
        self.message = ""
        self.search_text = ""
        self.search_results: list = []
        self.time_text = ""
        self._time_text_jd: float | None = None
        self._drawn = False

    def configure(self, description) -> None:
        """The sky shown (a SkyDescription): its atmosphere's knobs and its tables' config,
        which a rebuild keeps with the rest of the description."""
        self.knobs = Knobs.of(description.atmosphere)
        self.config = description.config
        self.weather = description.weather
        self.zone = time_zone(description.timezone) if description.timezone else None

    #: The time zone the Time section shows and reads (the place's; None: UTC).
    zone = None

    def _offset_days(self, jd_utc: float) -> float:
        """The zone's offset from UTC at ``jd_utc``, days (0 for UTC)."""
        if self.zone is None:
            return 0.0
        utc = datetime(1970, 1, 1, tzinfo=timezone.utc) + timedelta(
            seconds=round((jd_utc - UNIX_EPOCH_JD) * 86400.0)
        )
        return utc.astimezone(self.zone).utcoffset().total_seconds() / 86400.0

    # ------------------------------------------------------------------ input

    def wants_mouse(self) -> bool:
        """Whether the pointer is over the panel (or dragging one of its widgets)."""
        return bool(self._drawn and self.imgui.get_io().want_capture_mouse)

    def wants_keyboard(self) -> bool:
        """Whether a text field has the keyboard."""
        return bool(self._drawn and self.imgui.get_io().want_capture_keyboard)

    def on_key(self, key, action):
        self.platform.on_key(key, action)

    def on_char(self, codepoint):
        self.platform.on_char(codepoint)

    def on_cursor(self, x, y):
        self.platform.on_cursor(x, y)

    def on_mouse_button(self, button, action):
        self.platform.on_mouse_button(button, action)

    def on_scroll(self, dx, dy):
        self.platform.on_scroll(dx, dy)

    # ------------------------------------------------------------------ frames

    def build(self, scene, timer, dt_s: float) -> None:
        """Lay the panel out for this frame (its widgets act on ``scene`` at once)."""
        imgui = self.imgui
        imgui.set_current_context(self.context)
        self.platform.new_frame(dt_s)
        imgui.new_frame()
        self.rects = {}
        display = imgui.get_io().display_size
        flags = 0
        if self.docked(display.x):
            # a column at the right edge, the full height: the picture takes the rest
            imgui.set_next_window_pos(
                imgui.ImVec2(display.x - PANEL_WIDTH, 0.0), imgui.Cond_.always
            )
            imgui.set_next_window_size(imgui.ImVec2(PANEL_WIDTH, display.y), imgui.Cond_.always)
            flags = int(imgui.WindowFlags_.no_move) | int(imgui.WindowFlags_.no_resize)
        else:
            imgui.set_next_window_pos(imgui.ImVec2(*PANEL_POS), imgui.Cond_.first_use_ever)
            height = max(display.y - 2.0 * PANEL_POS[1], 100.0)
            imgui.set_next_window_size(
                imgui.ImVec2(PANEL_WIDTH, height), imgui.Cond_.first_use_ever
            )
        expanded, _ = imgui.begin("skydome", None, flags)
        self.collapsed = not expanded
        try:
            self._status(scene, timer)
            if self._header("Time", open_=True):
                self._time(scene)
            if self._header("Place"):
                self._place(scene)
            if self._header("Camera", open_=True):
                self._camera(scene)
            if self._header("Atmosphere"):
                self._atmosphere(scene)
            if self._header("Weather"):
                self._weather(scene)
                self._clouds_and_city(scene)
            if self._header("Display"):
                self._display(scene)
            if self._header("Frame times"):
                self._times(timer)
            pos, size = imgui.get_window_pos(), imgui.get_window_size()
            self.rects["panel"] = (pos.x, pos.y, pos.x + size.x, pos.y + size.y)
        finally:
            imgui.end()
        imgui.render()
        self._drawn = True

    @staticmethod
    def docked(window_width: float) -> bool:
        """Whether a window ``window_width`` units wide docks the panel at its right edge."""
        return window_width >= DOCK_MIN_WIDTH

    def picture_width(self, framebuffer_width: int, window_width: int) -> int:
        """The picture's width (framebuffer pixels) beside the docked panel: the framebuffer
        less the panel's column (scaled to pixels on a high-DPI screen), or all of it when
        the panel floats or is collapsed to its title bar."""
        if not self.docked(window_width) or self.collapsed:
            return int(framebuffer_width)
        scale = framebuffer_width / max(window_width, 1)
        return max(int(framebuffer_width - round(PANEL_WIDTH * scale)), 1)

    #: The panel was collapsed to its title bar at the last layout.
    collapsed = False
    #: Screenshots from the panel's button include the panel (else the picture alone).
    screenshot_with_panel = False

    def render(self, size: tuple[int, int]) -> None:
        """Draw the panel laid out by :meth:`build` over the frame."""
        self.imgui.set_current_context(self.context)
        self.renderer.render(self.imgui.get_draw_data(), size)

    def _mark(self, name: str, *, frame: bool = False) -> None:
        """Keep the last widget's rectangle as ``rects[name]`` (``frame``: a slider's frame
        only, without its label)."""
        imgui = self.imgui
        a, b = imgui.get_item_rect_min(), imgui.get_item_rect_max()
        x1 = a.x + imgui.calc_item_width() if frame else b.x
        self.rects[name] = (a.x, a.y, x1, b.y)

    def _header(self, label: str, open_: bool = False) -> bool:
        """A collapsing header (its rectangle kept as ``rects["header:" + label]``)."""
        imgui = self.imgui
        flags = imgui.TreeNodeFlags_.default_open if open_ else 0
        shown = imgui.collapsing_header(label, flags)
        self._mark(f"header:{label}")
        return shown

    def _combo(self, label: str, current: int, items: list[str], name: str):
        """A combo box as ``imgui.combo`` (returns (changed, index)), whose frame is kept as
        ``rects[name]`` and, while it is open, each item as ``rects[f"{name}:{item}"]``."""
        imgui = self.imgui
        preview = items[current] if 0 <= current < len(items) else ""
        opened = imgui.begin_combo(label, preview)
        self._mark(name, frame=True)
        changed, index = False, current
        if opened:
            for i, item in enumerate(items):
                picked, _ = imgui.selectable(item, i == current)
                self._mark(f"{name}:{item}")
                if picked and i != current:
                    changed, index = True, i
                if i == current:
                    imgui.set_item_default_focus()
            imgui.end_combo()
        return changed, index

    # ------------------------------------------------------------------ sections

    def _status(self, scene, timer) -> None:
        imgui = self.imgui
        s = scene.controls.state
        sky = scene.sky()
        sun = sky.state.sun
        line = redraw_line(
            timer, getattr(scene, "redrew", True), getattr(scene, "render_scale", None)
        )
        line += f"   Sun {sun.elevation_deg:+.1f} deg"
        if sky.state.moon is not None:
            line += f"   Moon {sky.state.moon.elevation_deg:+.1f} deg"
        imgui.text(line)
        if scene.last_ev100 is not None:
            imgui.text(f"EV100 {scene.last_ev100:.2f} ({s.exposure_mode})")
        status = self.rebuild.status
        if status.running:
            imgui.progress_bar(status.fraction, imgui.ImVec2(-1.0, 0.0), f"tables: {status.stage}")
        elif status.error:
            self.message = f"rebuild failed: {status.error}"
        if self.message:
            imgui.text_wrapped(self.message)

    def _time(self, scene) -> None:
        imgui = self.imgui
        c = scene.controls
        s = c.state
        if s.abstract:
            changed, el = imgui.slider_float(
                "Sun elevation", s.sun_elevation_deg, -90.0, 90.0, "%.2f deg", _clamp(imgui)
            )
            if changed:
                c.set(sun_elevation_deg=el)
            changed, az = imgui.slider_float(
                "Sun azimuth", s.sun_azimuth_deg, 0.0, 360.0, "%.1f deg", _clamp(imgui)
            )
            if changed:
                c.set(sun_azimuth_deg=az)
            return

        offset = self._offset_days(s.jd_utc)
        if self._time_text_jd != s.jd_utc and not imgui.get_io().want_text_input:
            # the wall clock of the place (ISO, no offset: what the field reads back)
            self.time_text = str(Time.from_utc(s.jd_utc + offset).iso()).rstrip("Z")
            self._time_text_jd = s.jd_utc
        label = "UTC" if self.zone is None else f"local ({self.zone.key})"
        entered, text = imgui.input_text(
            label, self.time_text, imgui.InputTextFlags_.enter_returns_true
        )
        self._mark("time_text")
        self.time_text = text
        if entered:
            try:
                t = to_time(text.strip(), zone=self.zone)
                c.set(jd_utc=float(t.jd_utc))
                self.message = ""
            except Exception as exc:  # a bad date: said, not raised
                self.message = f"time: {exc}"
            self._time_text_jd = None
        for label, days in (("-1 d", -1.0), ("-1 h", -1 / 24), ("+1 h", 1 / 24), ("+1 d", 1.0)):
            if imgui.button(label):
                c.set(jd_utc=s.jd_utc + days)
            imgui.same_line()
        if imgui.button("Now"):
            c.set(jd_utc=float(to_time(datetime.now(timezone.utc)).jd_utc))
        hours = (s.jd_utc + offset - 0.5) % 1.0 * 24.0
        hour_label = "hour (UTC)" if self.zone is None else "hour (local)"
        changed, h = imgui.slider_float(hour_label, hours, 0.0, 24.0, "%.2f h", _clamp(imgui))
        if changed:
            c.set(jd_utc=s.jd_utc + (h - hours) / 24.0)
        if imgui.button("Pause" if s.playing else "Play"):
            c.set(playing=not s.playing)
        self._mark("play")
        imgui.same_line()
        names = list(SPEED_PRESETS)
        current = next(
            (i for i, n in enumerate(names) if SPEED_PRESETS[n] == abs(s.speed)), len(names)
        )
        changed, i = imgui.combo("speed", current, [*names, "custom"])
        if changed and i < len(names):
            c.set(speed=math.copysign(SPEED_PRESETS[names[i]], s.speed or 1.0))
        changed, v = imgui.slider_float(
            "s per s",
            s.speed,
            *SPEED_RANGE,
            "%.0f",
            imgui.SliderFlags_.logarithmic | _clamp(imgui),
        )
        if changed:
            c.set(speed=v)
        for label, kind in (
            ("sunrise", "sunrise"),
            ("sunset", "sunset"),
            ("moonrise", "moonrise"),
            ("full Moon", "full_moon"),
            ("eclipse", "eclipse"),
        ):
            if imgui.button(label):
                if not scene.jump(kind):
                    self.message = f"no {label} in the next days here"
            self._mark(f"jump_{kind}")
            imgui.same_line()
        imgui.new_line()

    def _place(self, scene) -> None:
        imgui = self.imgui
        c = scene.controls
        s = c.state
        if s.abstract:
            imgui.text("a Sun alone: no place (start with --place or --lat/--lon)")
            return
        for label, field, rng, fmt in (
            ("latitude", "latitude_deg", LAT_RANGE, "%.4f deg"),
            ("longitude", "longitude_deg", LON_RANGE, "%.4f deg"),
            ("elevation", "elevation_m", ELEVATION_RANGE_M, "%.0f m"),
        ):
            changed, v = imgui.drag_float(
                label, getattr(s, field), 0.01 if "deg" in fmt else 1.0, *rng, fmt, _clamp(imgui)
            )
            if changed:
                c.set(**{field: v})
        changed, text = imgui.input_text("search", self.search_text)
        if changed:
            self.search_text = text

            self.search_results = search(text, limit=8) if text.strip() else []
        for p in self.search_results:
            picked, _ = imgui.selectable(p.label, False)
            if picked:
                c.set(
                    latitude_deg=p.latitude_deg,
                    longitude_deg=p.longitude_deg,
                    elevation_m=p.elevation_m,
                )
                self.search_results = []
                self.search_text = p.label
                self.zone = time_zone(p.timezone) if p.timezone else None
                self._time_text_jd = None  # the Time field in the new place's clock
                scene.aim_at_light()  # a new place: its Sun (or Moon) in view

    def _camera(self, scene) -> None:
        imgui = self.imgui
        c = scene.controls
        s = c.state
        changed, i = self._combo(
            "projection", PROJECTIONS.index(s.projection), list(PROJECTIONS), "projection"
        )
        if changed:
            c.set(projection=PROJECTIONS[i])
        if s.projection == "perspective":
            changed, v = imgui.slider_float("yaw", s.yaw_deg, 0.0, 360.0, "%.1f deg", _clamp(imgui))
            if changed:
                c.set(yaw_deg=v)
            changed, v = imgui.slider_float(
                "pitch", s.pitch_deg, *VIEW_PITCH_RANGE_DEG, "%.1f deg", _clamp(imgui)
            )
            if changed:
                c.set(pitch_deg=v)
            changed, v = imgui.slider_float(
                "fov", s.fov_deg, *VIEW_FOV_RANGE_DEG, "%.1f deg", _clamp(imgui)
            )
            self._mark("fov", frame=True)
            if changed:
                c.set(fov_deg=v)
        altitude = scene.altitude_m()
        changed, v = imgui.slider_float(
            "altitude",
            max(altitude, 0.1),
            max(VIEW_ALTITUDE_RANGE_M[0], 0.1),
            VIEW_ALTITUDE_RANGE_M[1],
            "%.1f m",
            imgui.SliderFlags_.logarithmic | _clamp(imgui),
        )
        if changed:
            c.set(altitude_m=v)
        if imgui.button("look at the Sun"):
            scene.look_at("sun")
        imgui.same_line()
        if imgui.button("look at the Moon"):
            scene.look_at("moon")
        imgui.text_disabled("drag: look, wheel: zoom, WASD: walk, Q/E: climb")

    def _atmosphere(self, scene) -> None:
        imgui = self.imgui
        if self.knobs is None:
            self.knobs = Knobs.of(scene.base.layer("atmosphere").params)
        k = self.knobs

        names = list(PRESETS)
        edited = False
        current = names.index(k.preset) if k.preset in names else 0
        changed, i = self._combo("preset", current, names, "preset")
        if changed:
            self.knobs = k = Knobs.of_preset(names[i])
            edited = True
        values = {}
        for field, label, fmt in (
            ("albedo", "ground albedo", "%.2f"),
            ("aod_550", "Mie amount (AOD 550)", "%.3f"),
            ("mie_g", "Mie g", "%.2f"),
            ("ozone_du", "ozone", "%.0f DU"),
            ("rayleigh_scale", "Rayleigh scale", "%.2f"),
        ):
            lo, hi = KNOB_RANGES[field]
            flags = _clamp(imgui) | (_logarithmic(imgui) if field == "aod_550" else 0)
            changed, v = imgui.slider_float(label, getattr(k, field), lo, hi, fmt, flags)
            if changed:
                values[field] = v
            if imgui.is_item_deactivated_after_edit():
                edited = True
        if values:
            self.knobs = k = clamp_knobs(k, **values)
        if edited:
            self._start_rebuild()

    def _weather(self, scene) -> None:
        """A weather preset and its visibility, rain and snow: a change builds the sky with
        it (its air's tables in the background first, as the atmosphere's knobs do)."""
        imgui = self.imgui
        names = ["none", *WEATHER_PRESETS]
        w = self.weather
        current = names.index(w.preset) if w is not None else 0
        changed, i = self._combo("weather", current, names, "weather")
        if changed:
            self._start_weather(scene, None if i == 0 else Weather(names[i]))
            return
        if w is None:
            return
        values, edited = {}, False
        visibility = w.visibility_km if w.visibility_km is not None else 20.0
        for field, label, value, lo, hi, fmt in (
            ("visibility_km", "visibility", visibility, 0.05, 50.0, "%.2f km"),
            ("rain_mm_h", "rain", w.rain_mm_h, 0.0, 50.0, "%.1f mm/h"),
            ("snow_mm_h", "snow", w.snow_mm_h, 0.0, 10.0, "%.1f mm/h"),
        ):
            flags = _clamp(imgui) | (_logarithmic(imgui) if field == "visibility_km" else 0)
            moved, v = imgui.slider_float(label, value, lo, hi, fmt, flags)
            if moved:
                values[field] = v
            if imgui.is_item_deactivated_after_edit():
                edited = True
        if values:
            try:
                self.weather = w.with_(**values)
            except Exception as exc:  # out of range: said, the weather stays
                self.message = f"weather: {exc}"
        if edited:
            self._start_weather(scene, self.weather)

    def _clouds_and_city(self, scene) -> None:
        """The clouds (a preset, or none) and the city's light (a Bortle class, 0: none): a
        change builds the sky with it at once (neither needs new air tables; a cloud
        preset's noise comes from the disk cache, or is drawn the first time)."""
        imgui = self.imgui
        description = scene.base.description
        names = ["none", *CLOUD_PRESETS]
        clouds = description.clouds
        current = names.index(clouds.preset) if clouds is not None and clouds.preset in names else 0
        changed, i = self._combo("clouds", current, names, "clouds")
        if changed and i != current:
            self._rebuild_with(scene, "clouds", clouds=None if i == 0 else names[i])
        if description.abstract:
            return
        lp = description.light_pollution
        bortle = lp if isinstance(lp, int) else 0
        moved, value = imgui.slider_int("Bortle (0: none)", bortle, 0, 9, "%d", _clamp(imgui))
        self._mark("bortle", frame=True)
        if moved:
            self._bortle = value
        if imgui.is_item_deactivated_after_edit() and self._bortle is not None:
            value, self._bortle = self._bortle, None
            self._rebuild_with(scene, "light pollution", light_pollution=value or None)

    #: A Bortle class being dragged on its slider (applied on release).
    _bortle: int | None = None

    def _rebuild_with(self, scene, what: str, **changes) -> None:
        """Build the sky with ``changes`` to its description and show it (the display
        settings kept); on a failure the old sky stays and the panel says why."""
        base = scene.base
        try:
            sky = Sky(base.description.with_(**changes), ctx=base.graph.ctx)
            sky.graph.set_display(night_vision=base.night_vision, overlays=base.overlays)
        except Exception as exc:  # a change this sky cannot have: said, the old one stays
            self.message = f"{what}: {exc}"
            return
        scene.replace_sky(sky)
        self.message = ""

    def _start_weather(self, scene, weather) -> None:
        """Start building the sky with ``weather``: its air's tables in the background."""
        try:
            description = scene.base.description.with_(weather=weather)
            air, _, config = description.effective
            self.rebuild.start(air, config)
        except Exception as exc:  # a weather this sky cannot have: said, the old one stays
            self.message = f"weather: {exc}"
            self.weather = scene.base.description.weather
            return
        self.weather = weather
        self._pending_weather = weather
        self.message = ""

    def _start_rebuild(self) -> None:
        try:
            self.rebuild.start(self.knobs.params(), self.config)
            self.message = ""
        except Exception as exc:  # bad knobs: said, the old tables stay
            self.message = f"atmosphere: {exc}"

    def poll_rebuild(self, scene) -> None:
        """Swap in the new tables once the background rebuild has them in the cache."""
        self.rebuild.poll()
        done = self.rebuild.take()
        if done is None:
            return
        params, config = done
        weather, self._pending_weather = self._pending_weather, _NO_WEATHER_CHANGE
        try:
            if weather is _NO_WEATHER_CHANGE:
                sky = build_sky(scene.base, params, config)
            else:
                base = scene.base
                sky = Sky(base.description.with_(weather=weather), ctx=base.graph.ctx)
                sky.graph.set_display(night_vision=base.night_vision, overlays=base.overlays)
        except Exception as exc:
            self.message = f"sky: {exc}"
            return
        scene.replace_sky(sky)
        self.message = (
            f"atmosphere: {params.name}"
            if weather is _NO_WEATHER_CHANGE
            else f"weather: {'none' if weather is None else weather.preset}"
        )

    def stop_rebuild(self) -> None:
        self.rebuild.stop()

    def _display(self, scene) -> None:
        imgui = self.imgui

        c = scene.controls
        s = c.state
        for mode in EXPOSURE_MODES:
            if imgui.radio_button(mode, s.exposure_mode == mode):
                c.set(exposure_mode=mode)
            self._mark(f"exposure:{mode}")
            imgui.same_line()
        imgui.new_line()
        if s.exposure_mode == "ev":
            changed, v = imgui.slider_float("EV100", s.ev100, *EV_RANGE, "%.2f", _clamp(imgui))
            self._mark("ev100", frame=True)
            if changed:
                c.set(ev100=v)
        changed, v = imgui.slider_float(
            "compensation", s.compensation_ev, *COMPENSATION_RANGE, "%.2f EV", _clamp(imgui)
        )
        if changed:
            c.set(compensation_ev=v)
        ops = list(TONEMAPS)
        changed, i = imgui.combo("tone map", ops.index(s.tonemap), ops)
        if changed:
            c.set(tonemap=ops[i])
        # how the automatic exposure meters, and the glare of the display image
        for attr, label, names in (("metering", "metering", METERINGS), ("glare", "glare", GLARES)):
            current = names.index(getattr(scene, attr))
            changed, i = self._combo(label, current, list(names), attr)
            if changed:
                setattr(scene, attr, names[i])
        changed, v = imgui.checkbox("night vision", s.night_vision)
        if changed:
            c.set(night_vision=v)

        for name in OVERLAYS:
            changed, on = imgui.checkbox(f"overlay: {name}", name in s.overlays)
            if changed:
                chosen = [n for n in OVERLAYS if (n in s.overlays) != (n == name)]
                c.set(overlays=tuple(chosen))
        imgui.separator()
        for layer in scene.base.layers:
            changed, on = imgui.checkbox(f"layer: {layer.name}", layer.name not in s.layers_off)
            if changed:
                off = set(s.layers_off)
                (off.discard if on else off.add)(layer.name)
                c.set(layers_off=frozenset(off))
        changed, v = imgui.checkbox("vsync", s.vsync)
        if changed:
            c.set(vsync=v)
        # dynamic resolution: the frame time a moving view is held to (0: off)
        changed, v = imgui.slider_float(
            "frame budget", scene.frame_budget_ms, 0.0, 100.0, "%.0f ms", _clamp(imgui)
        )
        self._mark("frame_budget", frame=True)
        if changed:
            scene.frame_budget_ms = round(v)

    def _times(self, timer) -> None:
        imgui = self.imgui
        r = timer.report()
        for kind in ("cpu", "gpu"):
            total = sum(r[kind].values())
            imgui.text(f"{kind.upper()} {total:.1f} ms")
            for name, ms in r[kind].items():
                imgui.bullet_text(f"{name}: {ms:.2f} ms")
        if imgui.button("screenshot (PNG + EXR)"):
            self.screenshot_requested = _time.strftime("skydome-%Y%m%d-%H%M%S")
        self._mark("screenshot")
        _, self.screenshot_with_panel = imgui.checkbox("with the panel", self.screenshot_with_panel)
        self._mark("screenshot_with_panel")

    screenshot_requested: str | None = None

    def release(self) -> None:
        """Free the renderer's GL objects, stop a rebuild and drop the ImGui context."""
        self.rebuild.stop()
        self.imgui.set_current_context(self.context)
        self.renderer.release()
        self.imgui.destroy_context(self.context)


def _clamp(imgui) -> int:
    """Slider flags that hold typed-in values inside the range."""
    return int(imgui.SliderFlags_.always_clamp)


def _logarithmic(imgui) -> int:
    """Slider flags for a quantity that spans decades (the aerosol's optical depth, 0-5,
    matters most below 0.3; the visibility, 0.05-50 km): even steps of its logarithm."""
    return int(imgui.SliderFlags_.logarithmic)


def redraw_line(timer, redrawing: bool, scale: float | None = None) -> str:
    """The panel's speed readout: drawn frames per second and the median ms per redraw
    while the view changes, with the render scale of the last frame (dynamic resolution:
    the fraction of each side drawn) when below 1; "still" with the last redraws' ms while
    a kept frame is shown (showing it again costs a copy, not a frame)."""
    ms = timer.median_redraw_ms()
    if ms is None:
        return "-- fps"
    if redrawing:
        line = f"{1e3 / ms:.1f} fps drawn ({ms:.0f} ms per redraw)"
        if scale is not None and scale < 1.0:
            line += f", scale {scale:g}"
        return line
    return f"still (a redraw takes {ms:.0f} ms)"
