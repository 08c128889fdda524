"""From the shared flags (:mod:`skydome.cli.options`) to what they describe: the place and
time, the air, the clouds, and the whole sky as one
:class:`~skydome.description.SkyDescription`, with errors that name the flag. ``render``,
``timelapse`` and ``view`` all build their sky here."""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any

from skydome.cli.parsing import MAX_ORDERS, check_int, parse_time, parse_wind
from skydome.errors import ParameterError, check_choice, check_range

#: Valid ranges of the place flags (the Observer's).
LAT_RANGE = (-90.0, 90.0)
LON_RANGE = (-180.0, 360.0)
ELEVATION_RANGE_M = (-1000.0, 100000.0)
LOOKS = ("sun", "moon", "antisun", "zenith", "north", "east", "south", "west")


def place_from_flags(flags: SimpleNamespace):
    """The gazetteer ``Place`` of ``--place`` (its time zone and light pollution), or None
    (no place, or ``--lat``/``--lon``)."""
    if getattr(flags, "place", None) is None:
        return None
    from skydome.astro.places import find_place

    try:
        return find_place(flags.place)
    except ParameterError as exc:
        raise ParameterError(f"--place: {exc}") from None


def time_zone_from_flags(flags: SimpleNamespace):
    """The zone a ``--time`` without an offset is read in: the ``--place``'s (a
    ``zoneinfo.ZoneInfo``), or None (UTC) with ``--lat``/``--lon``, without a place, or with
    ``--utc``."""
    place = place_from_flags(flags)
    if place is None or getattr(flags, "utc", False):
        return None
    return place.zone


def time_line(t, zone, end=None) -> str:
    """The one line every command prints (on stderr) about the instant it used (or the
    span from ``t`` to ``end``): local and UTC with a zone (``time: 2018-03-01 20:00:00 CET
    (UTC+01:00, Europe/Malta) = 2018-03-01 19:00:00 UTC``), else UTC."""
    from skydome.astro.time import format_local

    def both(when) -> str:
        utc = format_local(when, None)
        if zone is None:
            return utc
        return f"{format_local(when, zone)[:-1]}, {zone.key}) = {utc}"

    text = both(t) if end is None else f"{both(t)} to {both(end)}"
    return "time: " + text + (" (a time without an offset is UTC here)" if zone is None else "")


def report_time(t, zone, end=None) -> None:
    """Print :func:`time_line` on stderr (stdout stays the command's: JSON, tables)."""
    import typer

    typer.echo(time_line(t, zone, end), err=True)


def report_light_pollution(description, place, bortle) -> None:
    """One line on stderr: the light pollution a sky with a place is drawn with, and where
    its value comes from (``--bortle``, the place's estimate, or none)."""
    import typer

    lp = description.light_pollution
    if description.abstract or description.model == "cie":
        return
    if bortle is not None:
        from skydome.night.light_pollution import LightPollution

        text = LightPollution.from_bortle(bortle).summary().replace("given", "--bortle")
    elif lp is not None:
        text = lp.summary() + "; --bortle overrides"
    elif place is not None and place.bortle is not None:
        text = f"none: {place.name} is a dark site (Bortle {place.bortle}); --bortle adds some"
    elif place is not None and not description.night:
        text = "none (no night sky); --bortle adds some"
    else:
        text = "none (a place given as numbers has no estimate); --bortle adds some"
    typer.echo(f"light pollution: {text}", err=True)


def observer_from_flags(flags: SimpleNamespace):
    """The Observer the place flags describe, or None when none of them is given (the
    abstract mode). Raises ParameterError naming the flag for bad or conflicting values."""
    place, lat, lon, elevation = flags.place, flags.lat, flags.lon, flags.elevation
    if place is not None and (lat is not None or lon is not None):
        raise ParameterError("--place and --lat/--lon both give the place: use one of them")
    if place is None and (lat is None) != (lon is None):
        raise ParameterError("--lat and --lon go together: give both")
    if place is None and lat is None:
        if elevation is not None:
            raise ParameterError("--elevation needs a place: add --place or --lat and --lon")
        return None
    if elevation is not None:
        check_range("--elevation", elevation, *ELEVATION_RANGE_M, "m")
    from skydome.astro import Observer

    if place is not None:
        from skydome.astro.places import find_place

        try:
            p = find_place(place)
        except ParameterError as exc:
            raise ParameterError(f"--place: {exc}") from None
        return Observer(
            latitude=p.latitude_deg,
            longitude=p.longitude_deg,
            elevation_m=p.elevation_m if elevation is None else elevation,
        )
    check_range("--lat", lat, *LAT_RANGE, "deg")
    check_range("--lon", lon, *LON_RANGE, "deg")
    return Observer(
        latitude=lat, longitude=lon, elevation_m=0.0 if elevation is None else elevation
    )


@dataclass(frozen=True)
class PlaceTimeSun:
    """What the place, time and Sun flags say.

    Attributes:
        observer: the Observer of the place flags, or None (the abstract mode).
        time: the instant (``skydome.astro.Time``), None in the abstract mode.
        place: the gazetteer ``Place`` of ``--place``, or None.
        zone: the zone a time without an offset was read in (``ZoneInfo``), None for UTC.
        sun_elevation_deg, sun_azimuth_deg: the abstract mode's Sun (deg; 30 and 180 by
            default, checked also with a place, where they are unused).
        look: the ``--look`` target, or None.
    """

    observer: Any
    time: Any
    sun_elevation_deg: float
    sun_azimuth_deg: float
    look: str | None
    place: Any = None
    zone: Any = None

    @property
    def abstract(self) -> bool:
        """True without a place: a Sun alone at ``sun_elevation_deg``."""
        return self.observer is None


def place_time_sun(flags: SimpleNamespace, when: str | None, *, default_now: bool = False):
    """Check the place, ``--time``, ``--sun-elevation``/``--sun-azimuth`` and ``--look``
    flags together: a place sets the Sun (no Sun flags with it), a time needs a place, the
    Moon needs a place. Without ``--time`` a place takes the current time when
    ``default_now`` (the viewer), else it is an error (a render says when)."""
    observer = observer_from_flags(flags)
    abstract = observer is None
    sun_elevation, sun_azimuth = flags.sun_elevation, flags.sun_azimuth
    if not abstract and (sun_elevation is not None or sun_azimuth is not None):
        raise ParameterError("--place/--lat/--lon set the Sun: drop --sun-elevation/--sun-azimuth")
    if abstract and when is not None:
        raise ParameterError("--time needs a place: add --place NAME or --lat and --lon")
    t = None
    zone = time_zone_from_flags(flags)
    if not abstract:
        if when is None and not default_now:
            raise ParameterError("a place needs --time, e.g. --time 2018-03-01T19:00Z")
        if when is None:
            from datetime import datetime, timezone

            when = datetime.now(timezone.utc).isoformat()
        t = parse_time("--time", when, zone)
    look = getattr(flags, "look", None)
    if look is not None:
        check_choice("--look", look, LOOKS, "view")
        if abstract and look == "moon":
            raise ParameterError("--look moon needs a place and a time (there is no Moon)")
    el = 30.0 if sun_elevation is None else sun_elevation
    az = 180.0 if sun_azimuth is None else sun_azimuth
    check_range("--sun-elevation", el, -90.0, 90.0, "deg")
    check_range("--sun-azimuth", az, -360.0, 360.0, "deg")
    return PlaceTimeSun(observer, t, float(el), float(az), look, place_from_flags(flags), zone)


def atmosphere_from_flags(flags: SimpleNamespace):
    """The ``--atmosphere`` preset with the knob flags given (None keeps the preset's
    value; ``--visibility`` scales its aerosol column after the others); a bad value raises
    ParameterError naming its flag and range."""
    from skydome.atmosphere import (
        ALBEDO_RANGE,
        ANGSTROM_RANGE,
        AOD_550_RANGE,
        OZONE_DU_RANGE,
        PRESETS,
        preset,
    )

    check_choice("--atmosphere", flags.atmosphere, PRESETS, "atmosphere preset")
    for flag, value, valid, unit in (
        ("--albedo", flags.albedo, ALBEDO_RANGE, ""),
        ("--aod", flags.aod, AOD_550_RANGE, ""),
        ("--angstrom", flags.angstrom, ANGSTROM_RANGE, ""),
        ("--ozone", flags.ozone, OZONE_DU_RANGE, "DU"),
    ):
        if value is not None:
            check_range(flag, value, *valid, unit)
    visibility = getattr(flags, "visibility", None)
    if visibility is not None and flags.aod is not None:
        raise ParameterError("--visibility and --aod both set the aerosol: give one of them")
    return preset(
        flags.atmosphere,
        albedo=flags.albedo,
        aod_550=flags.aod,
        angstrom=flags.angstrom,
        ozone_du=flags.ozone,
    )


def ground_from_flags(flags: SimpleNamespace) -> str | float | None:
    """``--ground`` checked (None when not given); with ``--albedo`` too, a ParameterError."""
    from skydome.atmosphere.ground import parse_ground

    ground = getattr(flags, "ground", None)
    if ground is None:
        return None
    if getattr(flags, "albedo", None) is not None:
        raise ParameterError("--ground and --albedo both set the ground: give one of them")
    try:
        return parse_ground(ground)
    except ParameterError as exc:
        raise ParameterError(f"--ground: {exc}") from None


#: The weather flags that set a ``Weather``'s knobs, by the flag's parameter name.
_WEATHER_FIELDS = {
    "visibility": "visibility_km", "humidity": "humidity_pct", "fog_top": "fog_top_m",
    "fog_droplet": "fog_droplet_um", "rain": "rain_mm_h", "snow": "snow_mm_h",
    "snow_cover": "snow_cover", "rain_drop": "rain_drop_radius_mm",
}  # fmt: skip


def weather_from_flags(flags: SimpleNamespace):
    """The ``Weather`` of ``--weather`` and its knobs (``--visibility`` among them), or None
    when none is given; a bad value raises ParameterError naming its flag."""
    from skydome.weather.params import KNOB_RANGES, PRESETS, Weather

    knobs = {
        field: getattr(flags, name)
        for name, field in _WEATHER_FIELDS.items()
        if getattr(flags, name, None) is not None
    }
    name = getattr(flags, "weather", None)
    if name is None and not knobs:
        return None
    if name is not None:
        check_choice("--weather", name, PRESETS, "weather")
    for flag, field in _WEATHER_FIELDS.items():
        if field in knobs:
            lo, hi, unit = KNOB_RANGES[field]
            check_range("--" + flag.replace("_", "-"), knobs[field], lo, hi, unit)
    wind = getattr(flags, "wind", None)
    if wind is not None:
        knobs["wind_m_s"] = parse_wind(wind)
    return Weather(name or "sunny", **knobs)


def weathered_air_from_flags(flags: SimpleNamespace, config=None):
    """(air, clouds, tables) of the air and weather flags (no cloud flags: the weather's
    own clouds), as a sky with them is drawn."""
    from skydome.atmosphere.precompute_config import PrecomputeConfig
    from skydome.weather_effects import weathered

    return weathered(
        weather_from_flags(flags), atmosphere_from_flags(flags), None, config or PrecomputeConfig()
    )


def config_from_flags(flags: SimpleNamespace):
    """The tables' PrecomputeConfig of ``--orders`` and ``--spectral``."""
    from skydome.atmosphere.precompute_config import PrecomputeConfig
    from skydome.spectra.grids import MODES

    check_choice("--spectral", flags.spectral, MODES, "wavelength set")
    check_int("--orders", flags.orders, 1, MAX_ORDERS)
    return PrecomputeConfig(wavelengths=flags.spectral, orders=flags.orders)


#: The cloud flags that shape a ``Clouds``, by the flag's parameter name.
_CLOUD_FIELDS = {
    "coverage": "coverage", "cloud_base": "base_m", "cloud_thickness": "thickness_m",
    "cloud_type": "cloud_type", "cirrus": "cirrus", "halos": "halos",
}  # fmt: skip


def clouds_from_flags(flags: SimpleNamespace):
    """The ``Clouds`` the cloud flags describe, or None without --clouds (other cloud flags
    then are an error)."""
    from skydome.cli.options import GROUPS, flag_name

    if flags.clouds is None:
        given = [name for name in GROUPS["clouds"][1:] if getattr(flags, name) is not None]
        weather = weather_from_flags(flags) if given else None
        if weather is not None and set(given) <= {"wind", "halos"}:
            if flags.halos is None:
                return None  # the wind of the weather's own clouds
            from skydome.clouds.params import Clouds

            # the weather's own clouds (or none: its diamond dust's crystals), of these crystals
            wind = parse_wind(flags.wind) if flags.wind is not None else weather.wind_m_s
            return Clouds(weather.clouds or "clear", wind_m_s=wind, halos=flags.halos)
        if given:
            raise ParameterError(
                f"{flag_name(given[0])} needs --clouds PRESET (e.g. --clouds fair)"
            )
        return None
    from skydome.clouds.params import CLOUD_TYPES, PRESETS, Clouds

    check_choice("--clouds", flags.clouds, PRESETS, "cloud preset")
    if flags.cloud_type is not None:
        check_choice("--cloud-type", flags.cloud_type, CLOUD_TYPES, "cloud type")
    kwargs = {
        field: getattr(flags, name)
        for name, field in _CLOUD_FIELDS.items()
        if getattr(flags, name) is not None
    }
    if flags.wind is not None:
        kwargs["wind_m_s"] = parse_wind(flags.wind)
    if flags.cloud_seed is not None:
        kwargs["seed"] = flags.cloud_seed
    if flags.weather_map is not None:
        from skydome.clouds.weather import WeatherMap

        kwargs["weather"] = WeatherMap.from_image(flags.weather_map, tile_km=40.0)
    return Clouds(flags.clouds, **kwargs)


def overlays_from_flags(flags: SimpleNamespace) -> tuple[str, ...]:
    if flags.overlay is None:
        return ()
    from skydome.display.overlays import parse_overlays

    return parse_overlays(flags.overlay)


def sky_description(
    flags: SimpleNamespace,
    pts: PlaceTimeSun,
    *,
    model: str = "precomputed",
    samples: int = 16,
    night: bool = True,
    sky_view_size: tuple[int, int] | None = None,
    cloud_quality: str = "full",
    **cie,
):
    """The SkyDescription of the shared flags (the groups a command has: place, sun, air,
    tables, night, clouds), checked with errors that name the flag; ``cie``: the cie
    model's settings (``cie_type``, ``cie_illuminance``, ``cie_zenith_luminance``)."""
    from skydome.description import SkyDescription

    has = lambda name: hasattr(flags, name)  # noqa: E731
    bortle = flags.bortle if has("bortle") else None
    if bortle is not None:
        if pts.abstract:
            raise ParameterError("--bortle needs a place and a time (--place or --lat/--lon)")
        check_int("--bortle", bortle, 1, 9)
    overlays = overlays_from_flags(flags) if has("overlay") else ()
    night_vision = bool(flags.night_vision) if has("night_vision") else False
    clouds = clouds_from_flags(flags) if has("clouds") else None
    if model == "single" and (night_vision or overlays):
        raise ParameterError(
            "--night-vision and --overlay need the default model (a sky of the scene)"
        )
    if model == "single" and clouds is not None:
        raise ParameterError("--clouds needs the default model (a sky of the scene)")
    if model == "single" and not pts.abstract:
        raise ParameterError(
            "--model single renders a Sun alone: use --sun-elevation, or the default model "
            "for a place and a time"
        )
    config = config_from_flags(flags) if has("orders") else None
    params = atmosphere_from_flags(flags)
    weather = weather_from_flags(flags)
    if weather is not None and model != "precomputed":
        raise ParameterError(f"--weather and --visibility need the default model, not {model}")
    shutter = getattr(flags, "shutter", None)
    if shutter is not None:
        from skydome.weather.particles import EXPOSURE_RANGE_S

        check_range("--shutter", shutter, *EXPOSURE_RANGE_S, "s")
    settings = {
        "atmosphere": params,
        "model": model,
        "samples": samples,
        "night": night,
        "light_pollution": bortle if bortle is not None else auto_glow(pts, model, night),
        "clouds": clouds,
        "weather": weather,
        **({} if shutter is None else {"shutter_s": shutter}),
        "cloud_quality": cloud_quality,
        "night_vision": night_vision,
        "overlays": overlays,
        "sun_disk": not getattr(flags, "no_sun_disk", False),
        "ground": ground_from_flags(flags),
        "sky_view_size": sky_view_size,
        **cie,
    }
    if config is not None:
        settings["config"] = config
    if pts.abstract:
        return SkyDescription(
            sun_elevation_deg=pts.sun_elevation_deg,
            sun_azimuth_deg=pts.sun_azimuth_deg,
            **settings,
        )
    zone = "" if pts.zone is None else pts.zone.key
    return SkyDescription(observer=pts.observer, time=pts.time, timezone=zone, **settings)


def auto_glow(pts: PlaceTimeSun, model: str, night: bool):
    """The light pollution of a sky without ``--bortle``: the ``--place``'s own (a city's
    estimate, an observatory's class: ``skydome.description.auto_light_pollution``), none
    with ``--lat``/``--lon`` or no place."""
    if pts.place is None or pts.abstract:
        return None
    from skydome.description import auto_light_pollution

    return auto_light_pollution(pts.place, model, night)


def describe_state(state) -> list[str]:
    """Lines saying where the Sun and the Moon are (degrees) for a command's report."""
    sun = state.sun
    lines = [f"sun: elevation {sun.elevation_deg:.2f} deg, azimuth {sun.azimuth_deg:.2f} deg"]
    if state.moon is not None and state.moon_view is not None:
        moon = state.moon
        lines.append(
            f"moon: elevation {moon.elevation_deg:.2f} deg, azimuth {moon.azimuth_deg:.2f} deg, "
            f"{100 * state.moon_view.illuminated_fraction:.1f} % lit, "
            f"{moon.illuminance_lux:.3g} lx outside the air"
        )
    return lines


@contextlib.contextmanager
def precompute_progress(console):
    """A progress bar for table precomputation, shown only while a stage reports.

    Yields the ``report(stage, fraction)`` callback, to pass as ``progress=`` to what may
    precompute tables.
    """
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    bar = Progress(
        TextColumn("precomputing {task.description}"),
        BarColumn(),
        TextColumn("{task.percentage:>3.0f}%"),
        TimeElapsedColumn(),
        console=console,
        transient=True,
    )
    task = None

    def report(stage: str, fraction: float) -> None:
        nonlocal task
        if not console.is_terminal:  # no bar in logs and pipes
            return
        if task is None:
            bar.start()
            task = bar.add_task(stage, total=1.0)
        bar.update(task, completed=fraction, description=stage)

    try:
        yield report
    finally:
        if task is not None:
            bar.stop()
