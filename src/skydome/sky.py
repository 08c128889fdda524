"""Sky: a place, a time and layers, rendered by one frame graph.

>>> from skydome import Sky
>>> sky = Sky("Valletta", "2018-03-01T19:00Z")          # or Sky((35.9, 14.5), ...)
>>> frame = sky.render(width=1280, height=720, look="moon")   # Frame in cd/m^2
>>> later = sky.at("2018-03-01T23:00Z")                 # same tables, new lights

The abstract mode has no place or time, only a Sun: ``Sky(sun_elevation_deg=5,
sun_azimuth_deg=250)``. A Sky is made from a frozen :class:`~skydome.description.SkyDescription`
(``Sky(description)``, or the same settings as keywords); it holds GPU memory until
:meth:`Sky.release`, the end of a ``with`` block, or its garbage collection.
"""

from __future__ import annotations

import weakref
from typing import Any

from skydome.clouds.layer import CloudLayer
from skydome.core.cameras import MAX_ALTITUDE_M, Camera, EquirectCamera, PerspectiveCamera
from skydome.core.frame import Frame
from skydome.core.layer import Layer
from skydome.core.lights import SkyState
from skydome.description import NIGHT_LAYERS, SkyDescription
from skydome.display.exposure import COMPENSATION_RANGE, DEFAULT_METERING, ev100_to_scale
from skydome.display.glare import DEFAULT_GLARE
from skydome.errors import ParameterError, check_range
from skydome.lighting import DEFAULT_LIGHTS, Lighting, sky_lighting
from skydome.lighting import DEFAULT_SIZE as DEFAULT_LIGHTING_SIZE
from skydome.night.glow_layer import LightPollutionLayer
from skydome.scene.graph import FrameGraph

__all__ = ["EYE_HEIGHT_M", "LOOKS", "NIGHT_LAYERS", "Sky", "aim_camera", "default_look"]

#: Height of the eye above the ground at the place (m): a standing observer.
EYE_HEIGHT_M = 1.7
#: Where ``look=`` can aim the default camera.
LOOKS = ("sun", "moon", "antisun", "zenith", "north", "east", "south", "west")
_COMPASS = {"north": 0.0, "east": 90.0, "south": 180.0, "west": 270.0}


def aim_camera(
    state: SkyState, look: str = "sun", *, fov_deg: float = 90.0, pitch_deg: float | None = None
) -> PerspectiveCamera:
    """A perspective camera aimed by ``look``: at the Sun or the Moon (centred on it), at the
    antisolar point (opposite the Sun: the centre of the rainbows and the glory), at the
    zenith, or at a compass point (pitch 15 deg unless given)."""
    if look not in LOOKS:
        raise ParameterError(f"look {look!r} must be one of {', '.join(LOOKS)}")
    if look in ("sun", "moon"):
        light = state.sun if look == "sun" else state.moon
        if light is None:
            raise ParameterError("this sky has no Moon (the abstract mode has a Sun only)")
        yaw, pitch = light.azimuth_deg, light.elevation_deg
    elif look == "antisun":
        yaw, pitch = (state.sun.azimuth_deg + 180.0) % 360.0, -state.sun.elevation_deg
    elif look == "zenith":
        yaw, pitch = 0.0, 90.0
    else:
        yaw, pitch = _COMPASS[look], 15.0
    if pitch_deg is not None:
        pitch = pitch_deg
    return PerspectiveCamera(fov_deg=fov_deg, yaw_deg=yaw, pitch_deg=pitch)


def exposure_scale(exposure, compensation_ev: float):
    """The frame graph's exposure from a Sky's: "auto" and None as they are, an EV100 number
    as its scale (m^2/cd); the compensation checked."""
    check_range("exposure compensation", compensation_ev, *COMPENSATION_RANGE, "EV")
    return exposure if exposure is None or exposure == "auto" else ev100_to_scale(exposure)


def check_camera(camera, optional: bool = False) -> None:
    """ParameterError unless ``camera`` is a Camera (or None when ``optional``)."""
    if not isinstance(camera, Camera) and not (optional and camera is None):
        raise ParameterError(
            f"camera must be a skydome camera (PerspectiveCamera, FisheyeCamera, EquirectCamera, "
            f"CubemapCamera or DirectionsCamera), got {camera!r}"
        )


def default_look(state: SkyState) -> str:
    """What a camera looks at when nothing else is said: the Sun while it is up or in
    twilight (above -6 deg), else the Moon when it is up, else the zenith."""
    if state.sun.elevation_deg > -6.0 or state.moon is None:
        return "sun"
    return "moon" if state.moon.elevation_deg > 0.0 else "zenith"


def _placed(layers: list[Layer], extra: list[Layer]) -> list[Layer]:
    """``layers`` with ``extra`` added: a cloud layer just after the atmosphere (clouds lie
    nearer than the air beyond them), the others at the end."""
    out = list(layers)
    for layer in extra:
        names = [la.name for la in out]
        if isinstance(layer, CloudLayer):
            if "atmosphere" not in names:
                raise ParameterError("clouds need an atmosphere layer in the same sky")
            out.insert(names.index("atmosphere") + 1, layer)
        else:
            out.append(layer)
    return out


def _fresh(layer: Layer) -> Layer:
    """A new, unprepared copy of ``layer`` (its constructor's arguments), enabled as it is."""
    return layer.fresh()


class Sky:
    """The sky over a place at a time, or of a Sun at an elevation (the abstract mode).

    Args:
        place: a :class:`~skydome.description.SkyDescription` (then no other settings), an
            ``Observer``, a gazetteer name (``skydome places``), a ``Place`` or a
            ``(lat_deg, lon_deg[, elevation_m])`` tuple; None for the abstract mode.
        time: anything ``skydome.astro.to_time`` accepts: ISO 8601 with an offset or Z, or
            without one the local time of a gazetteer place (its IANA ``timezone``: ``Sky(
            "Valletta", "2018-03-01T20:00")`` is 19:00 UTC), UTC for a position given as
            numbers, an ``Observer``, or with ``utc=True``.
        atmosphere: a preset name or ``AtmosphereParams``.
        sun_elevation_deg, sun_azimuth_deg: the abstract mode's Sun (apparent, degrees).
        pressure_hPa, temperature_C: the weather that bends the light (refraction).
        model: "precomputed" (every scattering order, the default) or "single".
        config: the atmosphere tables' ``PrecomputeConfig``; ``samples``: the single
            model's samples per view ray.
        night: with a place, draw the night sky (stars, planets, Milky Way, zodiacal light,
            airglow).
        light_pollution: "auto" (the default: a gazetteer city's glow estimated from its
            population, an observatory's Bortle class; none for a position given as numbers:
            ``skydome.description.auto_light_pollution``), None (none), a Bortle class
            (1-9), a ``skydome.LightPollution``, or a ``LightPollutionLayer``.
        clouds: a preset name ("fair", "broken", "overcast", "nimbostratus", "storm",
            "cirrus", "clear"), a
            ``skydome.Clouds`` or a ``CloudLayer``: drawn just after the atmosphere.
        night_vision: show the image as a dark-adapted eye sees it (display only).
        overlays: names of ``skydome.display.overlays.OVERLAYS`` ("lines", "labels",
            "grid") or a comma list, drawn over the image (display only).
        layers: the layers to draw instead of the description's; ``extra_layers`` adds to
            them.
        progress: ``progress(stage, fraction)`` while tables are precomputed.
        ctx: a moderngl context (default: the shared headless one; a window's for a viewer).

    A Sky owns its frame graph and layers; the atmosphere's tables and the clouds' noise
    behind them are shared with every other Sky of the same context that needs the same
    ones (the layers' small textures and their shaders are made again: about 30 ms of
    compiling on a CPU rasterizer, with the driver's shader cache).
    ``release()`` (or ``with Sky(...) as sky:``) frees its GPU memory now; garbage
    collection does it otherwise.
    """

    def __init__(
        self,
        place: Any = None,
        time: Any = None,
        atmosphere: Any = "earth",
        *,
        layers: list[Layer] | None = None,
        extra_layers: list[Layer] = (),
        progress=None,
        ctx=None,
        clouds: Any = None,
        light_pollution: Any = "auto",
        **settings: Any,
    ):
        extra = list(extra_layers)
        if isinstance(clouds, CloudLayer):
            extra.append(clouds)
            clouds = None
        if isinstance(light_pollution, LightPollutionLayer):
            extra.append(light_pollution)
            light_pollution = None
        if isinstance(light_pollution, str) and light_pollution == "auto":
            if layers is not None or isinstance(place, SkyDescription):
                light_pollution = None  # the layers, or the description, say it all
        if layers is not None and (clouds is not None or light_pollution is not None):
            raise ParameterError(
                "light_pollution and clouds add to the default layers: with layers=[...] add "
                "a LightPollutionLayer or a CloudLayer yourself"
            )
        if isinstance(place, SkyDescription):
            given = [
                k
                for k, v in (
                    ("time", time),
                    ("clouds", clouds),
                    ("light_pollution", light_pollution),
                )
                if v is not None
            ]
            if given or settings or atmosphere != "earth":
                raise ParameterError(
                    "give a SkyDescription alone, or settings as keywords: not both"
                )  # fmt: skip
            description = place
        else:
            description = SkyDescription.of(
                place, time, atmosphere, clouds=clouds, light_pollution=light_pollution,
                **settings,
            )  # fmt: skip
        if layers is None:
            layers = description.layers(progress)
        layers = _placed(list(layers), extra)
        self.description = description
        self.state = description.state()
        self.graph = FrameGraph(layers, ctx=ctx)
        self.graph.set_display(night_vision=description.night_vision, overlays=description.overlays)
        # GPU memory goes with the Sky: released by release(), a with block, or when the Sky
        # is garbage collected (not at exit, when the context may be gone).
        self._finalizer = weakref.finalize(self, self.graph.release)
        self._finalizer.atexit = False
        self._view_of: Sky | None = None

    @classmethod
    def _view(cls, sky: Sky, state: SkyState) -> Sky:
        """A Sky drawing ``sky``'s graph at another ``state`` (for a window that moves the
        time every frame): it shares the graph and its settings, and owns nothing."""
        view = cls.__new__(cls)
        view.description, view.state, view.graph = sky.description, state, sky.graph
        view._finalizer = None
        view._view_of = sky
        return view

    # ------------------------------------------------------------------ lifetime

    def release(self) -> None:
        """Free this sky's GPU memory now (its targets, passes and layers; shared tables
        and textures when no other sky holds them). The sky cannot draw afterwards."""
        if self._finalizer is not None:
            self._finalizer()

    @property
    def released(self) -> bool:
        """True once :meth:`release` has freed this sky's GPU memory (or, for a view of
        another sky, once that one has)."""
        if self._view_of is not None:
            return self._view_of.released
        return not self._finalizer.alive

    def _check_alive(self) -> None:
        if self.released:
            raise ParameterError("this sky was released: make a new one (Sky(...)) to draw")

    def __enter__(self) -> Sky:
        return self

    def __exit__(self, *exc) -> None:
        self.release()

    # ------------------------------------------------------------------ display

    @property
    def observer(self):
        """The place (an ``Observer``), None in the abstract mode."""
        return self.description.observer

    @property
    def night_vision(self) -> bool:
        """Whether images show night vision (``sky.night_vision = True`` turns it on)."""
        return self.graph.night_vision

    @night_vision.setter
    def night_vision(self, on: bool) -> None:
        self.graph.set_display(night_vision=on)

    @property
    def overlays(self) -> tuple[str, ...]:
        """The overlays drawn over images (``sky.overlays = "lines,grid"``)."""
        return self.graph.overlays

    @overlays.setter
    def overlays(self, names) -> None:
        self.graph.set_display(overlays=names)

    # ------------------------------------------------------------------ the sky at other times

    def at(self, time: Any) -> Sky:
        """The same sky at another ``time``: a new Sky with its own layers and settings (the
        layers on and off, night vision and overlays as this one's now), sharing this one's
        atmosphere tables and cloud noise, and its atmosphere layer's compiled passes and
        sky-view tables: a light that moved in azimuth alone, or in elevation by less than
        ``atmosphere.sky_view.REAIM_*``, keeps its table; the Moon's disk integrals follow
        when the geometry they were taken for still holds (``celestial.moon``)."""
        if self.observer is None:
            raise ParameterError("an abstract sky (a Sun elevation) has no time: make a new Sky")
        return self._remade(self.description.with_(time=time))

    def with_sun(self, elevation_deg: float, azimuth_deg: float = 180.0) -> Sky:
        """The same air lit by a Sun alone at an apparent elevation and azimuth (deg): a new
        Sky (the abstract mode), sharing this one's tables."""
        d = self.description.with_(
            observer=None, time=None, sun_elevation_deg=elevation_deg,
            sun_azimuth_deg=azimuth_deg, light_pollution=None,
        )  # fmt: skip
        keep = [la for la in self.layers if la.name not in ("moon", *NIGHT_LAYERS)]
        keep = [la for la in keep if not isinstance(la, LightPollutionLayer)]
        return self._remade(d, keep)

    def _remade(self, description: SkyDescription, layers: list[Layer] | None = None) -> Sky:
        layers = [_fresh(la) for la in (self.layers if layers is None else layers)]
        sky = Sky(description, layers=layers, ctx=self.graph.ctx)
        sky.graph.set_display(
            night_vision=self.graph.night_vision, overlays=self.graph.overlays,
            seed=self.graph.night_vision_seed,
        )  # fmt: skip
        return sky

    # ------------------------------------------------------------------ layers

    @property
    def layers(self) -> list[Layer]:
        return self.graph.layers

    def layer(self, name: str) -> Layer:
        """A layer by name (``sky.layer("moon").enabled = False`` turns it off)."""
        try:
            return self.graph[name]
        except KeyError:
            names = ", ".join(la.name for la in self.layers)
            raise ParameterError(f"no layer {name!r} in this sky; it has {names}") from None

    # ------------------------------------------------------------------ cameras

    def camera(self, look: str = "sun", *, fov_deg: float = 90.0, pitch_deg: float | None = None):
        """A perspective camera aimed by ``look`` (see :func:`aim_camera`)."""
        return aim_camera(self.state, look, fov_deg=fov_deg, pitch_deg=pitch_deg)

    def altitude_m(self, altitude_m: float | None = None) -> float:
        """The camera's height above the atmosphere's ground (m): given, or the place's
        elevation plus a standing eye (EYE_HEIGHT_M)."""
        if altitude_m is not None:
            return check_range("altitude_m", altitude_m, 0.0, MAX_ALTITUDE_M, "m")
        ground = 0.0 if self.observer is None else max(float(self.observer.elevation_m), 0.0)
        return ground + EYE_HEIGHT_M

    # ------------------------------------------------------------------ frames

    def render(
        self,
        camera: Camera | None = None,
        width: int = 1280,
        height: int = 720,
        *,
        look: str | None = None,
        altitude_m: float | None = None,
        exposure: str | float | None = "auto",
        compensation_ev: float = 0.0,
        tonemap: str | None = None,
        depth_m=None,
        shadow_length_m=None,
        metering: str = DEFAULT_METERING,
        glare: str | None = DEFAULT_GLARE,
        supersample: int = 1,
    ) -> Frame:
        """A frame in cd/m^2 (read back once). Without a ``camera``, a 90 deg perspective one
        aimed by ``look`` (:func:`aim_camera`; default: :func:`default_look`). ``exposure``:
        "auto" (GPU log-average), an
        EV100 number, or None; with ``tonemap`` (e.g. "filmic") ``frame.image`` holds the
        uint8 sRGB image. ``frame.info`` says where the lights were and what was used.

        ``depth_m``: an (H, W) image of distances (m) to a scene of yours along each ray
        (<= 0 or +inf where there is none): in front of it the frame holds the light the air
        scatters, and ``frame.info["transmittance"]`` the (H, W, 3) RGB transmittance to
        it, so that ``scene * transmittance + frame`` is your scene seen through the air
        (aerial perspective). ``shadow_length_m``: an (H, W) image of the length (m) of each
        ray, from the camera, in the shadow of something of yours (light shafts).

        ``metering`` (how "auto" measures): "average" (every pixel, key 0.18), "center"
        (centre-weighted), "spot" (the central 2.5 % of the frame: what the camera looks
        at), or "eye" (default: the key of a dark-adapted observer, which falls below
        1.25 cd/m^2 (Krawczyk et al. 2005), and the eye's mesopic colours below 5 cd/m^2;
        brighter scenes as "average"). ``glare``: "eye" (default: the eye's point spread
        function, CIE 146:2002), "lens" (a camera lens's veiling glare) or "off"; on the
        image only, ``frame.data`` is the same.

        ``supersample`` (1-4): n x n rays a pixel, each pixel their mean (n^2 times the
        work): for stills where detail is finer than a pixel, above all clouds near the
        horizon, which one ray a pixel shows as a speckle of lit and shaded cloud."""
        self._check_alive()
        check_camera(camera, optional=True)
        cam = camera or self.camera(look or default_look(self.state))
        scale = exposure_scale(exposure, compensation_ev)
        frame = self.graph.render(
            self.state,
            cam,
            width,
            height,
            altitude_m=self.altitude_m(altitude_m),
            exposure=scale,
            compensation_ev=compensation_ev,
            tonemap=tonemap,
            depth_m=depth_m,
            shadow_length_m=shadow_length_m,
            metering=metering,
            glare=glare,
            supersample=supersample,
        )
        frame.info.update(self.state.summary())
        if self.state.time is not None:
            frame.info["time"] = str(self.state.time.iso())
        if self.description.weather is not None:
            frame.info.update(self.description.weather.summary())
            frame.info["visibility_km"] = self.description.visibility_km
        return frame

    def draw(
        self,
        framebuffer,
        camera: Camera,
        *,
        size: tuple[int, int] | None = None,
        altitude_m: float | None = None,
        exposure: str | float = "auto",
        compensation_ev: float = 0.0,
        tonemap: str = "filmic",
        measure: bool = False,
        read_back: bool = False,
        metering: str = DEFAULT_METERING,
        glare: str | None = DEFAULT_GLARE,
    ) -> float | None:
        """Draw into ``framebuffer`` (e.g. a window's ``ctx.screen``), tone-mapped on the GPU,
        with no read-back. ``exposure``: "auto" or an EV100 number; with ``measure`` an EV
        frame's log-average luminance is measured too (``graph.exposure_pass().read()``,
        cd/m^2: for an eye adapting over time); with "auto" and ``read_back`` the measured
        exposure is read back and applied as a fixed scale (cheaper on a CPU rasterizer).
        ``metering`` and ``glare`` as in :meth:`render`. Returns the exposure scale used (m^2/cd, compensation included) when known on the
        CPU, else None."""
        self._check_alive()
        check_camera(camera)
        scale = exposure_scale(exposure, compensation_ev)
        return self.graph.draw(
            self.state,
            framebuffer,
            camera,
            altitude_m=self.altitude_m(altitude_m),
            size=size,
            exposure=scale,
            compensation_ev=compensation_ev,
            tonemap=tonemap,
            measure=measure,
            read_back=read_back,
            metering=metering,
            glare=glare,
        )

    def lighting(
        self, size: tuple[int, int] = DEFAULT_LIGHTING_SIZE, n_lights: int = DEFAULT_LIGHTS
    ) -> Lighting:
        """What lights a 3D scene under this sky now (:mod:`skydome.lighting`): the Sun and
        the Moon as lights (direction, angular radius, RGB illuminance at the ground), the
        sky's irradiance as 9 spherical-harmonic coefficients (lx) and ``n_lights``
        directional lights, measured on equirect maps of ``size`` (width, height; 2:1)."""
        self._check_alive()
        return sky_lighting(self, size, n_lights)

    def _repr_png_(self) -> bytes:
        """A small tone-mapped equirect view, for Jupyter."""
        import io

        from PIL import Image

        frame = self.render(EquirectCamera(), 512, 256, tonemap="filmic")
        buf = io.BytesIO()
        Image.fromarray(frame.image).save(buf, format="PNG")
        return buf.getvalue()

    def __repr__(self) -> str:
        s = self.state
        where = (
            "abstract"
            if self.observer is None
            else (f"{float(self.observer.latitude):.4f}, {float(self.observer.longitude):.4f}")
        )
        when = "" if s.time is None else f" at {s.time.iso()}"
        sun = f"Sun {s.sun.elevation_deg:.2f} deg"
        moon = "" if s.moon is None else f", Moon {s.moon.elevation_deg:.2f} deg"
        return f"<Sky {where}{when}: {sun}{moon}; layers {[la.name for la in self.layers]}>"
