"""Series data shipped with the package and the fast evaluators that use them.

The coefficients come from ``src/skydome/data/astro_series.npz``, written by
``tools/build_astro_tables.py`` (VSOP87D truncated, ELP2000-82 of Meeus ch. 47,
IAU 1980 nutation of Meeus table 22.A). Nothing here is public API.

Evaluating a trigonometric series costs one cosine per term and per time, which
dominates the cost of the astronomy layer. For long, dense arrays of times the
smooth series are therefore sampled at Chebyshev nodes on fixed-length segments
of the time axis and interpolated (:func:`smooth`), as planetary ephemerides do;
the interpolation error is kept below 1e-4 arcsec (the float64 resolution of a
Julian Date, 40 us, is the floor) and is checked in the tests.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from importlib import resources

import numpy as np

J2000 = 2451545.0  # JD of the epoch J2000.0 (TT)
DAYS_PER_MILLENNIUM = 365250.0


@functools.lru_cache(maxsize=1)
def tables() -> dict[str, np.ndarray]:
    """Load the packaged coefficient tables once."""
    path = resources.files("skydome").joinpath("data/astro_series.npz")
    with path.open("rb") as fh, np.load(fh) as npz:
        return {k: npz[k] for k in npz.files}


class VSOPSeries:
    """One planet's truncated VSOP87D series, grouped by (coordinate, power of tau)."""

    def __init__(self, planet: str) -> None:
        t = tables()
        a = t[f"vsop_{planet}_A"] * 1e-8  # native unit: 1e-8 rad or 1e-8 au
        b = t[f"vsop_{planet}_B"]
        c = t[f"vsop_{planet}_C"]
        coord = t[f"vsop_{planet}_coord"].astype(int)
        power = t[f"vsop_{planet}_power"].astype(int)
        order = np.lexsort((power, coord))
        self.a, self.b, self.c = a[order], b[order], c[order]
        self.coord, self.power = coord[order], power[order]
        self.max_power = int(self.power.max())
        # slices of consecutive terms sharing (coord, power)
        self.groups: list[tuple[int, int, slice]] = []
        keys = self.coord * 16 + self.power
        edges = np.flatnonzero(np.diff(keys)) + 1
        starts = np.concatenate([[0], edges])
        stops = np.concatenate([edges, [keys.size]])
        for s, e in zip(starts, stops, strict=True):
            self.groups.append((int(self.coord[s]), int(self.power[s]), slice(int(s), int(e))))

    def lbr(self, jd_tt: np.ndarray) -> np.ndarray:
        """Heliocentric L, B (rad) and R (au), ecliptic and equinox of date; shape (3, N).

        Meeus eq. 32.1-32.2: X = sum_alpha tau^alpha * sum A cos(B + C tau).
        """
        tau = (np.asarray(jd_tt, dtype=float).ravel() - J2000) / DAYS_PER_MILLENNIUM
        arg = self.b[:, None] + self.c[:, None] * tau[None, :]
        cosines = np.cos(arg, out=arg)
        sums = np.zeros((3, self.max_power + 1, tau.size))
        for coord, power, sl in self.groups:
            sums[coord, power] = self.a[sl] @ cosines[sl]
        out = sums[:, self.max_power].copy()
        for p in range(self.max_power - 1, -1, -1):  # Horner in tau
            out = out * tau + sums[:, p]
        return out


@functools.cache
def vsop(planet: str) -> VSOPSeries:
    """The cached series of ``planet`` (lower-case English name)."""
    return VSOPSeries(planet)


# --------------------------------------------------------------------------- interpolation


@functools.cache
def _cheb_matrix(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev nodes on [-1, 1] and the matrix mapping node values to coefficients."""
    k = np.arange(n)
    theta = np.pi * (k + 0.5) / n
    nodes = np.cos(theta)
    mat = (2.0 / n) * np.cos(np.outer(k, theta))  # c_j = 2/n sum_k f(x_k) cos(j theta_k)
    mat[0] *= 0.5
    return nodes, mat


def smooth(
    func: Callable[[np.ndarray], np.ndarray],
    jd: np.ndarray,
    step_days: float,
    degree: int,
    min_gain: float = 3.0,
) -> np.ndarray:
    """Evaluate ``func(jd) -> (C, N)`` directly or by piecewise Chebyshev interpolation.

    The time axis is cut into segments ``[J2000 + i*step, J2000 + (i+1)*step)``; ``func``
    is evaluated at ``degree + 1`` Chebyshev nodes of every segment that holds a requested
    time, and the interpolant is evaluated at the times. This is used only when it saves at
    least a factor ``min_gain`` of evaluations; otherwise ``func`` is called on ``jd``.
    """
    jd = np.asarray(jd, dtype=float).ravel()
    n = degree + 1
    if jd.size < 4 * n * min_gain:
        return func(jd)
    seg = np.floor((jd - J2000) / step_days)
    useg, inverse = np.unique(seg, return_inverse=True)
    if useg.size * n * min_gain > jd.size:
        return func(jd)
    nodes, mat = _cheb_matrix(n)
    t_nodes = J2000 + (useg[:, None] + 0.5 * (nodes[None, :] + 1.0)) * step_days
    vals = func(t_nodes.ravel())  # (C, M*n)
    ncomp = vals.shape[0]
    coef = vals.reshape(ncomp, useg.size, n) @ mat.T  # (C, M, n)
    coef_j = np.ascontiguousarray(np.moveaxis(coef, 2, 0))  # (n, C, M)
    inverse = inverse.ravel()
    x2 = 2.0 * (2.0 * ((jd - J2000) / step_days - seg) - 1.0)  # 2x, x in [-1, 1]
    # Clenshaw recurrence for sum_j c_j T_j(x), gathering one coefficient plane at a time
    b1 = np.take(coef_j[n - 1], inverse, axis=1)
    b2 = np.zeros_like(b1)
    for j in range(n - 2, 0, -1):
        b1, b2 = x2 * b1 - b2 + np.take(coef_j[j], inverse, axis=1), b1
    return 0.5 * x2 * b1 - b2 + np.take(coef_j[0], inverse, axis=1)
