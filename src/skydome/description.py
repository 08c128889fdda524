"""One frozen description of a sky: what ``Sky``, the command line, the time-lapse and the
viewer's rebuild all build from.

>>> from skydome import SkyDescription, Sky
>>> d = SkyDescription.of("Valletta", "2018-03-01T19:00Z", clouds="fair", light_pollution=6)
>>> sky = Sky(d)
>>> later = Sky(d.with_(time="2018-03-01T23:00Z"))

A description holds values, never GL objects: a place (an ``Observer``) and a time, or a Sun
alone (the abstract mode); the air (``AtmosphereParams``, its model and tables); the night
sky, light pollution and clouds; the display settings. :meth:`SkyDescription.layers` makes
the layers it describes, in drawing order.
"""

from __future__ import annotations

from dataclasses import astuple, dataclass, field, fields, replace
from functools import cached_property
from typing import Any

import numpy as np

from skydome.astro import Observer, Time, to_time
from skydome.astro.places import Place, parse_place, time_zone
from skydome.astro.time import VALID_JD_RANGE
from skydome.atmosphere.cie_layer import CieSkyLayer
from skydome.atmosphere.ground import (
    BlackGroundLayer,
    LandscapeLayer,
    ground_albedo,
    is_landscape,
    parse_ground,
)
from skydome.atmosphere.layer import MODELS, AtmosphereLayer, atmosphere_params
from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.atmosphere.presets import preset
from skydome.atmosphere.single import SingleScatteringSky
from skydome.celestial.milky_way import MilkyWayLayer
from skydome.celestial.moon import MoonLayer
from skydome.celestial.planets import PlanetsLayer
from skydome.celestial.stars import StarsLayer
from skydome.celestial.sun import SunLayer
from skydome.clouds.layer import QUALITY, CloudLayer
from skydome.clouds.params import Clouds
from skydome.core.layer import Layer
from skydome.core.lights import SkyState
from skydome.display.overlays import parse_overlays
from skydome.errors import ParameterError, check_choice, check_range
from skydome.night.glow_layer import AirglowLayer, LightPollutionLayer, ZodiacalLightLayer
from skydome.night.light_pollution import LightPollution
from skydome.physics.constants import STANDARD_PRESSURE_HPA, STANDARD_TEMPERATURE_C
from skydome.scene.state import abstract_state, state_at
from skydome.weather import Weather
from skydome.weather.particles import EXPOSURE_RANGE_S, PrecipitationLayer
from skydome.weather_effects import ground_visibility_km, weathered

#: The sky models: the atmosphere's ("precomputed", "single") and the CIE standard general
#: sky ("cie": the standard's luminance distribution in place of the air).
SKY_MODELS = (*MODELS, "cie")

#: The layers of the night sky a sky with a place has (in this order, before the air).
NIGHT_LAYERS = ("stars", "planets", "milky_way", "zodiacal_light", "airglow")


def observer_for(place: Any, pressure_hPa=None, temperature_C=None) -> Observer:
    """An ``Observer`` for a place: an Observer, a ``Place`` of the gazetteer, a place name,
    or ``(lat, lon[, elevation_m])``; with the weather given (refraction)."""
    weather = {}
    if pressure_hPa is not None:
        weather["pressure_hPa"] = pressure_hPa
    if temperature_C is not None:
        weather["temperature_C"] = temperature_C
    if isinstance(place, Observer):
        return replace(place, **weather) if weather else place
    return parse_place(place).observer(**weather)


def place_of(place: Any) -> Place | None:
    """The ``Place`` a place is given as (a name, a Place, a position as numbers), or None
    for an ``Observer`` (which carries no time zone or light pollution)."""
    return None if isinstance(place, Observer) else parse_place(place)


def place_timezone(place: Any) -> str:
    """The IANA zone whose local time a naive time given with ``place`` is read in: a
    gazetteer place's (``Place.timezone``); "" (UTC) for a position given as numbers or an
    Observer."""
    p = place_of(place)
    return "" if p is None else p.timezone


def auto_light_pollution(place: Any, model: str = "precomputed", night: bool = True):
    """The light pollution a sky takes by default (``light_pollution="auto"``): a gazetteer
    place's own (``LightPollution.for_place``: a city's estimate from its population, an
    observatory's class) with the default model and the night sky on; else None."""
    p = place_of(place)
    if p is None or model != "precomputed" or not night:
        return None
    return LightPollution.for_place(p)


def light_pollution_value(value: Any) -> int | LightPollution | None:
    """None, a Bortle class (1-9) or a LightPollution, checked."""
    if value is None or isinstance(value, LightPollution):
        return value
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        if not 1 <= int(value) <= 9:
            raise ParameterError(f"light_pollution = {value} is outside the valid range 1 to 9")
        return int(value)
    raise ParameterError(
        f"light_pollution {value!r} must be a Bortle class 1-9 or a LightPollution"
    )


@dataclass(frozen=True)
class SkyDescription:
    """A sky as values (see the module docstring). Make one with :meth:`of` (which takes
    what a user types: names, ISO times, preset names) or directly with checked values.

    Attributes:
        observer: the place (with its weather), or None for a Sun alone.
        time: the instant (``skydome.astro.Time``), None without a place.
        timezone: the IANA zone of the place (``"Europe/Malta"``), in whose local time
            :meth:`of` and :meth:`with_` read a time given without an offset; "" for UTC (a
            position given as numbers, or ``utc=True``).
        sun_elevation_deg, sun_azimuth_deg: the abstract mode's Sun (apparent, degrees).
        pressure_hPa, temperature_C: the abstract mode's weather (refraction; pressure 0
            bends no light). With a place, the observer's.
        atmosphere: the air.
        model: "precomputed" (every order, tables), "single" (single scattering) or "cie"
            (a CIE standard general sky in place of the air: ``CieSkyLayer``).
        cie_type, cie_zenith_luminance, cie_illuminance: the "cie" model's type (1-15) and
            its scale, exactly one: the zenith luminance (cd/m^2) or the diffuse
            horizontal illuminance (lx).
        config: the precomputed model's tables.
        samples: the single model's samples per view ray.
        sky_view_size: the sky-view tables' texels (None: 256 x 256).
        night: with a place, the night sky's layers (stars, planets, Milky Way, zodiacal
            light, airglow).
        light_pollution: a Bortle class (1-9), a ``LightPollution`` or None.
        clouds: the clouds, or None; ``cloud_quality``: "full", "best" or "interactive";
            ``cloud_shafts``: the air in their shadows unlit by the Sun (light shafts;
            None: on but in the interactive quality).
        weather: a ``Weather`` (fog, mist, rain, snow, visibility, humidity) or None: it
            changes the air and the clouds the sky is drawn with (``effective``;
            ``skydome.weather_effects``), brings its preset's clouds where the sky has none,
            and its rain or snow falls near the camera (``PrecipitationLayer``) as streaks
            of one exposure of ``shutter_s`` seconds.
        night_vision, overlays: the display (the image only, never the frame's data).
        sun_disk: draw the Sun's disk (False: the sky without it, e.g. an environment map
            for a renderer that lights with its own Sun lamp; the air is lit all the same).
        ground: what lies below the horizon (``skydome.atmosphere.ground``): None, the
            atmosphere's own ground (the measured Earth's: grassland); an albedo 0-1; a
            surface's spectral albedo by name ("grassland", "cropland", "forest", "desert",
            "snow", "ocean", "urban"); "none", a ground that reflects nothing
            (the air in front of it only); "black", zero wherever a ray meets the ground; an
            image file, a landscape panorama in front of the sky (``LandscapeLayer``).
    """

    observer: Observer | None = None
    time: Time | None = None
    timezone: str = ""
    sun_elevation_deg: float = 30.0
    sun_azimuth_deg: float = 180.0
    pressure_hPa: float = STANDARD_PRESSURE_HPA
    temperature_C: float = STANDARD_TEMPERATURE_C
    atmosphere: AtmosphereParams = field(default_factory=lambda: preset("earth"))
    model: str = "precomputed"
    cie_type: int = 12
    cie_zenith_luminance: float | None = None
    cie_illuminance: float | None = None
    config: PrecomputeConfig = field(default_factory=PrecomputeConfig)
    samples: int = 16
    sky_view_size: tuple[int, int] | None = None
    night: bool = True
    light_pollution: int | LightPollution | None = None
    clouds: Clouds | None = None
    cloud_quality: str = "full"
    cloud_shafts: bool | None = None
    weather: Weather | None = None
    shutter_s: float = 1.0 / 60.0
    night_vision: bool = False
    overlays: tuple[str, ...] = ()
    sun_disk: bool = True
    ground: str | float | None = None

    def __post_init__(self):
        object.__setattr__(self, "ground", parse_ground(self.ground))
        if self.observer is not None and not isinstance(self.observer, Observer):
            raise ParameterError(f"observer must be an Observer, got {self.observer!r}")
        if self.observer is not None and any(np.ndim(v) for v in astuple(self.observer)):
            raise ParameterError(
                f"a sky is for one place and weather: numbers, not arrays, got {self.observer!r}"
            )
        if (self.observer is None) != (self.time is None):
            raise ParameterError(
                "a place needs a time and a time needs a place (or give neither, and a Sun "
                "elevation)"
            )
        if self.time is not None and (
            not isinstance(self.time, Time) or np.shape(self.time.jd_utc) != ()
        ):
            raise ParameterError("time must be one instant (skydome.astro.Time)")
        if self.time is not None:
            jd, (lo, hi) = float(self.time.jd_utc), VALID_JD_RANGE
            if not lo <= jd <= hi:  # (not finite: outside too)
                raise ParameterError(
                    f"time JD {jd:.6g} is outside the years -3000 to 4000 the astronomy holds for"
                )
        if self.timezone:
            time_zone(self.timezone)  # a zone zoneinfo knows
        for name, lo, hi, unit in (
            ("sun_elevation_deg", -90.0, 90.0, "deg"),
            ("sun_azimuth_deg", -360.0, 360.0, "deg"),
            ("pressure_hPa", 0.0, 2000.0, "hPa"),
            ("temperature_C", -100.0, 100.0, "deg C"),
        ):
            object.__setattr__(self, name, check_range(name, getattr(self, name), lo, hi, unit))
        if not isinstance(self.atmosphere, AtmosphereParams):
            raise ParameterError(f"atmosphere must be AtmosphereParams, got {self.atmosphere!r}")
        check_choice("model", self.model, SKY_MODELS, "model")
        if self.model == "cie":
            self.cie_layer()  # checks the type and the scale
            if self.clouds is not None or self.light_pollution is not None:
                raise ParameterError(
                    "the cie model is the standard's sky alone: no clouds or light pollution "
                    "(they need the physical air: the default model)"
                )
        elif self.cie_zenith_luminance is not None or self.cie_illuminance is not None:
            raise ParameterError("a CIE sky's scale needs model='cie'")
        if not isinstance(self.config, PrecomputeConfig):
            raise ParameterError(f"config must be a PrecomputeConfig, got {self.config!r}")
        SingleScatteringSky.check_samples(self.samples)
        light_pollution_value(self.light_pollution)
        if self.light_pollution is not None and self.abstract:
            raise ParameterError("light pollution needs a place and a time")
        if self.clouds is not None and not isinstance(self.clouds, Clouds):
            raise ParameterError(f"clouds must be a Clouds or None, got {self.clouds!r}")
        check_choice("cloud_quality", self.cloud_quality, QUALITY, "cloud quality")
        if self.weather is not None:
            if not isinstance(self.weather, Weather):
                raise ParameterError(f"weather must be a Weather or None, got {self.weather!r}")
            if self.model != "precomputed":
                raise ParameterError(f"a weather needs the default model, not {self.model!r}")
            _ = self.effective  # checks that the weather fits the air and the clouds
        check_range("shutter_s", self.shutter_s, *EXPOSURE_RANGE_S, "s")
        object.__setattr__(self, "overlays", parse_overlays(self.overlays))
        if self.model == "single" and (
            self.clouds is not None or self.night_vision or self.overlays or self.observer
        ):
            raise ParameterError(
                "the single-scattering model renders a Sun alone: no place, clouds, night "
                "vision or overlays (use the default model for those)"
            )
        if not isinstance(self.sun_disk, bool):
            raise ParameterError(f"sun_disk must be True or False, got {self.sun_disk!r}")
        if not self.sun_disk and self.model == "single":
            raise ParameterError(
                "the single-scattering model draws its Sun's disk itself: sun_disk=False "
                "needs the default model"
            )
        if self.ground is not None and self.model == "single":
            raise ParameterError("ground needs the default model (or the cie model)")
        if is_landscape(self.ground) and self.model != "precomputed":
            raise ParameterError("a landscape panorama needs the default model (its air)")

    # ------------------------------------------------------------------ from what users type

    @classmethod
    def of(
        cls,
        place: Any = None,
        time: Any = None,
        atmosphere: str | AtmosphereParams = "earth",
        *,
        sun_elevation_deg: float | None = None,
        sun_azimuth_deg: float = 180.0,
        pressure_hPa: float | None = None,
        temperature_C: float | None = None,
        model: str = "precomputed",
        cie_type: int = 12,
        cie_zenith_luminance: float | None = None,
        cie_illuminance: float | None = None,
        config: PrecomputeConfig | None = None,
        samples: int = 16,
        sky_view_size: tuple[int, int] | None = None,
        night: bool = True,
        light_pollution: Any = "auto",
        clouds: Clouds | str | None = None,
        cloud_quality: str = "full",
        cloud_shafts: bool | None = None,
        weather: Weather | str | None = None,
        shutter_s: float = 1.0 / 60.0,
        night_vision: bool = False,
        overlays: Any = (),
        sun_disk: bool = True,
        ground: str | float | None = None,
        utc: bool = False,
    ) -> SkyDescription:
        """A description from what a user gives: ``place`` an ``Observer``, a gazetteer
        name, a ``Place`` or ``(lat_deg, lon_deg[, elevation_m])`` (None: a Sun alone at
        ``sun_elevation_deg``); ``time`` anything ``skydome.astro.to_time`` accepts (ISO
        8601 with an offset or Z; without one, a gazetteer place's local time, in its
        ``timezone``, and UTC for a position given as numbers, an Observer, or with
        ``utc=True``; a wall-clock time the zone skips or repeats raises
        ``skydome.astro.time.LocalTimeError``); ``atmosphere`` a preset name or
        ``AtmosphereParams``; ``clouds`` a preset name or a ``Clouds``; ``weather`` a preset
        name ("fog", "rain", ...) or a ``Weather``; ``overlays`` names or a comma list;
        ``light_pollution`` "auto" (the default: a gazetteer place's own,
        :func:`auto_light_pollution`), None (none), a Bortle class or a ``LightPollution``."""
        abstract = place is None
        if abstract and time is not None:
            raise ParameterError("a time needs a place: give place=(lat, lon) or a place name")
        if abstract and sun_elevation_deg is None:
            raise ParameterError("give a place and a time, or sun_elevation_deg for a Sun alone")
        if not abstract and sun_elevation_deg is not None:
            raise ParameterError(
                "a place and a time set the Sun: drop sun_elevation_deg, or drop the place"
            )
        if not abstract and time is None:
            raise ParameterError("a place needs a time (ISO 8601, e.g. 2018-03-01T19:00Z)")
        refraction = {}
        observer = instant = None
        zone = ""
        if isinstance(light_pollution, str) and light_pollution == "auto":
            light_pollution = None if abstract else auto_light_pollution(place, model, night)
        if abstract:
            if pressure_hPa is not None:
                refraction["pressure_hPa"] = pressure_hPa
            if temperature_C is not None:
                refraction["temperature_C"] = temperature_C
        else:
            observer = observer_for(place, pressure_hPa, temperature_C)
            zone = "" if utc else place_timezone(place)
            instant = to_time(time, zone=time_zone(zone) if zone else None)
            if instant.shape != ():
                raise ParameterError(f"a sky is for one instant; got {instant.shape} times")
        if isinstance(clouds, str):
            clouds = Clouds(clouds)
        if isinstance(weather, str):
            weather = Weather(weather)
        overlays = () if overlays is None else parse_overlays(overlays)
        return cls(
            observer=observer,
            time=instant,
            timezone=zone,
            sun_elevation_deg=30.0 if sun_elevation_deg is None else sun_elevation_deg,
            sun_azimuth_deg=sun_azimuth_deg,
            atmosphere=atmosphere_params(atmosphere),
            model=model,
            cie_type=cie_type,
            cie_zenith_luminance=cie_zenith_luminance,
            cie_illuminance=cie_illuminance,
            config=config or PrecomputeConfig(),
            samples=samples,
            sky_view_size=sky_view_size,
            night=bool(night),
            light_pollution=light_pollution_value(light_pollution),
            clouds=clouds,
            cloud_quality=cloud_quality,
            cloud_shafts=None if cloud_shafts is None else bool(cloud_shafts),
            weather=weather,
            shutter_s=shutter_s,
            night_vision=bool(night_vision),
            overlays=tuple(overlays),
            sun_disk=sun_disk,
            ground=ground,
            **refraction,
        )

    def with_(self, **changes) -> SkyDescription:
        """A copy with ``changes``: fields of the description, or what :meth:`of` takes for
        them (``time="2018-03-01T23:00Z"``, ``atmosphere="hazy"``, ``clouds="fair"``,
        ``place="Paranal"``). A new ``place`` brings its ``timezone`` (unless one is given);
        a time without an offset is read in the (new) ``timezone``, as :meth:`of` does. The
        light pollution stays as it is unless given (``light_pollution="auto"``: the place's
        own)."""
        names = {f.name for f in fields(self)}
        unknown = set(changes) - names - {"place"}
        if unknown:
            raise ParameterError(
                f"unknown sky setting {sorted(unknown)[0]!r}; the settings are "
                f"{', '.join(sorted(names))}"
            )
        place = self.observer
        if "place" in changes:
            place = changes.pop("place")
            changes["observer"] = None if place is None else observer_for(place)
            if "timezone" not in changes:
                changes["timezone"] = "" if place is None else place_timezone(place)
        if isinstance(changes.get("light_pollution"), str) and changes["light_pollution"] == "auto":
            model, night = changes.get("model", self.model), changes.get("night", self.night)
            changes["light_pollution"] = (
                None if place is None else auto_light_pollution(place, model, night)
            )
        if isinstance(changes.get("time"), (str, int, float)) or (
            "time" in changes
            and changes["time"] is not None
            and not isinstance(changes["time"], Time)
        ):
            zone = changes.get("timezone", self.timezone)
            changes["time"] = to_time(changes["time"], zone=time_zone(zone) if zone else None)
        if isinstance(changes.get("atmosphere"), str):
            changes["atmosphere"] = preset(changes["atmosphere"])
        if isinstance(changes.get("clouds"), str):
            changes["clouds"] = Clouds(changes["clouds"])
        if isinstance(changes.get("weather"), str):
            changes["weather"] = Weather(changes["weather"])
        if isinstance(changes.get("overlays"), str):
            changes["overlays"] = parse_overlays(changes["overlays"])
        return replace(self, **changes)

    # ------------------------------------------------------------------ what it makes

    @property
    def abstract(self) -> bool:
        """True for a Sun alone (no place or time)."""
        return self.observer is None

    def state(self) -> SkyState:
        """The lights at the description's instant (or of its Sun alone)."""
        if self.abstract:
            return abstract_state(
                self.sun_elevation_deg,
                self.sun_azimuth_deg,
                pressure_hPa=self.pressure_hPa,
                temperature_C=self.temperature_C,
            )
        return state_at(self.observer, self.time)

    @cached_property
    def effective(self) -> tuple[AtmosphereParams, Clouds | None, PrecomputeConfig]:
        """The air, the clouds and the tables the sky is drawn with: the description's, with
        its weather (``skydome.weather_effects.weathered``)."""
        albedo = ground_albedo(self.ground)
        air = self.atmosphere if albedo is None else self.atmosphere.with_albedo(albedo)
        return weathered(self.weather, air, self.clouds, self.config)

    @property
    def visibility_km(self) -> float:
        """The visibility at the ground (km, Koschmieder, 550 nm) of the air and the weather."""
        air, clouds, _ = self.effective
        return ground_visibility_km(air, clouds)

    def atmosphere_layer(self, progress=None) -> AtmosphereLayer:
        extra = {} if self.sky_view_size is None else {"sky_view_size": self.sky_view_size}
        air, _, config = self.effective
        return AtmosphereLayer(
            air,
            model=self.model,
            config=config,
            samples=self.samples,
            spectral=config.wavelengths,
            progress=progress,
            **extra,
        )

    def cie_layer(self) -> CieSkyLayer:
        """The "cie" model's layer (checked: the type, exactly one scale)."""
        return CieSkyLayer(
            self.cie_type,
            zenith_luminance=self.cie_zenith_luminance,
            horizontal_illuminance=self.cie_illuminance,
            ground_albedo=float(np.mean(self.effective[0].ground_albedo.values)),
        )

    def layers(self, progress=None) -> list[Layer]:
        """The layers of this sky in drawing order: the Sun and (with a place) the Moon;
        with a place and ``night``, the stars, the planets, the Milky Way, the zodiacal
        light and the airglow; the atmosphere; the clouds; the light pollution. The single
        model is the atmosphere alone (it draws its own Sun); the cie model the CIE sky
        alone."""
        if self.model == "cie":
            return [self.cie_layer()] + ([BlackGroundLayer()] if self.ground == "black" else [])
        air = self.atmosphere_layer(progress)
        if self.model == "single":
            return [air]
        layers: list[Layer] = [SunLayer(enabled=self.sun_disk)]
        if not self.abstract:
            layers.append(MoonLayer())
            if self.night:
                layers += [
                    StarsLayer(),
                    PlanetsLayer(),
                    MilkyWayLayer(),
                    ZodiacalLightLayer(),
                    AirglowLayer(),
                ]
        layers.append(air)
        clouds = self.effective[1]
        if clouds is not None:
            layers.append(CloudLayer(clouds, quality=self.cloud_quality, shafts=self.cloud_shafts))
        if self.weather is not None and self.weather.precipitates:
            layers.append(PrecipitationLayer(self.weather, exposure_s=self.shutter_s))
        glow = self.light_pollution_layer()
        if glow is not None:
            layers.append(glow)
        if self.ground == "black":
            layers.append(BlackGroundLayer())
        elif is_landscape(self.ground):
            layers.append(LandscapeLayer(self.ground))
        return layers

    def light_pollution_layer(self) -> LightPollutionLayer | None:
        lp = self.light_pollution
        if lp is None:
            return None
        if isinstance(lp, LightPollution):
            return LightPollutionLayer(lp)
        return LightPollutionLayer.from_bortle(lp)
