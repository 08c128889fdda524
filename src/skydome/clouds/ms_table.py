"""The clouds' multiple-scattering source table: the source function of scattering orders >= 2
in a plane-parallel slab, computed once by Monte Carlo and interpolated per sample.

The renderer lights each cloud sample from a local slab facing the light (shaders/clouds/):
the vertical optical depth ``tau_top`` of the sample below the slab's top, the slab's total
optical thickness ``tau_total``, the light's cosine ``mu0`` to the slab's normal. Single
scattering of the direct beam is computed exactly; the orders >= 2 come from this table,
``skydome/data/cloud_ms_table.npz``, built by ``tools/build_cloud_ms_table.py`` with
:func:`skydome.reference.clouds_mc.slab_source_function` (a conservative slab over a black
ground, phase function :data:`~skydome.clouds.phase.RENDER_PHASE`, i.e. optical depths are
the renderer's, scaled by 1 - :data:`~skydome.clouds.phase.PEAK_FRACTION`; the sibling
``cloud_ms_table.txt`` describes it and its errors).

The table ``J`` (19, 12, 24, 12, 3) holds, on the axes ``tau_total`` (0.25 ... 128, powers of
sqrt 2), ``mu0`` (cosines of 12 zenith angles of the light uniform from acos 0.02 to 0),
``depth_s`` (bin centres of s, the fraction of the
thickness from the top being u = (1 - cos(pi s)) / 2) and ``mu`` (upward cosines of the
direction the scattered light travels in), the Fourier cosine coefficients in the azimuth phi
of that direction from the light's: J2(phi) = J0 + J1 cos(phi) + J2 cos(2 phi), in 1/sr per
unit irradiance normal to the beam (radiance emitted per unit optical path).

:func:`ms_source` is the float64 twin of the GLSL lookup, written to the same specification
(linear in every index, the indices as below), so that the two agree to float32 rounding.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from functools import cache
from importlib import resources

import numpy as np
from numpy.typing import ArrayLike

from skydome.clouds.phase import RENDER_PHASE
from skydome.errors import SkydomeError
from skydome.physics.phase import henyey_greenstein

__all__ = ["MS_TABLE_FILE", "MSTable", "load_ms_table", "ms_source", "table_axes"]

#: The packaged table (built by ``tools/build_cloud_ms_table.py``).
MS_TABLE_FILE = "cloud_ms_table.npz"
_TOOL = "tools/build_cloud_ms_table.py"
#: Axis sizes: tau_total, mu0, depth bins, mu; Fourier coefficients.
N_TAU, N_MU0, N_DEPTH, N_MU, N_FOURIER = 19, 12, 24, 12, 3
#: Thickness nodes per doubling of tau_total.
TAU_NODES_PER_OCTAVE = 2
#: The lowest cosine of the light of the table (its zenith angle acos 0.02 = 88.85 deg).
MU0_MIN = 0.02
#: The thinnest slab of the table; thinner ones scale its values by tau_total / TAU_MIN.
TAU_MIN = 0.25


def table_axes() -> dict[str, np.ndarray]:
    """The table's axes as specified (float64): ``tau_total`` = 2^(-2 + k / 2), k = 0 ... 18;
    ``mu0`` = cos(acos(0.02) (1 - k / 11)), k = 0 ... 11 (uniform in the light's zenith angle:
    the azimuth structure grows as its sine); ``depth_s`` = (k + 0.5) / 24; ``mu`` (12 upward
    cosines)."""
    return {
        "tau_total": 2.0 ** (-2.0 + np.arange(N_TAU) / TAU_NODES_PER_OCTAVE),
        "mu0": np.cos(math.acos(MU0_MIN) * (1.0 - np.arange(N_MU0) / (N_MU0 - 1))),
        "depth_s": (np.arange(N_DEPTH) + 0.5) / N_DEPTH,
        "mu": np.array(
            [-1.0, -0.85, -0.65, -0.45, -0.25, -0.08, 0.08, 0.25, 0.45, 0.65, 0.85, 1.0]
        ),
    }


@dataclass(frozen=True)
class MSTable:
    """The packaged table (see the module docstring): axes ``tau_total`` (19,), ``mu0``
    (12,), ``depth_s`` (24,), ``mu`` (12,); ``J`` (19, 12, 24, 12, 3) float32 Fourier
    coefficients (1/sr); the phase function it is for (``phase_values``: RENDER_PHASE's
    table); ``photons`` (19, 12) per run and the base ``seed`` of the runs; ``norm_g`` (19,)
    the peak shape's asymmetry per thickness."""

    tau_total: np.ndarray
    mu0: np.ndarray
    depth_s: np.ndarray
    mu: np.ndarray
    J: np.ndarray
    phase_values: np.ndarray
    photons: np.ndarray
    seed: int
    norm_g: np.ndarray


def peak_shape(cos_theta, g) -> np.ndarray:
    """The table's peak normalisation h = HG(cos theta, g) (1/sr)."""
    return henyey_greenstein(cos_theta, g)


def _read(raw: bytes) -> MSTable:
    with np.load(io.BytesIO(raw), allow_pickle=False) as z:
        d = {k: z[k] for k in z.files}
    axes = table_axes()
    for name, ref in axes.items():
        if d[name].shape != ref.shape or not np.allclose(d[name], ref, rtol=0, atol=1e-12):
            raise SkydomeError(f"axis {name} is not the specified one")
    if d["J"].shape != (N_TAU, N_MU0, N_DEPTH, N_MU, N_FOURIER) or d["J"].dtype != np.float32:
        raise SkydomeError(f"J has shape {d['J'].shape} and type {d['J'].dtype}")
    if d.get("norm_g", np.zeros(0)).shape != (N_TAU,):
        raise SkydomeError("norm_g (the peak normalisation per thickness) is missing")
    if not np.all(np.isfinite(d["J"])):
        raise SkydomeError("J is not finite")
    values = d.get("phase_values", np.zeros(0))
    if values.shape != RENDER_PHASE.values.shape or not np.allclose(
        values, RENDER_PHASE.values, rtol=1e-9, atol=0
    ):
        raise SkydomeError(
            "it was built for another phase function than skydome.clouds.phase.RENDER_PHASE"
        )
    return MSTable(
        tau_total=d["tau_total"],
        mu0=d["mu0"],
        depth_s=d["depth_s"],
        mu=d["mu"],
        J=d["J"],
        phase_values=d["phase_values"],
        photons=d["photons"],
        seed=int(d["seed"]),
        norm_g=np.asarray(d["norm_g"], dtype=np.float64),
    )


@cache
def load_ms_table() -> MSTable:
    """The packaged multiple-scattering table (read once per process). A missing, foreign or
    stale file (other axes, shape, or a phase function other than RENDER_PHASE) raises
    SkydomeError naming the tool that rebuilds it."""
    try:
        raw = resources.files("skydome.data").joinpath(MS_TABLE_FILE).read_bytes()
        return _read(raw)
    except Exception as exc:  # missing, truncated, foreign or stale file
        raise SkydomeError(
            f"the packaged cloud multiple-scattering table {MS_TABLE_FILE} cannot be used "
            f"({exc}); rebuild it with {_TOOL}"
        ) from exc


def _linear(x: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(lower index, weight of the upper one) of a continuous index x in [0, n - 1]."""
    i = np.clip(np.floor(x), 0, n - 2).astype(np.intp)
    return i, x - i


def ms_source(
    tau_top: ArrayLike,
    tau_total: ArrayLike,
    mu0: ArrayLike,
    mu_up: ArrayLike,
    cos_phi: ArrayLike,
    *,
    table: MSTable | None = None,
) -> np.ndarray:
    """The source function of orders >= 2 (1/sr, per unit irradiance normal to the beam) at
    vertical optical depth ``tau_top`` below the top of a slab of thickness ``tau_total``
    (both in the renderer's scaled optical depth), lit at cosine ``mu0``, towards the
    direction of upward cosine ``mu_up`` whose azimuth from the light's has cosine
    ``cos_phi`` (arguments broadcast). Interpolation, as the GLSL does it:

    - depth: u = clamp(tau_top / tau_total, 0, 1), s = acos(1 - 2 u) / pi, index
      x = clamp(24 s - 0.5, 0, 23), linear;
    - thickness: y = clamp(2 (log2(tau_total) + 2), 0, 18), linear; below 0.25 the value
      is scaled by tau_total / 0.25 (orders >= 2 vanish linearly in thin slabs);
    - light: z = 11 (1 - acos(clamp(mu0, 0.02, 1)) / acos(0.02)), linear;
    - direction: linear between the two ``mu`` entries around mu_up (clamped);
    - per thickness node: J2 = h (c0 + c1 cos_phi + c2 (2 cos_phi^2 - 1)) of the
      coefficients interpolated in the other three indices, h = HG(cos theta, norm_g) of
      the scattering angle from the beam in the slab, cos theta = -mu mu0 - sqrt(1 - mu^2)
      sqrt(1 - mu0^2) cos_phi (mu clamped to the table's); the two nodes' J2 linear in y;
      clamped >= 0.

    A slab of tau_total <= 0 gives 0."""
    t = load_ms_table() if table is None else table
    tau_top, tau_total, mu0, mu_up, cos_phi = np.broadcast_arrays(
        *(np.asarray(a, dtype=np.float64) for a in (tau_top, tau_total, mu0, mu_up, cos_phi))
    )
    positive = tau_total > 0.0
    safe_total = np.where(positive, tau_total, 1.0)
    u = np.clip(tau_top / safe_total, 0.0, 1.0)
    s = np.arccos(1.0 - 2.0 * u) / np.pi
    ix, fx = _linear(np.clip(s * N_DEPTH - 0.5, 0.0, N_DEPTH - 1.0), N_DEPTH)
    y = TAU_NODES_PER_OCTAVE * (np.log2(safe_total) + 2.0)
    iy, fy = _linear(np.clip(y, 0.0, N_TAU - 1.0), N_TAU)
    mu0 = np.clip(mu0, MU0_MIN, 1.0)  # the table's range (the peak shape's too)
    z = (N_MU0 - 1) * (1.0 - np.arccos(mu0) / math.acos(MU0_MIN))
    iz, fz = _linear(np.clip(z, 0.0, N_MU0 - 1.0), N_MU0)
    m = np.clip(mu_up, t.mu[0], t.mu[-1])
    iw = np.clip(np.searchsorted(t.mu, m, side="right") - 1, 0, N_MU - 2)
    fw = (m - t.mu[iw]) / (t.mu[iw + 1] - t.mu[iw])
    J = t.J
    c = cos_phi
    # the scattering angle from the beam in the slab (the table's geometry)
    cos_theta = (
        -m * mu0
        - np.sqrt(np.maximum(1.0 - m * m, 0.0)) * np.sqrt(np.maximum(1.0 - mu0 * mu0, 0.0)) * c
    )
    j2 = np.zeros(tau_top.shape)
    for dy, wy in ((0, 1.0 - fy), (1, fy)):
        coef = np.zeros(tau_top.shape + (N_FOURIER,))
        for dz, wz in ((0, 1.0 - fz), (1, fz)):
            for dx, wx in ((0, 1.0 - fx), (1, fx)):
                for dw, ww in ((0, 1.0 - fw), (1, fw)):
                    w = wz * wx * ww
                    coef += w[..., None] * J[iy + dy, iz + dz, ix + dx, iw + dw].astype(float)
        series = coef[..., 0] + coef[..., 1] * c + coef[..., 2] * (2.0 * c * c - 1.0)
        j2 = j2 + wy * peak_shape(cos_theta, t.norm_g[iy + dy]) * series
    thin = np.where(tau_total < TAU_MIN, tau_total / TAU_MIN, 1.0)
    return np.where(positive, np.maximum(j2, 0.0) * thin, 0.0)
