"""A root of a function by bisection (the tests' own: scipy is not among their needs)."""

from __future__ import annotations

from collections.abc import Callable


def bisect_root(f: Callable[[float], float], lo: float, hi: float, xtol: float = 1e-9) -> float:
    """The root of ``f`` in [lo, hi] (f(lo) and f(hi) of opposite signs) to ``xtol``."""
    f_lo, f_hi = f(lo), f(hi)
    if f_lo == 0.0:
        return lo
    if f_hi == 0.0:
        return hi
    if (f_lo > 0.0) == (f_hi > 0.0):
        raise ValueError(f"no sign change in [{lo}, {hi}]: f = {f_lo}, {f_hi}")
    while hi - lo > xtol:
        mid = 0.5 * (lo + hi)
        f_mid = f(mid)
        if f_mid == 0.0:
            return mid
        if (f_mid > 0.0) == (f_lo > 0.0):
            lo, f_lo = mid, f_mid
        else:
            hi = mid
    return 0.5 * (lo + hi)
