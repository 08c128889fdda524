"""Exception hierarchy. Every error the user can cause is a SkydomeError subclass.

Messages name the bad value and the valid range; the CLI prints them as one
line on stderr and exits with status 2.
"""


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


def check_range(name: str, value: float, lo: float, hi: float, unit: str = "") -> float:
    """Return ``float(value)`` or raise ParameterError naming the valid range [lo, hi]."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a number, got {value!r}") from None
    if not (lo <= v <= hi):  # also rejects NaN
        u = f" {unit}" if unit else ""
        raise ParameterError(f"{name} = {value}{u} is outside the valid range [{lo}, {hi}]{u}")
    return v
