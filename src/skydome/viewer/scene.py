"""The Sky a viewer shows: one frame graph (layers and tables) following a ``Controls``.

:class:`ViewerScene` turns the controls' :class:`~skydome.viewer.controls.ViewState` into
a ``Sky`` at that time and place (a new SkyState only when the time or the place changed),
keeps the display settings and the layers' switches in step, runs the exposure modes (auto,
EV, an eye adapting over time) and draws a frame or renders the same frame for a
screenshot. It swaps in a new atmosphere (from ``viewer.rebuild``) between two frames. The
window and the notebook widget both use it.
"""

from __future__ import annotations

from typing import Any

from skydome.errors import ParameterError
from skydome.render.frame import Frame
from skydome.scene.sky import Sky
from skydome.viewer.controls import Controls, ViewState

#: The most the Sun or the Moon may move (deg) before a new time is drawn: a tenth of
#: their disks' diameter (less when half a pixel of the view is less).
HOLD_MAX_DEG = 0.05


def initial_state(sky: Sky, **overrides: Any) -> ViewState:
    """A ViewState for ``sky``'s place and time, the camera on what ``skydome render``
    would look at (the Sun, or at night the Moon when it is up, else south); then
    ``overrides`` (ViewState fields)."""
    from skydome.scene.sky import default_look

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
        from skydome.display.adaptation import EyeAdaptation

        self.base = sky
        self.controls = controls or Controls(initial_state(sky))
        self.eye = EyeAdaptation()
        self._key: tuple | None = None
        self._sky: Sky | None = None
        self._observer_key: tuple | None = None
        self._observer = sky.observer
        self._pending = None
        #: The width (pixels) of the view drawn, for the half-pixel hold of :meth:`sky`.
        self.view_width_px: int | None = None
        #: The exposure (EV100) of the last frame drawn, and its tone map.
        self.last_ev100: float | None = None

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
            from skydome.astro import Observer

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
                self._sky = self.base.with_sun(s.sun_elevation_deg, s.sun_azimuth_deg)
            else:
                from skydome.astro.time import Time
                from skydome.scene.state import SkyState

                state = self._pending or SkyState.at_place(self.observer(), Time.from_utc(s.jd_utc))
                self._sky = Sky(_graph=self.base.graph, _state=state)
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
        import numpy as np

        from skydome.astro.time import Time
        from skydome.scene.state import SkyState

        self._pending = None
        s = self.controls.state
        if not s.playing or self._sky is None or self._key is None or self._key[1:] != key[1:]:
            return False
        state = SkyState.at_place(self.observer(), Time.from_utc(s.jd_utc))
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

    def _aim(self, sky: Sky, look: str) -> None:
        light = sky.state.sun if look == "sun" else sky.state.moon
        if light is not None:
            self.controls.look_at(light.elevation_deg, light.azimuth_deg)

    def look_at(self, body: str) -> None:
        """Aim the camera at the Sun or the Moon ("sun" or "moon") of the current time."""
        if body not in ("sun", "moon"):
            raise ParameterError(f"look_at {body!r} must be 'sun' or 'moon'")
        self._aim(self.sky(), body)

    def jump(self, kind: str) -> bool:
        """Set the time to the next ``kind`` (``viewer.jumps.JUMPS``: sunrise, sunset,
        moonrise, moonset, full_moon); False when there is none ahead (or no place)."""
        from skydome.viewer.jumps import next_event

        s = self.controls.state
        if s.abstract:
            return False
        jd = next_event(self.observer(), s.jd_utc, kind)
        if jd is None:
            return False
        self.controls.set(jd_utc=jd)
        return True

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
            from skydome.display.exposure import scale_to_ev100

            return scale_to_ev100(self.eye.exposure_scale(0.0)), s.compensation_ev
        return "auto", s.compensation_ev

    # ------------------------------------------------------------------ frames

    def draw(self, framebuffer, size: tuple[int, int], dt_s: float = 0.0) -> None:
        """Draw the state's frame into ``framebuffer`` over ``size`` (w, h) pixels,
        tone-mapped; in the adapt mode, then let the eye adapt for ``dt_s`` real seconds to
        what it measured. The auto exposure is read back (one texel) and applied as a fixed
        scale, as ``Sky.render`` does: cheaper per pixel on a CPU rasterizer."""
        from skydome.display.exposure import scale_to_ev100

        s = self.controls.state
        self.view_width_px = int(size[0])
        sky = self.sky()
        exposure, comp = self.exposure()
        adapt = s.exposure_mode == "adapt"
        scale = sky.draw(
            framebuffer,
            s.camera(),
            size=size,
            altitude_m=self.altitude_m(),
            exposure=exposure,
            compensation_ev=comp,
            tonemap=s.tonemap,
            measure=adapt,
            read_back=True,
        )
        if adapt:
            luminance = sky.graph.exposure_pass().read()
            self.eye.update(min(luminance, 1e12), max(float(dt_s), 0.0))
        #: The EV100 of the exposure applied (compensation included).
        self.last_ev100 = None if scale is None else scale_to_ev100(scale)

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
            old.graph.release()

    def release(self) -> None:
        """Free the GPU resources of the sky shown."""
        self.base.graph.release()
