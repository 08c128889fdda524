"""Options shared by the commands that take a place and a time (``render``, ``view``,
``timelapse``): parsing and checking them, with errors that name the flag."""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

import typer

from skydome.errors import ParameterError, check_choice, check_range

#: Valid ranges of the place flags (the Observer's).
LAT_RANGE = (-90.0, 90.0)
LON_RANGE = (-180.0, 360.0)
ELEVATION_RANGE_M = (-1000.0, 100000.0)
LOOKS = ("sun", "moon", "zenith", "north", "east", "south", "west")

_UNITS_S = {
    "s": 1.0, "sec": 1.0, "second": 1.0, "seconds": 1.0,
    "min": 60.0, "minute": 60.0, "minutes": 60.0, "m": 60.0,
    "h": 3600.0, "hour": 3600.0, "hours": 3600.0,
    "d": 86400.0, "day": 86400.0, "days": 86400.0,
}  # fmt: skip


def place_option():
    return typer.Option(
        None, "--place", help="A city or observatory of the built-in gazetteer (skydome places)."
    )


def lat_option():
    return typer.Option(None, "--lat", help="Latitude, degrees north (-90..90).")


def lon_option():
    return typer.Option(None, "--lon", help="Longitude, degrees east (-180..360).")


def elevation_option():
    return typer.Option(
        None, "--elevation", help="Elevation above sea level, metres (default: the place's, or 0)."
    )


def observer_from_flags(place: str | None, lat: float | None, lon: float | None, elevation):
    """The Observer the flags describe, or None when none of them is given (the abstract
    mode). Raises ParameterError naming the flag for bad or conflicting values."""
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


def parse_time(flag: str, text: str):
    """An instant (skydome.astro.Time) from ISO 8601 text (an offset or Z; naive is UTC)."""
    from skydome.astro import to_time

    try:
        t = to_time(text)
    except ParameterError:
        raise ParameterError(
            f"{flag} {text!r} must be an ISO 8601 date and time, e.g. 2018-03-01T19:00Z "
            "(an offset or Z; without one it is UTC)"
        ) from None
    if t.shape != ():
        raise ParameterError(f"{flag} {text!r} must be one instant")
    return t


@dataclass(frozen=True)
class PlaceTimeSun:
    """What the place, time and Sun flags of ``render`` and ``view`` say.

    Attributes:
        observer: the Observer of the place flags, or None (the abstract mode).
        time: the instant (``skydome.astro.Time``), None in the abstract mode.
        sun_elevation_deg, sun_azimuth_deg: the abstract mode's Sun (deg; 30 and 180 by
            default, checked also with a place, where they are unused).
        look: the ``--look`` target, or None.
    """

    observer: Any
    time: Any
    sun_elevation_deg: float
    sun_azimuth_deg: float
    look: str | None

    @property
    def abstract(self) -> bool:
        """True without a place: a Sun alone at ``sun_elevation_deg``."""
        return self.observer is None


def place_time_sun(
    place: str | None,
    lat: float | None,
    lon: float | None,
    elevation: float | None,
    when: str | None,
    sun_elevation: float | None,
    sun_azimuth: float | None,
    look: str | None,
    *,
    default_now: bool = False,
) -> PlaceTimeSun:
    """Check the place, ``--time``, ``--sun-elevation``/``--sun-azimuth`` and ``--look``
    flags together: a place sets the Sun (no Sun flags with it), a time needs a place, the
    Moon needs a place. Without ``--time`` a place takes the current time when
    ``default_now`` (the viewer), else it is an error (a render says when). Raises
    ParameterError naming the flag."""
    observer = observer_from_flags(place, lat, lon, elevation)
    abstract = observer is None
    if not abstract and (sun_elevation is not None or sun_azimuth is not None):
        raise ParameterError("--place/--lat/--lon set the Sun: drop --sun-elevation/--sun-azimuth")
    if abstract and when is not None:
        raise ParameterError("--time needs a place: add --place NAME or --lat and --lon")
    t = None
    if not abstract:
        if when is None and not default_now:
            raise ParameterError("a place needs --time, e.g. --time 2018-03-01T19:00Z")
        if when is None:
            from datetime import datetime, timezone

            when = datetime.now(timezone.utc).isoformat()
        t = parse_time("--time", when)
    if look is not None:
        check_choice("--look", look, LOOKS, "view")
        if abstract and look == "moon":
            raise ParameterError("--look moon needs a place and a time (there is no Moon)")
    el = 30.0 if sun_elevation is None else sun_elevation
    az = 180.0 if sun_azimuth is None else sun_azimuth
    check_range("--sun-elevation", el, -90.0, 90.0, "deg")
    check_range("--sun-azimuth", az, -360.0, 360.0, "deg")
    return PlaceTimeSun(observer, t, float(el), float(az), look)


def parse_step(text: str) -> float:
    """Seconds from a duration such as 1min, 30s, 2h, 1d or 90 (seconds); > 0."""
    m = re.fullmatch(r"\s*(\d+(?:\.\d*)?|\.\d+)\s*([a-zA-Z]*)\s*", text or "")
    unit = (m.group(2).lower() or "s") if m else ""
    if not m or unit not in _UNITS_S:
        raise ParameterError(f"--step {text} must be a duration such as 30s, 1min, 2h or 1d")
    seconds = float(m.group(1)) * _UNITS_S[unit]
    if not seconds > 0:
        raise ParameterError(f"--step {text} must be longer than zero")
    return seconds


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
