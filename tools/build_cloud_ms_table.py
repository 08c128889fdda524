#!/usr/bin/env python
"""Build ``src/skydome/data/cloud_ms_table.npz``: the clouds' source function of scattering
orders >= 2, by Monte Carlo (developer tool; the sibling ``cloud_ms_table.txt`` records the
run's numbers).

Usage::

    PYTHONPATH=src .venv/bin/python tools/build_cloud_ms_table.py [--workers 2] [--scale 1]

(about 50 minutes of CPU, 30 of wall time, at the default settings on two cores; ``--scale`` multiplies every
run's photon count, for trials.)

Problem (what the renderer's local slab is): a plane-parallel conservative slab (single-
scattering albedo 1) of optical thickness tau_total over a black ground, nothing above, lit at
its top by a beam of unit irradiance normal to it at cosine mu0; the phase function
:data:`skydome.clouds.phase.RENDER_PHASE` (the droplets' HG mixture without its diffraction
peak, Wiscombe 1977's delta-M as ``LobePhase.delta_truncated(0.98)``): optical depths are the
renderer's scaled ones and there is no further delta scaling in the Monte Carlo.

Method: for each of the 19 x 12 (tau_total, mu0) of the table one run of
:func:`skydome.reference.clouds_mc.slab_source_function` (the forward tracer of
``slab_radiance``; the collision estimator of the source function, Marchuk et al. 1980, *The
Monte Carlo Methods in Atmospheric Optics*, ch. 2), every order >= 2, in the 24 depth bins
between s = k / 24 (u = (1 - cos(pi s)) / 2 of the thickness from the top), towards 52
directions at once: the 12 cosines ``mu``, each at azimuths phi = 0, 45, 90, 135, 180 deg
from the Sun's (phi = 0: towards the Sun's side, +x), except mu = +-1 (one direction). The
Fourier cosine coefficients J0 + J1 cos(phi) + J2 cos(2 phi) are fitted by least squares to
the five azimuths (at mu = +-1: J0 = the value, J1 = J2 = 0). The source is symmetric in phi
(tests/test_clouds_mc.py), so phi in [0, 180] covers it.

Photons: a pilot run of :data:`PILOT_PHOTONS` per entry (its own seeds, then discarded)
measures the median relative standard error r of the entry's J values; the entry then gets
PILOT_PHOTONS (r / TARGET_RELATIVE_SE)^2 photons, clipped to [MIN_PHOTONS, MAX_PHOTONS] and
rounded up to 1000: the same median relative error everywhere, within the CPU budget.

Seeds: entry (i, j) (tau index i, mu0 index j) uses seed + 100 i + j; its pilot
seed + 50 + 100 i + j. The output is deterministic for given settings.
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import time
from pathlib import Path

import numpy as np

from skydome.clouds.ms_table import MS_TABLE_FILE, N_MU0, N_TAU, peak_shape, table_axes
from skydome.clouds.phase import RENDER_PHASE
from skydome.reference.clouds_mc import slab_source_function

OUT = Path(__file__).resolve().parents[1] / "src/skydome/data" / MS_TABLE_FILE
#: Every estimate of the last build (raw, fitted, coefficients, residuals, standard errors).
ESTIMATES = Path(__file__).resolve().parents[1] / "build/cloud_ms_table_estimates.npz"
#: Azimuths (deg) of the estimated directions, from the Sun's.
PHI_DEG = (0.0, 45.0, 90.0, 135.0, 180.0)
SEED = 20240611
PILOT_PHOTONS = 2000
TARGET_RELATIVE_SE = 0.0225
MIN_PHOTONS = 20_000
MAX_PHOTONS = 1_000_000


def depth_edges(tau_total: float) -> np.ndarray:
    """The 25 bin edges in vertical optical depth: tau_total (1 - cos(pi k / 24)) / 2."""
    return tau_total * (1.0 - np.cos(np.pi * np.arange(25) / 24.0)) / 2.0


def table_directions() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(directions (52, 3), their mu index (52,), their azimuth index (52,)): for each table
    cosine mu, (sqrt(1 - mu^2) cos phi, sqrt(1 - mu^2) sin phi, mu) at :data:`PHI_DEG`, and
    one direction (0, 0, mu) at mu = +-1 (azimuth index 0)."""
    dirs, mi, pi = [], [], []
    for i, mu in enumerate(table_axes()["mu"]):
        if abs(mu) == 1.0:
            dirs.append((0.0, 0.0, mu))
            mi.append(i)
            pi.append(0)
            continue
        s = math.sqrt(1.0 - mu * mu)
        for k, phi in enumerate(np.radians(PHI_DEG)):
            dirs.append((s * math.cos(phi), s * math.sin(phi), mu))
            mi.append(i)
            pi.append(k)
    return np.array(dirs), np.array(mi), np.array(pi)


def fourier_matrix() -> np.ndarray:
    """(52, 12 * 3) matrix F with coefficients = J_dirs @ F: per mu, the least-squares fit
    of c0 + c1 cos(phi) + c2 cos(2 phi) to its five azimuths (the pseudo-inverse of
    [1, cos phi, cos 2 phi]); at mu = +-1, c0 = the value and c1 = c2 = 0."""
    _, mi, _ = table_directions()
    phi = np.radians(PHI_DEG)
    pinv = np.linalg.pinv(np.stack([np.ones_like(phi), np.cos(phi), np.cos(2.0 * phi)], 1))
    f = np.zeros((mi.size, 12 * 3))
    for i in range(12):
        rows = np.flatnonzero(mi == i)
        if rows.size == 1:
            f[rows[0], 3 * i] = 1.0
        else:
            f[rows, 3 * i : 3 * i + 3] = pinv.T
    return f


def reconstruct(coef: np.ndarray) -> np.ndarray:
    """The J values (..., 52) at :func:`table_directions` of coefficients (..., 12, 3)."""
    _, mi, pk = table_directions()
    phi = np.radians(np.asarray(PHI_DEG))[pk]
    c = coef[..., mi, :]
    return c[..., 0] + c[..., 1] * np.cos(phi) + c[..., 2] * np.cos(2.0 * phi)


def reconstruct_matrix() -> np.ndarray:
    """(36, 52) matrix R with the J values at :func:`table_directions` = coefficients @ R
    (coefficients flattened (12 * 3,))."""
    _, mi, pk = table_directions()
    phi = np.radians(np.asarray(PHI_DEG))[pk]
    r = np.zeros((12 * 3, mi.size))
    r[3 * mi, np.arange(mi.size)] = 1.0
    r[3 * mi + 1, np.arange(mi.size)] = np.cos(phi)
    r[3 * mi + 2, np.arange(mi.size)] = np.cos(2.0 * phi)
    return r


def estimate(i_tau: int, i_mu0: int, photons: int, seed: int) -> dict[str, np.ndarray]:
    """One entry, tau_total[i_tau] and mu0[i_mu0]: {"coef": the coefficients (24, 12, 3),
    "raw": J at the 52 directions (24, 52), "fit": the fitted J there (24, 52), "resid": raw
    - fit}, and their standard errors "coef_se", "raw_se", "fit_se", "resid_se" (exact: the Monte Carlo combines each
    photon's contributions first, ``slab_source_function(combine=...)``)."""
    axes = table_axes()
    tau, mu0 = float(axes["tau_total"][i_tau]), float(axes["mu0"][i_mu0])
    dirs, _, _ = table_directions()
    f = fourier_matrix()
    eye = np.eye(dirs.shape[0])
    proj = f @ reconstruct_matrix()  # raw values -> fitted values
    combine = np.hstack([eye, f, proj, eye - proj])
    j, se = slab_source_function(
        tau, mu0, depth_edges(tau), dirs, phase=RENDER_PHASE, photons=photons, seed=seed,
        combine=combine,
    )  # fmt: skip
    k = dirs.shape[0]
    out = {}
    for name, a in (("", j), ("_se", se)):
        out["raw" + name] = a[:, :k]
        out["coef" + name] = a[:, k : k + 36].reshape(24, 12, 3)
        out["fit" + name] = a[:, k + 36 : 2 * k + 36]
        out["resid" + name] = a[:, 2 * k + 36 :]
    return out


#: Candidate asymmetries g_n of the peak normalisation, one chosen per thickness.
NORM_G_CANDIDATES = (0.0, 0.1, 0.2, 0.3, 0.4, 0.5)


def peak_normalisation(mu0: float, g: float) -> np.ndarray:
    """h = HG(cos theta, g) (1/sr) at the 52 :func:`table_directions`, theta the scattering
    angle from the beam's direction of travel (-sqrt(1 - mu0^2), 0, -mu0)."""
    dirs, _, _ = table_directions()
    cos_theta = dirs @ np.array([-math.sqrt(1.0 - mu0 * mu0), 0.0, -mu0])
    return peak_shape(cos_theta, g)


def normalised_fit(raw: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The orders >= 2 peak around the beam's direction of travel (the light scattered once
    into the phase function's forward lobe goes on forward), which three azimuth terms and
    linear interpolation in mu and mu0 miss. So the table holds J / h with h = HG(cos theta,
    g_n) (the peak's shape; theta from the beam) and the renderer multiplies h back: g_n per
    thickness from NORM_G_CANDIDATES, the one whose series misses the five azimuths least
    (90th percentile of |fit - raw| / the largest of the five, plus a tenth of the largest).
    ``raw`` (19, 12, 24, 52) -> (coefficients (19, 12, 24, 12, 3), g_n (19,), fit (19, 12, 24,
    52) in J's units)."""
    f = fourier_matrix()
    _, mi, _ = table_directions()
    axes = table_axes()
    peak = np.zeros_like(raw)
    for m in range(12):
        cols = mi == m
        peak[..., cols] = raw[..., cols].max(axis=-1, keepdims=True)
    coef = np.zeros(raw.shape[:3] + (12, 3))
    fit = np.zeros_like(raw)
    norm_g = np.zeros(raw.shape[0])
    for i in range(raw.shape[0]):
        best = None
        for g in NORM_G_CANDIDATES:
            h = np.stack([peak_normalisation(mu0, g) for mu0 in axes["mu0"]])[:, None, :]
            c = ((raw[i] / h) @ f).reshape(raw.shape[1], raw.shape[2], 12, 3)
            fitted = reconstruct(c) * h
            miss = np.abs(fitted - raw[i]) / np.maximum(peak[i], 1e-300)
            score = float(np.percentile(miss, 90) + 0.1 * miss.max())
            if best is None or score < best[0]:
                best = (score, g, c, fitted)
        _, norm_g[i], coef[i], fit[i] = best
    return coef, norm_g, fit


def refit(e: dict[str, np.ndarray]) -> np.ndarray:
    """Replace the estimates' coefficients, fit and residuals by :func:`normalised_fit`'s;
    returns g_n. (The standard errors stay those of the raw estimates' series: close.)"""
    coef, norm_g, fit = normalised_fit(e["raw"])
    e["coef"], e["fit"], e["resid"] = coef, fit, e["raw"] - fit
    return norm_g


def _tau(i: int) -> float:
    return float(table_axes()["tau_total"][i])


def _median_rel(e: dict[str, np.ndarray]) -> float:
    """The median relative standard error of an entry's fitted J values."""
    return float(np.median(e["fit_se"] / np.maximum(np.abs(e["fit"]), 1e-300)))


def _job(args):
    i, k, photons, seed = args
    t0, c0 = time.perf_counter(), time.process_time()
    e = estimate(i, k, photons, seed)
    return i, k, photons, e, time.perf_counter() - t0, time.process_time() - c0


def _run(jobs, workers: int, label: str, t_start: float):
    """{(i, k): estimate} of the jobs, and the CPU seconds they took."""
    out, cpu = {}, 0.0
    with multiprocessing.Pool(workers) as pool:
        for n_done, (i, k, n, e, dt, dc) in enumerate(pool.imap_unordered(_job, jobs), start=1):
            out[(i, k)] = e
            cpu += dc
            print(
                f"{label} {n_done:2d}/{len(jobs)} tau {_tau(i):7.2f} mu0 index {k:2d} "
                f"{n:7d} photons {dt:6.1f} s, median rel. se {_median_rel(e):.4f} "
                f"(elapsed {time.perf_counter() - t_start:6.1f} s)",
                flush=True,
            )
    return out, cpu


def allocate(pilot_rel: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """Photons per entry (19, 12) from the pilot's median relative errors (module docstring)."""
    n = PILOT_PHOTONS * (pilot_rel / TARGET_RELATIVE_SE) ** 2
    n = np.clip(n, MIN_PHOTONS, MAX_PHOTONS) * scale
    return (np.ceil(n / 1000.0) * 1000).astype(np.int64)


def _q(x: np.ndarray) -> str:
    p = np.percentile(x, [50, 75, 90, 99])
    return (
        f"median {p[0]:.4f}, 75 % {p[1]:.4f}, 90 % {p[2]:.4f}, 99 % {p[3]:.4f}, max "
        f"{x.max():.3f}; below 2 %: {np.mean(x < 0.02):.1%}, below 5 %: {np.mean(x < 0.05):.1%}"
    )


def statistics(e: dict[str, np.ndarray]) -> list[str]:
    """Lines describing the errors of the estimates ``e`` (the arrays of :func:`estimate`
    stacked to (19, 12, ...))."""
    rel = e["fit_se"] / np.maximum(np.abs(e["fit"]), 1e-300)
    raw = e["raw_se"] / np.maximum(e["raw"], 1e-300)
    c0 = e["coef_se"][..., 0] / np.maximum(e["coef"][..., 0], 1e-300)
    lines = [
        "relative standard error of the table's J at its nodes (the 3-term series at the 52",
        f"  directions, {N_TAU} x {N_MU0} x 24 x 52 values): {_q(rel)}",
        f"  of the raw estimates at the 52 directions: {_q(raw)}",
        f"  of the azimuthal mean J[..., 0]: {_q(c0)}",
        "by tau_total (median / 90 % / share below 2 %, table J at the nodes):",
    ]
    for i in range(N_TAU):
        r = rel[i]
        lines.append(
            f"  tau {_tau(i):7.2f}: {np.median(r):.4f} / {np.percentile(r, 90):.4f} / "
            f"{np.mean(r < 0.02):.0%}"
        )
    lines.append("by depth bin, 0 at the top (median over tau, mu0, directions):")
    med = np.median(rel, axis=(0, 1, 3))
    lines.append("  " + " ".join(f"{v:.3f}" for v in med[:12]))
    lines.append("  " + " ".join(f"{v:.3f}" for v in med[12:]))
    deep = rel[-6:, :, 18:, :]
    lines.append(
        f"deepest quarter (bins 18-23) of tau 32-128: median {np.median(deep):.4f}, "
        f"90 % {np.percentile(deep, 90):.4f}"
    )
    _, mi, _ = table_directions()
    mu = table_axes()["mu"]
    side = np.abs(mu[mi]) < 1.0
    z = e["resid"][..., side] / np.maximum(e["resid_se"][..., side], 1e-300)

    def rms(a, axis):
        return np.sqrt(np.mean(a * a, axis=axis))

    lines.append(
        "Fourier fit (3 terms to 5 azimuths), residual / its standard error: RMS "
        f"{float(rms(z, None)):.2f} (1 for an adequate fit), |z| > 4: {np.mean(np.abs(z) > 4):.1%}"
    )
    lines.append("  RMS by mu0 index: " + " ".join(f"{v:.1f}" for v in rms(z, (0, 2, 3))))
    lines.append("  RMS by tau_total: " + " ".join(f"{v:.1f}" for v in rms(z, (1, 2, 3))))
    by_mu = [float(rms(z[..., mi[side] == m], None)) for m in range(1, 11)]
    lines.append("  RMS by mu (-0.85 ... 0.85): " + " ".join(f"{v:.1f}" for v in by_mu))
    # the misfit relative to the largest of the five azimuths' values (per bin and mu)
    peak = np.zeros_like(e["raw"])
    for m in range(1, 11):
        cols = mi == m
        peak[..., cols] = e["raw"][..., cols].max(axis=-1, keepdims=True)
    mis = (np.abs(e["resid"]) / np.maximum(peak, 1e-300))[..., side]
    q = np.percentile(mis, [50, 90, 99])
    lines.append(
        "  |raw - fit| / (largest raw value of the 5 azimuths): median "
        f"{q[0]:.3f}, 90 % {q[1]:.3f}, 99 % {q[2]:.3f}, max {mis.max():.3f}"
    )
    lines.append(
        "  its 99 % by mu0 index: "
        + " ".join(f"{np.percentile(mis[:, k], 99):.3f}" for k in range(N_MU0))
    )
    near = np.isin(mi[side], (5, 6))  # mu = -0.08, 0.08
    lines.append(
        f"  at mu = +-0.08: 99 % {np.percentile(mis[..., near], 99):.3f}, elsewhere 99 % "
        f"{np.percentile(mis[..., ~near], 99):.3f}"
    )
    lines.append(
        f"table J at the estimated directions: min {e['fit'].min():.3e}, negative: "
        f"{int(np.sum(e['fit'] < 0))}; J[..., 0] min {e['coef'][..., 0].min():.3e}"
    )
    return lines


def build(
    workers: int = 2, scale: float = 1.0, seed: int = SEED, pilot_photons: int = PILOT_PHOTONS
):
    """(arrays for the npz, report lines, the estimates of :func:`estimate` stacked to
    (19, 12, ...))."""
    t0 = time.perf_counter()
    jobs = [
        (i, k, pilot_photons, seed + 50 + 100 * i + k) for i in range(N_TAU) for k in range(N_MU0)
    ]
    jobs.sort(key=lambda a: -a[0])  # thickest (slowest) first
    pilot, cpu_pilot = _run(jobs, workers, "pilot", t0)
    pilot_rel = np.array([[_median_rel(pilot[(i, k)]) for k in range(N_MU0)] for i in range(N_TAU)])
    photons = allocate(pilot_rel * math.sqrt(pilot_photons / PILOT_PHOTONS), scale)
    t_pilot = time.perf_counter() - t0
    cost = photons * table_axes()["tau_total"][:, None]  # rough: collisions ~ tau_total
    jobs = [
        (i, k, int(photons[i, k]), seed + 100 * i + k) for i in range(N_TAU) for k in range(N_MU0)
    ]
    jobs.sort(key=lambda a: -cost[a[0], a[1]])
    runs, cpu_main = _run(jobs, workers, "run", t0)
    runtime = time.perf_counter() - t0
    e = {
        name: np.stack([np.stack([runs[(i, k)][name] for k in range(N_MU0)]) for i in range(N_TAU)])
        for name in runs[(0, 0)]
    }
    norm_g = refit(e)
    axes = table_axes()
    arrays = {
        "norm_g": norm_g,
        "tau_total": axes["tau_total"],
        "mu0": axes["mu0"],
        "depth_s": axes["depth_s"],
        "mu": axes["mu"],
        "J": e["coef"].astype(np.float32),
        "phase_values": np.asarray(RENDER_PHASE.values),
        "photons": photons,
        "seed": np.int64(seed),
    }
    lines = [
        f"photons per (tau_total, mu0): {int(photons.min())} to {int(photons.max())}, "
        f"{int(photons.sum())} in all (scale {scale}); pilot {pilot_photons} each",
        f"runtime: {runtime:.0f} s wall with {workers} worker processes (pilot {t_pilot:.0f} s), "
        f"{cpu_pilot + cpu_main:.0f} s CPU (pilot {cpu_pilot:.0f} s)",
    ] + statistics(e)
    return arrays, lines, e


TXT_HEAD = """\
cloud_ms_table.npz: the clouds' source function of scattering orders >= 2
==========================================================================

Built by tools/build_cloud_ms_table.py (its docstring has the details); read by
skydome.clouds.ms_table (load_ms_table, ms_source: the float64 twin of the GLSL lookup).

Problem
  A plane-parallel conservative slab (single-scattering albedo 1) of optical thickness
  tau_total over a black ground, lit at its top by a collimated beam of unit irradiance
  (normal to the beam) at cosine mu0, Sun at azimuth 0. Phase function RENDER_PHASE of
  skydome.clouds.phase: the droplets' Mie phase function (tools/build_cloud_phase.py,
  r_eff 10 um, 550 nm) with its diffraction peak cut flat at TRUNCATION_DEG (5 deg), the
  light inside it counted as unscattered (PEAK_FRACTION of the scattering). Optical depths
  are thus the renderer's scaled ones, (1 - PEAK_FRACTION) times the real ones.

Arrays
  tau_total (19,)  2^(-2 + k / 2), 0.25 ... 128 (scaled optical thickness)
  mu0 (12,)        cos(acos(0.02) (1 - k / 11)): cosine of the light to the slab's normal,
                   uniform in its zenith angle
  depth_s (24,)    bin centres (k + 0.5) / 24 of s; the fraction of the thickness from the
                   top is u = (1 - cos(pi s)) / 2; the bins lie between s = k / 24
  mu (12,)         upward cosine of the direction the scattered light travels in
  J (19, 12, 24, 12, 3) float32, per unit irradiance normal to the beam (J2, the radiance
                   emitted per unit optical path, in 1/sr, divided by the peak shape h):
                   Fourier cosine coefficients in the azimuth phi of that direction from the
                   Sun's (phi = 0: towards the Sun's side),
                   J2 = h(cos theta) (J[..., 0] + J[..., 1] cos(phi) + J[..., 2] cos(2 phi)),
                   each the average over its depth bin; h = HG(cos theta, norm_g[tau]) with
                   theta the scattering angle from the beam, cos theta = -mu mu0 -
                   sqrt(1 - mu^2) sqrt(1 - mu0^2) cos(phi)
  norm_g (19,)     the peak shape's asymmetry per thickness (the orders >= 2 peak around
                   the beam's direction; dividing it out leaves a smooth function that three
                   azimuth terms and linear interpolation hold: the misfit to the five
                   estimated azimuths halves)
  phase_values     RENDER_PHASE's table (2048 angles)
  photons (19, 12) photons of each (tau_total, mu0) run; seed: the base seed (run (i, j)
                   used seed + 100 i + j)

Method
  Forward Monte Carlo (skydome.reference.clouds_mc.slab_source_function: Marchuk et al.
  1980, The Monte Carlo Methods in Atmospheric Optics, ch. 2; the tracer of slab_radiance,
  tested against DISORT / van de Hulst's tables): first collision forced inside the slab,
  analog escape. Collision estimator: J(bin k, v) = (1 / dtau_k) sum over the collisions in
  bin k of photons that have already scattered, of w P(u . v), w = mu0 / N, u the direction
  before the collision. 52 directions per run (the 12 mu at phi = 0, 45, 90, 135, 180 deg;
  one at mu = +-1), the coefficients of J2 / h fitted by least squares to the five azimuths.

Errors (standard errors from the spread over photons of each photon's contribution, exact
for every linear combination of the 52 estimates: the table's 3-term series at the nodes, the
raw estimates, the azimuthal mean; relative ones blow up where a value is near 0)
"""

TXT_TAIL = """
Limits
  - Noise: the relative errors above are largest in the thinnest slabs' narrow edge bins (few
    collisions of order >= 2 fall there) and deep in thick slabs far from the light, where
    little light arrives (the collision estimator's variance is set by the photons that get
    there). The azimuthal mean J[..., 0] is better determined than the values at each azimuth.
  - Azimuth: three cosine terms of J2 / h (h the peak shape) miss the five estimated azimuths
    by 0.5 % of their largest value at the median, 2.3 % at the 90th percentile, 6.2 % at
    the 99th and 24 % at most (above: more than the noise, RMS 2.8 standard errors, most at
    grazing light, mu0 index 0-2, and near-horizontal directions); no node's series is
    negative. The light's zenith angle is sampled uniformly (the azimuth structure grows as
    its sine): between the former nodes (0.02 + 0.98 (k / 7)^1.5) near a high Sun the
    interpolated source was off by up to 18 % towards and away from the Sun.
  - Phase function: RENDER_PHASE is the Mie table itself beyond 5 deg (cloudbow and glory
    included); the light within 5 deg of the beam is treated as unscattered.
"""


def old_text_head(path: Path) -> list[str]:
    """The photon and runtime lines of the last build's description (a refit keeps them)."""
    lines = path.read_text().splitlines()
    return [ln.strip() for ln in lines if ln.strip().startswith(("photons per", "runtime:"))]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--scale", type=float, default=1.0, help="photon count multiplier")
    ap.add_argument("--pilot", type=int, default=PILOT_PHOTONS, help="pilot photons")
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument(
        "--refit",
        action="store_true",
        help="refit the last build's estimates (build/) without a Monte Carlo",
    )
    args = ap.parse_args(argv)
    if args.refit:
        e = dict(np.load(ESTIMATES))
        old = dict(np.load(args.out))
        norm_g = refit(e)
        arrays = {**old, "norm_g": norm_g, "J": e["coef"].astype(np.float32)}
        head = old_text_head(args.out.with_suffix(".txt"))
        lines = head + statistics(e)
    else:
        arrays, lines, e = build(args.workers, args.scale, pilot_photons=args.pilot)
    print("\n".join(lines))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(args.out, **arrays)
    args.out.with_suffix(".txt").write_text(
        TXT_HEAD + "".join(f"  {ln}\n" for ln in lines) + TXT_TAIL
    )
    ESTIMATES.parent.mkdir(parents=True, exist_ok=True)
    if not args.refit:
        np.savez_compressed(ESTIMATES, **e)  # for later analysis (build/ is not committed)
    print(f"wrote {args.out}, {args.out.with_suffix('.txt')} and {ESTIMATES}")


if __name__ == "__main__":
    main()
