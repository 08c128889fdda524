"""Parsing the command line's values, with errors that name the flag."""

from __future__ import annotations

import math
import re

from skydome.errors import ParameterError, check_range

#: Frames larger than this many pixels are refused (a 16k x 8k equirect is 128 Mpixel).
MAX_PIXELS = 134_217_728
#: Largest --size side (pixels), as skydome.core.cameras.MAX_SIDE.
MAX_SIDE = 16384
#: Scattering orders accepted by the precomputed model.
MAX_ORDERS = 20

_UNITS_S = {
    "s": 1.0, "sec": 1.0, "second": 1.0, "seconds": 1.0,
    "min": 60.0, "minute": 60.0, "minutes": 60.0, "m": 60.0,
    "h": 3600.0, "hour": 3600.0, "hours": 3600.0,
    "d": 86400.0, "day": 86400.0, "days": 86400.0,
}  # fmt: skip


def check_int(flag: str, value: int, lo: int, hi: int) -> int:
    """``value`` if it is an integer in [lo, hi], else ParameterError naming ``flag``."""
    if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
        raise ParameterError(f"{flag} {value} must be an integer from {lo} to {hi}")
    return value


def parse_size(text: str, flag: str = "--size") -> tuple[int, int]:
    """Parse 'WxH' (e.g. 1280x720) into positive ints."""
    m = re.fullmatch(r"\s*(\d+)\s*[xX×]\s*(\d+)\s*", text or "")
    if not m:
        raise ParameterError(f"{flag} {text} must look like WIDTHxHEIGHT, e.g. 1280x720")
    w, h = int(m.group(1)), int(m.group(2))
    if w < 1 or h < 1 or w > MAX_SIDE or h > MAX_SIDE or w * h > MAX_PIXELS:
        raise ParameterError(
            f"{flag} {text} must have sides of 1 to {MAX_SIDE} pixels and at most "
            f"{MAX_PIXELS} pixels in all"
        )
    return w, h


def parse_exposure(text: str) -> float | None:
    """'auto' -> None, else an EV100 number."""
    if text.strip().lower() == "auto":
        return None
    try:
        ev = float(text)
    except ValueError:
        raise ParameterError(
            f"--exposure {text} must be auto or an EV100 number such as 14.5"
        ) from None
    return check_range("--exposure", ev, -20.0, 40.0, "EV")


def parse_time(flag: str, text: str, zone=None):
    """An instant (skydome.astro.Time) from ISO 8601 text: with an offset or Z as it says;
    without one, the local time of ``zone`` (a ``tzinfo``: the place's), or UTC when it is
    None. A local time the zone skips or repeats (daylight saving) is refused, naming the
    flag."""
    from skydome.astro.time import LocalTimeError, to_time

    try:
        t = to_time(text, zone=zone)
    except LocalTimeError as exc:
        raise ParameterError(f"{flag}: {exc}") from None
    except ParameterError:
        without = "the place's local time" if zone is not None else "UTC"
        raise ParameterError(
            f"{flag} {text!r} must be an ISO 8601 date and time, e.g. 2018-03-01T19:00Z "
            f"(an offset or Z; without one it is {without})"
        ) from None
    if t.shape != ():
        raise ParameterError(f"{flag} {text!r} must be one instant")
    return t


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


def parse_wind(text: str) -> tuple[float, float]:
    """'SPEED,FROM' -> (east, north) velocity in m/s (meteorological: FROM is where the wind
    comes from, degrees from north through east)."""
    parts = text.split(",")
    try:
        speed, frm = (float(p) for p in parts)
    except ValueError:
        raise ParameterError(f"--wind must be SPEED,FROM (m/s, degrees), got {text!r}") from None
    if not (math.isfinite(speed) and 0 <= speed <= 200 and math.isfinite(frm)):
        raise ParameterError(f"--wind speed must be within [0, 200] m/s, got {text!r}")
    a = math.radians(frm)
    return (-speed * math.sin(a), -speed * math.cos(a))
