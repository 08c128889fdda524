"""Sky: a place, a time and a list of layers, rendered by one frame graph.

>>> from skydome import Sky
>>> sky = Sky("Valletta", "2018-03-01T19:00Z")          # or Sky((35.9, 14.5), ...)
>>> frame = sky.render(width=1280, height=720, look="moon")   # Frame in cd/m^2
>>> later = sky.at("2018-03-01T23:00Z")                 # same tables, new lights

The abstract mode has no place or time, only a Sun: ``Sky(sun_elevation_deg=5,
sun_azimuth_deg=250)``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from skydome.errors import ParameterError, check_range
from skydome.render.cameras import Camera, PerspectiveCamera
from skydome.render.frame import Frame
from skydome.scene.graph import FrameGraph
from skydome.scene.layer import Layer
from skydome.scene.state import SkyState

#: Height of the eye above the ground at the place (m): a standing observer.
EYE_HEIGHT_M = 1.7
#: Where ``look=`` can aim the default camera.
LOOKS = ("sun", "moon", "zenith", "north", "east", "south", "west")
_COMPASS = {"north": 0.0, "east": 90.0, "south": 180.0, "west": 270.0}


def observer_for(place: Any, **weather):
    """An ``Observer`` for a place: an Observer, a ``Place`` of the gazetteer, a place name,
    or ``(lat, lon[, elevation_m])``."""
    from skydome.astro import Observer

    if isinstance(place, Observer):
        return place
    from skydome.astro.places import parse_place

    return parse_place(place).observer(**weather)


def aim_camera(
    state: SkyState, look: str = "sun", *, fov_deg: float = 90.0, pitch_deg: float | None = None
) -> PerspectiveCamera:
    """A perspective camera aimed by ``look``: at the Sun or the Moon (centred on it), at the
    zenith, or at a compass point (pitch 15 deg unless given)."""
    if look not in LOOKS:
        raise ParameterError(f"look {look!r} must be one of {', '.join(LOOKS)}")
    if look in ("sun", "moon"):
        light = state.sun if look == "sun" else state.moon
        if light is None:
            raise ParameterError("this sky has no Moon (the abstract mode has a Sun only)")
        yaw, pitch = light.azimuth_deg, light.elevation_deg
    elif look == "zenith":
        yaw, pitch = 0.0, 90.0
    else:
        yaw, pitch = _COMPASS[look], 15.0
    if pitch_deg is not None:
        pitch = pitch_deg
    return PerspectiveCamera(fov_deg=fov_deg, yaw_deg=yaw, pitch_deg=pitch)


def _exposure_scale(exposure, compensation_ev: float):
    """The frame graph's exposure from a Sky's: "auto" and None as they are, an EV100 number
    as its scale (m^2/cd); the compensation checked."""
    from skydome.display.exposure import COMPENSATION_RANGE, ev100_to_scale

    check_range("exposure compensation", compensation_ev, *COMPENSATION_RANGE, "EV")
    return exposure if exposure is None or exposure == "auto" else ev100_to_scale(exposure)


#: The layers of the night sky a Sky with a place has (in this order, before the air).
NIGHT_LAYERS = ("stars", "planets", "milky_way", "zodiacal_light", "airglow")


def light_pollution_layer(light_pollution: Any) -> Layer | None:
    """The light-pollution layer for ``light_pollution``: None (none), a Bortle class (int
    1-9), a ``LightPollution`` model or a ``LightPollutionLayer``."""
    if light_pollution is None:
        return None
    from skydome.night.glow_layer import LightPollutionLayer
    from skydome.night.light_pollution import LightPollution

    if isinstance(light_pollution, LightPollutionLayer):
        return light_pollution
    if isinstance(light_pollution, LightPollution):
        return LightPollutionLayer(light_pollution)
    if isinstance(light_pollution, (int, np.integer)) and not isinstance(light_pollution, bool):
        return LightPollutionLayer.from_bortle(int(light_pollution))
    raise ParameterError(
        f"light_pollution {light_pollution!r} must be a Bortle class 1-9, a LightPollution "
        "or a LightPollutionLayer"
    )


def default_layers(
    atmosphere_layer: Layer, *, night: bool = True, light_pollution: Any = None
) -> list[Layer]:
    """A sky's layers: the Sun and the Moon; with ``night``, the stars, the planets, the
    Milky Way, the zodiacal light and the airglow; the atmosphere; the light pollution."""
    from skydome.celestial.moon import MoonLayer
    from skydome.celestial.sun import SunLayer

    layers: list[Layer] = [SunLayer(), MoonLayer()]
    if night:
        from skydome.celestial.milky_way import MilkyWayLayer
        from skydome.celestial.planets import PlanetsLayer
        from skydome.celestial.stars import StarsLayer
        from skydome.night.glow_layer import AirglowLayer, ZodiacalLightLayer

        layers += [
            StarsLayer(),
            PlanetsLayer(),
            MilkyWayLayer(),
            ZodiacalLightLayer(),
            AirglowLayer(),
        ]
    layers.append(atmosphere_layer)
    glow = light_pollution_layer(light_pollution)
    if glow is not None:
        layers.append(glow)
    return layers


def cloud_layer(clouds: Any, quality: str = "full") -> Layer | None:
    """The cloud layer for ``clouds``: None (none), a preset name, a ``Clouds`` or a
    ``CloudLayer``."""
    if clouds is None:
        return None
    from skydome.clouds.layer import CloudLayer
    from skydome.clouds.params import Clouds

    if isinstance(clouds, CloudLayer):
        return clouds
    if isinstance(clouds, (str, Clouds)):
        return CloudLayer(clouds, quality=quality)
    raise ParameterError(f"clouds {clouds!r} must be a preset name, a Clouds or a CloudLayer")


def default_look(state: SkyState) -> str:
    """What a camera looks at when nothing else is said: the Sun while it is up or in
    twilight (above -6 deg), else the Moon when it is up, else the zenith."""
    if state.sun.elevation_deg > -6.0 or state.moon is None:
        return "sun"
    return "moon" if state.moon.elevation_deg > 0.0 else "zenith"


class Sky:
    """The sky over a place at a time, or of a Sun at an elevation (the abstract mode).

    Args:
        place: an ``Observer``, a gazetteer name (``skydome places``), a ``Place`` or a
            ``(lat_deg, lon_deg[, elevation_m])`` tuple. None for the abstract mode.
        time: anything ``skydome.astro.to_time`` accepts (ISO 8601; naive is UTC).
        atmosphere: a preset name or ``AtmosphereParams``.
        sun_elevation_deg, sun_azimuth_deg: the abstract mode's Sun (apparent, degrees).
        layers: the layers to draw (default: :func:`default_layers`: with a place, the night
            sky too); a list of ``Layer`` objects replaces them, ``extra_layers`` adds to
            them.
        night: with a place and the default layers, draw the night sky (stars, planets,
            Milky Way, zodiacal light, airglow); the abstract mode has none.
        light_pollution: a Bortle class (1-9), a ``skydome.night.LightPollution`` or None.
        clouds: a preset name ("fair", "overcast", "storm", "cirrus", "clear"), a
            ``skydome.Clouds`` or a ``CloudLayer``: drawn just after the atmosphere.
        night_vision: show the image as a dark-adapted eye sees it (display only).
        overlays: names of ``skydome.display.overlays.OVERLAYS`` ("lines", "labels",
            "grid") or a comma list, drawn over the image (display only).
        config: the atmosphere tables' ``PrecomputeConfig``.
        progress: ``progress(stage, fraction)`` while tables are precomputed.
        ctx: a moderngl context (default: the shared headless one; a window's for a viewer).
        pressure_hPa, temperature_C: the weather that bends the light (refraction).
    """

    def __init__(
        self,
        place: Any = None,
        time: Any = None,
        atmosphere: Any = "earth",
        *,
        sun_elevation_deg: float | None = None,
        sun_azimuth_deg: float = 180.0,
        layers: list[Layer] | None = None,
        extra_layers: list[Layer] = (),
        config=None,
        progress=None,
        ctx=None,
        pressure_hPa: float | None = None,
        temperature_C: float | None = None,
        night: bool = True,
        light_pollution: Any = None,
        clouds: Any = None,
        night_vision: bool = False,
        overlays: Any = (),
        _graph: FrameGraph | None = None,
        _state: SkyState | None = None,
    ):
        if _graph is not None:  # from at(): the same layers, a new state
            self.graph, self.state, self.observer = _graph, _state, _state.observer
            return
        abstract = place is None
        if abstract and time is not None:
            raise ParameterError("a time needs a place: give place=(lat, lon) or a place name")
        if abstract and sun_elevation_deg is None:
            raise ParameterError("give a place and a time, or sun_elevation_deg for a Sun alone")
        if not abstract and sun_elevation_deg is not None:
            raise ParameterError(
                "a place and a time set the Sun: drop sun_elevation_deg, or drop the place"
            )
        weather = {}
        if pressure_hPa is not None:
            weather["pressure_hPa"] = pressure_hPa
        if temperature_C is not None:
            weather["temperature_C"] = temperature_C
        if abstract:
            self.observer = None
            self.state = SkyState.abstract(sun_elevation_deg, sun_azimuth_deg)
        else:
            if time is None:
                raise ParameterError("a place needs a time (ISO 8601, e.g. 2018-03-01T19:00Z)")
            self.observer = observer_for(place, **weather)
            self.state = SkyState.at_place(self.observer, time)
        if layers is None:
            from skydome.atmosphere.layer import AtmosphereLayer

            air = AtmosphereLayer(atmosphere, config=config, progress=progress)
            layers = default_layers(
                air, night=night and not abstract, light_pollution=light_pollution
            )
        elif light_pollution is not None:
            raise ParameterError(
                "light_pollution adds to the default layers: with layers=[...] add a "
                "LightPollutionLayer yourself"
            )
        layers = [*layers, *extra_layers]
        sky_clouds = cloud_layer(clouds)
        if sky_clouds is not None:
            names = [la.name for la in layers]
            if "atmosphere" not in names:
                raise ParameterError("clouds need an atmosphere layer in the same sky")
            layers.insert(names.index("atmosphere") + 1, sky_clouds)
        atmosphere_layer = next((la for la in layers if la.name == "atmosphere"), None)
        solar_scale = atmosphere_layer.params.solar_scale if atmosphere_layer is not None else 1.0
        self.graph = FrameGraph(layers, ctx=ctx, solar_scale=solar_scale)
        self.graph.set_display(night_vision=night_vision, overlays=overlays)

    # ------------------------------------------------------------------ display

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
        """The same sky (place, layers and their tables) at another ``time``."""
        if self.observer is None:
            raise ParameterError("an abstract sky (a Sun elevation) has no time: make a new Sky")
        return Sky(_graph=self.graph, _state=SkyState.at_place(self.observer, time))

    def with_sun(self, elevation_deg: float, azimuth_deg: float = 180.0) -> Sky:
        """The same layers with the abstract mode's Sun at an apparent elevation, azimuth."""
        return Sky(_graph=self.graph, _state=SkyState.abstract(elevation_deg, azimuth_deg))

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
            return float(altitude_m)
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
    ) -> Frame:
        """A frame in cd/m^2 (read back once). Without a ``camera``, a 90 deg perspective one
        aimed by ``look`` (:func:`aim_camera`; default: :func:`default_look`). ``exposure``:
        "auto" (GPU log-average), an
        EV100 number, or None; with ``tonemap`` (e.g. "filmic") ``frame.image`` holds the
        uint8 sRGB image. ``frame.info`` says where the lights were and what was used."""
        cam = camera or self.camera(look or default_look(self.state))
        scale = _exposure_scale(exposure, compensation_ev)
        frame = self.graph.render(
            self.state,
            cam,
            width,
            height,
            altitude_m=self.altitude_m(altitude_m),
            exposure=scale,
            compensation_ev=compensation_ev,
            tonemap=tonemap,
        )
        frame.info.update(self.state.summary())
        frame.info["camera"] = cam.name
        if self.state.time is not None:
            frame.info["time"] = str(self.state.time.iso())
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
    ) -> float | None:
        """Draw into ``framebuffer`` (e.g. a window's ``ctx.screen``), tone-mapped on the GPU,
        with no read-back. ``exposure``: "auto" or an EV100 number; with ``measure`` an EV
        frame's log-average luminance is measured too (``graph.exposure_pass().read()``,
        cd/m^2: for an eye adapting over time); with "auto" and ``read_back`` the measured
        exposure is read back and applied as a fixed scale (cheaper on a CPU rasterizer).
        Returns the exposure scale used (m^2/cd, compensation included) when known on the
        CPU, else None."""
        scale = _exposure_scale(exposure, compensation_ev)
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
        )

    def _repr_png_(self) -> bytes:
        """A small tone-mapped equirect view, for Jupyter."""
        import io

        from PIL import Image

        from skydome.render.cameras import EquirectCamera

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
