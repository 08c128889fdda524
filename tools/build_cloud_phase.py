"""Build the cloud droplet phase function's two packaged tables: skydome/data/
cloud_droplet_mie_phase.csv (the Mie phase function itself, tabulated in angle: what the
renderer scatters with, skydome.clouds.phase.MIE_PHASE) and cloud_droplet_phase.csv (the same
fitted by HG lobes: skydome.clouds.phase.CLOUD_PHASE, the Monte Carlo tests' analytic form).

Usage::

    python tools/build_cloud_phase.py          # about 80 s

Model (each input's source)
---------------------------
- Droplets: liquid water spheres, refractive index m = 1.333 + 0i at 550 nm (Hale & Querry
  1973, Appl. Opt. 12, 555: n = 1.333, k ~ 2e-9, negligible over a cloud's path).
- Size distribution: the modified gamma distribution of Hansen & Travis (1974, Space Sci. Rev.
  16, 527, eq. 2.56) with effective radius 10 um and effective variance 0.1, their standard
  water cloud (sec. 2, Figs. 8-11): size parameter 2 pi r_eff / lambda = 114.
- Mie theory: ``skydome.atmosphere.mie.bulk_optics`` (Bohren & Huffman series, n_stop = x +
  4 x^(1/3) + 2, i.e. ~960 terms at the largest radius 8 r_eff = 80 um), 16000 radii (1000
  left the side and back directions 1-8 % off miepython: the phase function of one droplet
  swings with its size faster than 1000 radii sample; tests/test_droplet_phase_miepython.py).

Fit
---
P_fit = sum_j w_j HG(g_j) over a candidate set of asymmetries (:data:`CANDIDATE_G`), w_j >= 0,
minimising the squared error of ln P_fit - ln P_Mie at the angles :data:`THETA_DEG` (uniform in
angle, denser over the diffraction peak), subject to sum w_j = 1 and sum w_j g_j = the Mie
asymmetry parameter (the similarity parameter 1 - g sets a thick cloud's albedo, so the fit
keeps it). The log misfit is minimised by Gauss-Newton steps, each one a non-negative least
squares problem (``mie.nnls``, Lawson & Hanson) with the two constraints as heavily weighted
rows; the steps are halved until the misfit falls. Lobes with zero weight are dropped.

HG lobes are monotone in angle, so no mixture reproduces the cloudbow (140 deg) and the glory
(180 deg) or the deep side-scattering minimum (100 deg): the best log fit over all non-negative
mixtures of the candidates (without the constraints) has an RMS log error of 0.66 over
5-175 deg; with them, 0.70. The file's header records the numbers.

Columns: weight, g (one row per lobe, the weights sum to 1).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from skydome.atmosphere.mie import bulk_optics, hg_lobes, nnls
from skydome.physics.phase import henyey_greenstein

DATA = Path(__file__).resolve().parents[1] / "src/skydome/data"
OUT = DATA / "cloud_droplet_phase.csv"
MIE_OUT = DATA / "cloud_droplet_mie_phase.csv"
WAVELENGTH_UM, R_EFF_UM, V_EFF, M_WATER = 0.55, 10.0, 0.1, 1.333 + 0.0j
RADII = 16000
#: Scattering angles (deg): 0.025 deg steps over the diffraction peak, 0.05 deg beyond.
THETA_DEG = np.concatenate([np.linspace(0.0, 10.0, 401), np.linspace(10.05, 180.0, 3400)])
#: Candidate lobe asymmetries: dense near 1 for the ~1 deg wide diffraction peak (a lobe's width
#: is about 1 - g radians), a few broad and backward ones.
CANDIDATE_G = (0.998, 0.996, 0.994, 0.992, 0.99, 0.985, 0.98, 0.97, 0.96, 0.94, 0.92, 0.9,
               0.87, 0.84, 0.8, 0.75, 0.7, 0.6, 0.5, 0.3, 0.0, -0.2, -0.4, -0.6, -0.8)  # fmt: skip
#: Weight of the constraint rows relative to one angle's log residual.
CONSTRAINT_WEIGHT = 1.0e3
ITERATIONS = 40
#: Range where the log error is reported (the 0 and 180 deg ends are single points).
REPORT_RANGE_DEG = (5.0, 175.0)


def mie_phase(radii: int = RADII):
    """(theta_deg, phase in 1/sr, asymmetry) of the droplet distribution from Mie theory."""
    optics = bulk_optics(M_WATER, WAVELENGTH_UM, R_EFF_UM, V_EFF, np.cos(np.radians(THETA_DEG)),
                         radii=radii)  # fmt: skip
    return THETA_DEG.copy(), optics.phase, optics.asymmetry


def fit_lobes(theta_deg, phase, g_target: float, candidates=CANDIDATE_G):
    """Non-negative weights (summing to 1, first moment ``g_target``) of HG lobes of
    asymmetries ``candidates`` that minimise the squared log error against ``phase`` (1/sr)
    at ``theta_deg``; returns (weights, g) of the lobes with non-zero weight, by decreasing g."""
    g = np.asarray(candidates, float)
    h = henyey_greenstein(np.cos(np.radians(theta_deg))[:, None], g[None, :])
    p = np.asarray(phase, float)
    s = CONSTRAINT_WEIGHT * np.sqrt(p.size)
    c_rows = np.vstack([np.ones_like(g), g]) * s
    c_rhs = np.array([1.0, g_target]) * s

    def misfit(w):
        return float(np.sum(np.log(h @ w / p) ** 2) + np.sum((c_rows @ w - c_rhs) ** 2))

    # Start: the linear fit in relative error, sum_j w_j HG_ij / P_i ~ 1.
    w = nnls(np.vstack([h / p[:, None], c_rows]), np.concatenate([np.ones_like(p), c_rhs]))
    for _ in range(ITERATIONS):
        f = h @ w
        # ln(f + h dw) ~ ln f + h dw / f: solve for the new weights w' = w + dw >= 0.
        w_new = nnls(np.vstack([h / f[:, None], c_rows]),
                     np.concatenate([1.0 + np.log(p / f), c_rhs]))  # fmt: skip
        step, m0 = 1.0, misfit(w)
        while step > 1e-3 and misfit(w + step * (w_new - w)) > m0:
            step *= 0.5
        w = w + step * (w_new - w)
    keep = w > 1e-9
    w, g = w[keep], g[keep]
    return w / w.sum(), g


def log_error(theta_deg, phase, weights, g):
    """ln(P_fit / P_Mie) at the angles inside :data:`REPORT_RANGE_DEG`."""
    sel = (theta_deg >= REPORT_RANGE_DEG[0]) & (theta_deg <= REPORT_RANGE_DEG[1])
    fit = hg_lobes(np.cos(np.radians(theta_deg[sel])), weights, g)
    return np.log(fit / phase[sel])


def build_text(radii: int = RADII) -> str:
    """The CSV file's text."""
    theta, phase, g_mie = mie_phase(radii)
    w, g = fit_lobes(theta, phase, g_mie)
    err = log_error(theta, phase, w, g)
    header = [
        "Cloud droplet phase function as Henyey-Greenstein lobes: built by",
        "tools/build_cloud_phase.py (see its docstring). Mie theory (skydome.atmosphere.mie) for",
        f"liquid water m = {M_WATER.real} + 0i at {WAVELENGTH_UM * 1000:.0f} nm, a modified gamma",
        f"distribution (Hansen & Travis 1974) of r_eff {R_EFF_UM} um, v_eff {V_EFF}, {radii} radii.",
        f"Mie asymmetry parameter {g_mie:.5f}; lobes fitted in ln P with sum w = 1 and",
        f"sum w g = {g_mie:.5f}; ln(fit/Mie) over {REPORT_RANGE_DEG[0]:g}-{REPORT_RANGE_DEG[1]:g}"
        f" deg: RMS {np.sqrt(np.mean(err**2)):.3f}, max {np.abs(err).max():.3f}.",
    ]
    lines = [f"# {h}" for h in header] + ["weight,g"]
    lines += [f"{wj:.12g},{gj:.12g}" for wj, gj in zip(w, g, strict=True)]
    return "\n".join(lines) + "\n"


def build_mie_text(radii: int = RADII) -> str:
    """The Mie table's text: the phase function at :data:`THETA_DEG` (6 significant digits),
    renormalised to 1 over the sphere (the trapezoid rule in cos theta on this grid)."""
    theta, phase, g_mie = mie_phase(radii)
    mu = np.cos(np.radians(theta))
    norm = -np.trapezoid(phase * 2.0 * np.pi, mu)
    header = [
        "Cloud droplet phase function P(theta) (1/sr, normalised to 1 over the sphere): built",
        "by tools/build_cloud_phase.py (see its docstring). Mie theory (skydome.atmosphere.mie)",
        f"for liquid water m = {M_WATER.real} + 0i at {WAVELENGTH_UM * 1000:.0f} nm, a modified",
        f"gamma distribution (Hansen & Travis 1974) of r_eff {R_EFF_UM} um, v_eff {V_EFF},",
        f"{radii} radii; asymmetry parameter {g_mie:.5f}; the raw table integrated to",
        f"{norm:.6f} (trapezoid rule in cos theta) and was divided by that. 0.025 deg steps to",
        "10 deg (the diffraction peak), 0.05 deg beyond.",
    ]
    lines = [f"# {h}" for h in header] + ["theta_deg,phase"]
    lines += [f"{t:.3f},{p / norm:.6g}" for t, p in zip(theta, phase, strict=True)]
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", type=Path, default=OUT, help="the lobes' CSV")
    ap.add_argument("--mie-output", type=Path, default=MIE_OUT, help="the Mie table's CSV")
    args = ap.parse_args()
    text = build_text()
    args.output.write_text(text)
    print(text, end="")
    print(f"wrote {args.output}")
    args.mie_output.write_text(build_mie_text())
    print(f"wrote {args.mie_output}")


if __name__ == "__main__":
    main()
