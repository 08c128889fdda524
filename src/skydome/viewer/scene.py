"""The Sky a viewer shows: one frame graph (layers and tables) following a ``Controls``.

:class:`ViewerScene` turns the controls' :class:`~skydome.viewer.controls.ViewState` into
a ``Sky`` at that time and place (a new SkyState only when the time or the place changed),
keeps the display settings and the layers' switches in step, runs the exposure modes (auto,
EV, an eye adapting over time) and draws a frame or renders the same frame for a
screenshot. It swaps in a new atmosphere (from ``viewer.rebuild``) between two frames. The
window and the notebook widget both use it.
"""

from __future__ import annotations

import contextlib
import math
from collections import deque
from typing import Any

import numpy as np

from skydome.astro import Observer
from skydome.astro.time import Time
from skydome.core.frame import Frame
from skydome.core.services import AirService
from skydome.display.adaptation import EyeAdaptation
from skydome.display.exposure import scale_to_ev100
from skydome.errors import ParameterError
from skydome.scene.state import abstract_state, state_at
from skydome.sky import Sky, default_look, exposure_scale
from skydome.viewer.controls import Controls, ViewState
from skydome.viewer.dynamic_resolution import (
    DEFAULT_FRAME_BUDGET_MS,
    MAX_SCALE,
    ResolutionController,
    Upsampler,
    reduced_size,
)
from skydome.viewer.jumps import next_event

#: The most the Sun or the Moon may move (deg) before a new time is drawn: a tenth of
#: their disks' diameter (less when half a pixel of the view is less).
HOLD_MAX_DEG = 0.05


def initial_state(sky: Sky, **overrides: Any) -> ViewState:
    """A ViewState for ``sky``'s place and time, the camera on what ``skydome render``
    would look at (the Sun, or at night the Moon when it is up, else south); then
    ``overrides`` (ViewState fields)."""

    state = sky.state
    fields: dict[str, Any] = {}
    if sky.observer is not None:
        fields.update(
            latitude_deg=float(sky.observer.latitude),
            longitude_deg=float(sky.observer.longitude),
            elevation_m=float(sky.observer.elevation_m),
            jd_utc=float(state.time.jd_utc),
        )
        look = default_look(state)
        if look == "zenith":
            look = "south"
        cam = sky.camera(look)
        fields.update(yaw_deg=cam.yaw_deg, pitch_deg=cam.pitch_deg)
    else:
        fields.update(
            sun_elevation_deg=state.sun.elevation_deg,
            sun_azimuth_deg=state.sun.azimuth_deg,
            yaw_deg=state.sun.azimuth_deg,
            pitch_deg=15.0,
        )
    fields.update(overrides)
    return ViewState(**fields)


class ViewerScene:
    """The frames of a viewer.

    Args:
        sky: the Sky to show (its layers, tables and context: a window's ``ctx``).
        controls: the state to follow (default: :func:`initial_state` of ``sky``).
    """

    def __init__(self, sky: Sky, controls: Controls | None = None):

        self.base = sky
        self.controls = controls or Controls(initial_state(sky))
        self.eye = EyeAdaptation(key="eye")
        #: Metering and glare of the frames (``Sky.render``'s): the command line's flags.
        self.metering = "eye"
        self.glare = "eye"
        self._key: tuple | None = None
        self._sky: Sky | None = None
        self._observer_key: tuple | None = None
        self._observer = sky.observer
        self._pending = None
        #: The width (pixels) of the view drawn, for the half-pixel hold of :meth:`sky`.
        self.view_width_px: int | None = None
        #: The exposure (EV100) of the last frame drawn, and its tone map.
        self.last_ev100: float | None = None
        self._cache: FrameCache | None = None
        #: Dynamic resolution: the render scale of a moving view, held to the frame budget
        #: (:attr:`frame_budget_ms`; ``viewer.dynamic_resolution``).
        self.resolution = ResolutionController(DEFAULT_FRAME_BUDGET_MS)
        #: The render scale (fraction of each side) of the last frame drawn anew, and those
        #: of the recent frames drawn anew.
        self.render_scale = MAX_SCALE
        self.drawn_scales: deque[float] = deque(maxlen=600)
        #: Whether the last frame drew the sky anew (the frame timer's drawn frames).
        self.redrew = False
        #: Draw the next frame at full resolution even if the view moves (a screenshot).
        self.full_resolution_next = False
        self._upsampler: Upsampler | None = None

    @property
    def frame_budget_ms(self) -> float:
        """The frame time (ms) a moving view is held to by drawing it at a reduced size
        (dynamic resolution); 0: off, every frame at full resolution."""
        return self.resolution.budget_ms

    @frame_budget_ms.setter
    def frame_budget_ms(self, value: float) -> None:
        self.resolution = ResolutionController(value)
        self.render_scale = MAX_SCALE

    # ------------------------------------------------------------------ the sky now

    @property
    def ctx(self):
        return self.base.graph.ctx

    def observer(self):
        """The Observer of the state's place (None in the abstract mode)."""
        s = self.controls.state
        if s.abstract:
            return None
        key = (s.latitude_deg, s.longitude_deg, s.elevation_m)
        if key != self._observer_key:
            base = self.base.observer
            weather = {}
            if base is not None:
                weather = {
                    "pressure_hPa": float(base.pressure_hPa),
                    "temperature_C": float(base.temperature_C),
                }
            self._observer = Observer(
                latitude=s.latitude_deg,
                longitude=s.longitude_deg,
                elevation_m=s.elevation_m,
                **weather,
            )
            self._observer_key = key
        return self._observer

    def sky(self) -> Sky:
        """The Sky of the controls' state (its SkyState made again only when the time, the
        place or the abstract Sun changed), with the display and layer switches applied."""
        s = self.controls.state
        if s.abstract:
            key = ("abstract", s.sun_elevation_deg, s.sun_azimuth_deg)
        else:
            key = (s.jd_utc, s.latitude_deg, s.longitude_deg, s.elevation_m)
        if (key != self._key or self._sky is None) and not (not s.abstract and self._hold(key)):
            if s.abstract:
                state = abstract_state(s.sun_elevation_deg, s.sun_azimuth_deg)
                self._sky = Sky._view(self.base, state)
            else:
                state = self._pending or state_at(self.observer(), Time.from_utc(s.jd_utc))
                self._sky = Sky._view(self.base, state)
            self._key = key
        self._pending = None
        graph = self.base.graph
        for layer in graph.layers:
            layer.enabled = layer.name not in s.layers_off
        if graph.night_vision != s.night_vision or graph.overlays != tuple(s.overlays):
            graph.set_display(night_vision=s.night_vision, overlays=tuple(s.overlays))
        if self.controls.pending_look is not None:
            self._aim(self._sky, self.controls.pending_look)
            self.controls.pending_look = None
        return self._sky

    def _hold(self, key: tuple) -> bool:
        """Whether a new time at the same place moves the Sun and the Moon (and with them
        the turning sky) by less than half a pixel of the view (at most HOLD_MAX_DEG)
        from the state drawn, while the time plays: then the drawn state is kept and its tables are not re-aimed
        (a time running slowly costs one astronomy call a frame, not a re-aim). Otherwise
        the new state is kept in ``_pending`` for :meth:`sky`."""

        self._pending = None
        s = self.controls.state
        if not s.playing or self._sky is None or self._key is None or self._key[1:] != key[1:]:
            return False
        state = state_at(self.observer(), Time.from_utc(s.jd_utc))
        old = self._sky.state
        w = 1280.0 if self.view_width_px is None else float(self.view_width_px)
        fov = s.fov_deg if s.projection == "perspective" else 360.0
        tol = min(HOLD_MAX_DEG, 0.5 * fov / max(w, 1.0))
        for a, b in ((old.sun, state.sun), (old.moon, state.moon)):
            if a is None or b is None:
                continue
            cos = float(np.clip(np.dot(a.direction, b.direction), -1.0, 1.0))
            if np.degrees(np.arccos(cos)) >= tol:
                self._pending = state
                return False
        return True

    def _aim(self, sky: Sky, look: str, min_pitch_deg: float = -90.0) -> None:
        light = sky.state.sun if look == "sun" else sky.state.moon
        if light is not None:
            self.controls.look_at(max(light.elevation_deg, min_pitch_deg), light.azimuth_deg)

    def look_at(self, body: str) -> None:
        """Aim the camera at the Sun or the Moon ("sun" or "moon") of the current time."""
        if body not in ("sun", "moon"):
            raise ParameterError(f"look_at {body!r} must be 'sun' or 'moon'")
        self._aim(self.sky(), body)

    def jump(self, kind: str) -> bool:
        """Set the time to the next ``kind`` (``viewer.jumps.JUMPS``: sunrise, sunset,
        moonrise, moonset, full_moon); False when there is none ahead (or no place)."""

        s = self.controls.state
        if s.abstract:
            return False
        jd = next_event(self.observer(), s.jd_utc, kind)
        if jd is None:
            return False
        self.controls.set(jd_utc=jd)
        # the camera turns to the event: the Sun rising or setting, the Moon (a full Moon
        # below the horizon: its azimuth, the horizon in view)
        body = "sun" if kind.startswith("sun") else "moon"
        if kind == "eclipse":  # the body the Moon or the Earth's shadow covers
            sky = self.sky()
            solar = (
                sky.state.moon is not None and _separation_deg(sky.state.sun, sky.state.moon) < 2.0
            )
            body = "sun" if solar else "moon"
        self._aim(self.sky(), body, min_pitch_deg=2.0)
        return True

    def aim_at_light(self) -> None:
        """Turn the camera to what lights the sky at a new place: the Sun down to 12 deg
        below the horizon (its twilight), else the Moon when it is up; else leave it."""
        sky = self.sky()
        if sky.state.sun.elevation_deg > -12.0:
            self._aim(sky, "sun", min_pitch_deg=2.0)
        elif sky.state.moon is not None and sky.state.moon.elevation_deg > 0.0:
            self._aim(sky, "moon")

    def altitude_m(self) -> float:
        """The camera's altitude above the ground (m) in use."""
        s = self.controls.state
        return self.base.altitude_m(s.altitude_m)

    # ------------------------------------------------------------------ exposure

    def exposure(self) -> tuple[str | float, float]:
        """(exposure, compensation_ev) for ``Sky.draw``/``Sky.render`` now: "auto", or
        an EV100 number (the EV mode's, or the adapted eye's)."""
        s = self.controls.state
        if s.exposure_mode == "ev":
            return s.ev100, s.compensation_ev
        if s.exposure_mode == "adapt" and self.eye.adapted_luminance is not None:
            return scale_to_ev100(self.eye.exposure_scale(0.0)), s.compensation_ev
        return "auto", s.compensation_ev

    # ------------------------------------------------------------------ frames

    def draw(self, framebuffer, size: tuple[int, int], dt_s: float = 0.0) -> None:
        """Draw the state's frame into ``framebuffer`` over ``size`` (w, h) pixels,
        tone-mapped; in the adapt mode, then let the eye adapt for ``dt_s`` real seconds to
        what it measured. The auto exposure is read back (one texel) and applied as a fixed
        scale, as ``Sky.render`` does: cheaper per pixel on a CPU rasterizer.

        A view that has not changed since the last frame is not drawn again (see
        :class:`FrameCache`): a new view (time, place, camera, size or layers changed) is
        drawn and tone-mapped straight into ``framebuffer``; when the next frame has the
        same view, its float frame, kept on the GPU, is tone-mapped into the scene's own
        8-bit target, which is copied (a blit) into ``framebuffer`` for as long as nothing
        changes. When only the display changes (an exposure, the tone map, night vision,
        overlays) the post passes alone run again, from the kept float frame.

        Dynamic resolution (:attr:`frame_budget_ms` > 0): a new view whose previous frame was
        drawn anew too (the view moves) is drawn, measured and tone-mapped at the
        controller's :attr:`render_scale` and upsampled to ``size``
        (``viewer.dynamic_resolution``); ``dt_s``, the time since the last frame, is that
        frame's time. When the view stops, the next frame is drawn at full resolution."""

        s = self.controls.state
        self.view_width_px = int(size[0])
        sky = self.sky()
        graph = sky.graph
        exposure, comp = self.exposure()
        adapt = s.exposure_mode == "adapt"
        size = (int(size[0]), int(size[1]))
        view = (
            s.projection, s.yaw_deg, s.pitch_deg, s.fov_deg, self.altitude_m(),
            tuple(layer.enabled for layer in graph.layers),
        )  # fmt: skip
        display = (s.tonemap, s.night_vision, tuple(s.overlays), s.exposure_mode, comp,
                   self.metering, self.glare)  # fmt: skip
        cache = self._cache
        if cache is None or cache.ctx is not graph.ctx:
            if cache is not None:
                cache.release()
            cache = self._cache = FrameCache(graph.ctx)
        moved = not cache.holds_view(graph, sky.state, view, size)
        scale = MAX_SCALE
        if moved:
            if self.redrew and dt_s > 0.0:  # the last frame was drawn anew: its time
                self.resolution.observe(dt_s * 1e3, self.render_scale)
            if (
                self.frame_budget_ms > 0.0
                and self.redrew
                and not self.full_resolution_next
                and not cache.same_view(graph, sky.state, view, size)
            ):
                scale = self.resolution.scale
            self.render_scale = scale
            self.drawn_scales.append(scale)
        self.full_resolution_next = False
        self.redrew = moved
        if moved and scale < MAX_SCALE:
            self._draw_reduced(framebuffer, size, scale, sky, view, display, cache)
            return
        if moved:
            texture = graph.frame_texture(
                sky.state, s.camera(), *size, altitude_m=self.altitude_m()
            )
            cache.keep_view(graph, sky.state, view, size, texture)
        if moved or not cache.holds_display(display, exposure):
            # A new view goes straight to the screen (a moving view pays no copy); a view
            # that stays is tone-mapped into the kept image, shown from there from now on.
            target = framebuffer if moved else cache.target(size)
            scale = graph.draw(
                sky.state,
                target,
                s.camera(),
                altitude_m=self.altitude_m(),
                size=size,
                exposure=exposure_scale(exposure, comp),
                compensation_ev=comp,
                tonemap=s.tonemap,
                measure=adapt,
                read_back=True,
                texture=cache.texture,
                metering=self.metering,
                glare=self.glare,
                adaptation=self.eye.adapted_luminance if adapt else None,
            )
            luminance = graph.exposure_pass().read() if adapt else None
            cache.keep_display(display, exposure, scale, luminance, graph, kept=not moved)
        if not moved:
            cache.show(framebuffer, size)
        #: The EV100 of the exposure applied (compensation included).
        self.last_ev100 = None if cache.scale is None else scale_to_ev100(cache.scale)

    def _draw_reduced(self, framebuffer, size, scale, sky, view, display, cache) -> None:
        """Draw the moving view at ``scale``: the layers, the exposure, the display passes
        and the tone map at the reduced size, into the upsampler's 8-bit target, then
        upsampled into ``framebuffer`` over ``size``. The kept float frame is the reduced
        one (the next frame of the same view refines it at full resolution)."""
        s = self.controls.state
        graph = sky.graph
        camera = s.camera()
        altitude_m = self.altitude_m()
        exposure, comp = self.exposure()
        adapt = s.exposure_mode == "adapt"
        rsize = camera.frame_size(*reduced_size(size, scale))
        up = self._upsampler
        if up is None or up.ctx is not graph.ctx:
            if up is not None:
                up.release()
            up = self._upsampler = Upsampler(graph.ctx)
        target = up.target(rsize)
        if cache.reduced_size is not None and cache.reduced_size != rsize:
            graph.release_targets(keep=size)  # the last scale's targets: not kept
        texture = graph.frame_texture(sky.state, camera, *rsize, altitude_m=altitude_m)
        cache.keep_view(graph, sky.state, view, size, texture, reduced=rsize)
        target.viewport = (0, 0, *rsize)
        used = graph.draw(
            sky.state, target, camera, altitude_m=altitude_m, size=rsize,
            exposure=exposure_scale(exposure, comp), compensation_ev=comp, tonemap=s.tonemap,
            measure=adapt, read_back=True, texture=texture, metering=self.metering,
            glare=self.glare, adaptation=self.eye.adapted_luminance if adapt else None,
        )  # fmt: skip
        luminance = graph.exposure_pass().read() if adapt else None
        cache.keep_display(display, exposure, used, luminance, graph, kept=False)
        air = graph.find_service(AirService)
        bottom_m = 6_371_000.0 if air is None else float(air.bottom_radius_m)
        section = contextlib.nullcontext()
        if graph.profiler is not None:
            section = graph.profiler.section("upsample")
        with section:
            up.draw(framebuffer, size, camera, altitude_m=altitude_m, bottom_radius_m=bottom_m)
        self.last_ev100 = None if cache.scale is None else scale_to_ev100(cache.scale)

    def invalidate(self) -> None:
        """Forget the kept frame: the next :meth:`draw` draws the layers again. For a change
        the view's key does not see (a layer's parameters set directly, e.g. by a script
        between frames); the time, the place, the camera, the size, the layers' switches,
        the display settings and a new atmosphere are seen."""
        if self._cache is not None:
            self._cache.release()

    def render(self, width: int, height: int, *, tonemap: bool = True) -> Frame:
        """The frame :meth:`draw` shows, read back: ``Frame.data`` in cd/m^2 and (with
        ``tonemap``) ``Frame.image``, at the exposure in use now (the adapt mode's current
        eye; no adaptation step)."""
        s = self.controls.state
        exposure, comp = self.exposure()
        return self.sky().render(
            s.camera(),
            width,
            height,
            altitude_m=self.altitude_m(),
            exposure=exposure,
            compensation_ev=comp,
            tonemap=s.tonemap if tonemap else None,
            metering=self.metering,
            glare=self.glare,
        )

    # ------------------------------------------------------------------ atmosphere

    def replace_sky(self, sky: Sky) -> None:
        """Show ``sky`` (the same context; e.g. a new atmosphere's) from the next frame on,
        keeping the view state, and free the old one's GPU resources."""
        if sky.graph.ctx is not self.base.graph.ctx:
            raise ParameterError("the new sky must draw in the viewer's own GL context")
        old = self.base
        sky.graph.profiler = old.graph.profiler
        self.base = sky
        self._sky = None
        self._key = None
        if old.graph is not sky.graph:
            old.release()

    def release(self) -> None:
        """Free the GPU resources of the sky shown (and of the kept frame)."""
        if self._cache is not None:
            self._cache.release()
            self._cache = None
        if self._upsampler is not None:
            self._upsampler.release()
            self._upsampler = None
        self.base.release()


class FrameCache:
    """The last frame a viewer drew, kept on the GPU: which view its float texture holds (a
    frame graph's target, valid while the graph's ``generation`` stays where it was after
    the draw), and the 8-bit image tone-mapped from it (in a target of its own) with the
    display settings and exposure used.

    A view is the same when the SkyState object, the graph, the camera fields, the altitude,
    the layers' switches and the size are; an exposure when it is the same string ("auto":
    the frame's own measure) or the same EV100 to within EXPOSURE_HOLD_EV (the adapt mode's
    eye creeps towards its target for ever: a change of 1.4e-4 EV scales linear values by
    1e-4, under 0.03 of an 8-bit code value after the sRGB encoding).
    """

    #: The EV100 change below which a kept image is shown again.
    EXPOSURE_HOLD_EV = 1.4e-4

    def __init__(self, ctx):
        self.ctx = ctx
        self.texture = None
        self.scale: float | None = None
        self.luminance: float | None = None
        self._view: tuple | None = None
        self._display: tuple | None = None
        self._exposure = None
        self._generation: int | None = None
        self._graph = None
        self._state = None
        self._target = None  # (size, texture, framebuffer)
        #: The size (w, h) the kept float frame was drawn at when it is a moving view's
        #: reduced frame (dynamic resolution), else None.
        self.reduced_size: tuple[int, int] | None = None

    def same_view(self, graph, state, view: tuple, size: tuple[int, int]) -> bool:
        """Whether the kept frame is of this view (at any resolution; drawn with the
        targets as they are)."""
        return (
            self.texture is not None
            and graph is self._graph
            and state is self._state
            and graph.generation == self._generation
            and (view, size) == self._view
        )

    def holds_view(self, graph, state, view: tuple, size: tuple[int, int]) -> bool:
        """Whether the kept float texture is the frame of this view (and no layer is still
        settling over frames: the clouds' interactive accumulation)."""
        return (
            self.texture is not None
            and self.reduced_size is None
            and not any(getattr(la, "settling", False) for la in graph.layers if la.enabled)
            and graph is self._graph
            and state is self._state
            and graph.generation == self._generation
            and (view, size) == self._view
        )

    def keep_view(
        self, graph, state, view: tuple, size: tuple[int, int], texture, *, reduced=None
    ) -> None:
        """``texture`` (just drawn by ``graph``) is the frame of this view (``reduced``: at
        that reduced size (w, h), a moving view's); the kept image is not its tone map."""
        self.reduced_size = None if reduced is None else tuple(reduced)
        self._graph, self._state, self._view = graph, state, (view, size)
        self.texture = texture
        self._generation = graph.generation
        self._display = None

    def holds_display(self, display: tuple, exposure) -> bool:
        """Whether the kept image is the kept view's under these display settings."""
        if self._display != display:
            return False
        if isinstance(exposure, str) or isinstance(self._exposure, str):
            return exposure == self._exposure
        return abs(float(exposure) - float(self._exposure)) < self.EXPOSURE_HOLD_EV

    def keep_display(
        self, display: tuple, exposure, scale, luminance, graph, *, kept: bool = True
    ) -> None:
        """The kept view was tone-mapped with these settings (the exposure scale used and
        the measured log-average luminance, cd/m^2, when known) into the kept image, or
        (``kept`` False) elsewhere: the kept image is then not its. The post passes left
        the float texture as it was."""
        self._display = display if kept else None
        self._exposure = exposure
        self.scale, self.luminance = scale, luminance
        self._generation = graph.generation

    def target(self, size: tuple[int, int]):
        """The 8-bit framebuffer (RGBA8, GL rows) the image is kept in, of ``size``."""
        if self._target is None or self._target[0] != size:
            self._release_target()
            tex = self.ctx.texture(size, 4, dtype="f1")
            self._target = (size, tex, self.ctx.framebuffer(color_attachments=[tex]))
        return self._target[2]

    def show(self, framebuffer, size: tuple[int, int]) -> None:
        """Copy the kept image into ``framebuffer`` (a window's screen) over ``size``, and
        leave ``framebuffer`` bound (what is drawn next, the panel, goes over it)."""
        framebuffer.viewport = (0, 0, *size)
        self.ctx.copy_framebuffer(framebuffer, self._target[2])
        framebuffer.use()

    def _release_target(self) -> None:
        if self._target is not None:
            self._target[2].release()
            self._target[1].release()
            self._target = None

    def release(self) -> None:
        """Free the 8-bit target; forget the kept frame."""
        self._release_target()
        self.texture = self._graph = self._state = self._view = self._display = None
        self.reduced_size = None


def _separation_deg(a, b) -> float:
    """The angle (deg) between two bodies' apparent directions (elevation, azimuth)."""
    e1, a1 = math.radians(a.elevation_deg), math.radians(a.azimuth_deg)
    e2, a2 = math.radians(b.elevation_deg), math.radians(b.azimuth_deg)
    c = math.sin(e1) * math.sin(e2) + math.cos(e1) * math.cos(e2) * math.cos(a1 - a2)
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))
