"""Exception hierarchy. Every error the user can cause is a SkydomeError subclass.

Messages name the bad value and the valid range; the CLI prints them as one
line on stderr and exits with status 2.
"""

import math
import numbers


class SkydomeError(Exception):
    """Base class of all errors raised by skydome for bad input or environment."""


class ParameterError(SkydomeError, ValueError):
    """An input value is outside its valid range or of the wrong kind."""


class GLError(SkydomeError, RuntimeError):
    """No usable OpenGL context, or a shader failed to compile or link."""


class OutputError(SkydomeError, OSError):
    """An output file cannot be written (bad path, extension or permissions)."""


class CacheError(SkydomeError):
    """A cached file is unreadable, truncated or does not match its key."""


class SkydomeWarning(UserWarning):
    """Base class of the warnings skydome itself gives (e.g. a damaged cache file rebuilt).

    The CLI prints them as one line ``skydome: warning: <message>`` on stderr; warnings of
    other libraries (NumPy, Pillow, moderngl...) are not shown there."""


def check_range(name: str, value: float, lo: float, hi: float, unit: str = "") -> float:
    """Return ``float(value)`` or raise ParameterError naming the valid range [lo, hi].

    A ``name`` that is a command-line flag (starts with ``--``) gets the message in plain
    words, ``--fov 500 deg is outside the valid range 0.01 to 179 deg``; a keyword argument
    gets interval notation, ``fov_deg = 500 deg is outside the valid range [0.01, 179.0] deg``.
    """
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(f"{name} must be a number, got {value!r}") from None
    if not (lo <= v <= hi):  # also rejects NaN
        u = f" {unit}" if unit else ""
        if name.startswith("--"):
            raise ParameterError(f"{name} {v:g}{u} is outside the valid range {lo:g} to {hi:g}{u}")
        raise ParameterError(f"{name} = {value}{u} is outside the valid range [{lo}, {hi}]{u}")
    return v


def check_integer(name: str, value, lo: int, hi: int, meaning: str = "") -> int:
    """Return ``int(value)`` if it is an integer (not a bool) in [lo, hi], else raise
    ParameterError naming the range (``meaning``: words after it, e.g. what it counts)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not lo <= value <= hi:
        raise ParameterError(
            f"{name} = {value!r} must be an integer in [{lo}, {hi}]"
            + (f" ({meaning})" if meaning else "")
        )
    return int(value)


#: The fastest wind (m/s) a sky takes: past the strongest gusts on record (~113 m/s).
WIND_LIMIT_M_S = 200.0


def check_wind(value) -> tuple[float, float]:
    """Return an (east, north) wind ``value`` (m/s) as two floats, or raise ParameterError:
    two finite numbers, each within WIND_LIMIT_M_S."""
    try:
        wind = tuple(float(v) for v in value)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(f"wind must be (east, north) m/s, got {value!r}") from None
    if len(wind) != 2 or not all(math.isfinite(v) and abs(v) <= WIND_LIMIT_M_S for v in wind):
        raise ParameterError(
            f"wind must be (east, north) m/s, each within {WIND_LIMIT_M_S:g} m/s, got {value!r}"
        )
    return wind


def check_rates(name: str, values, unit: str):
    """Return ``values`` (a number or an array) as a float64 array, or raise ParameterError
    unless every one is finite and >= 0 (rates: of rain, of snow)."""
    import numpy as np  # here: the command line imports this module before NumPy

    v = np.asarray(values, float)
    if not np.all(np.isfinite(v)) or np.any(v < 0):
        raise ParameterError(f"{name} must be >= 0 {unit}, got {values!r}")
    return v


def check_choice(name: str, value: str, choices, what: str) -> str:
    """Return ``value`` if it is one of ``choices``, else raise ParameterError naming them as
    plain words, e.g. ``--camera pinhole: unknown camera; choose one of perspective, fisheye``.

    Args:
        name: what the user typed the value as (a CLI flag or a keyword argument).
        value: the given value.
        choices: the valid values (an iterable of str, e.g. a dict's keys), in the order shown.
        what: what the value names, e.g. "camera".
    """
    names = [str(c) for c in choices]
    if value not in names:
        raise ParameterError(f"{name} {value}: unknown {what}; choose one of {', '.join(names)}")
    return value
