"""Build skydome/data/mars_dust.csv: the optics of Martian dust from Mie theory.

Usage::

    python tools/build_mars_dust.py            # about a minute

Model (each input's source)
---------------------------
- Size distribution: the modified gamma of Hansen & Travis (1974) with effective radius
  1.71 um and effective variance 0.25: Mars Pathfinder's midday sky (Markiewicz et al. 1999,
  JGR 104, 9009); MER Navcam near-Sun images give 1.3-1.8 um (Soderblom 2008).
- Refractive index m = 1.5 + i k(lambda): the real part of palagonite-like dust in the visible;
  the imaginary part k(lambda) is solved at each wavelength so that the distribution's
  single-scattering albedo equals :data:`SSA_SPECTRUM` (absorbing in the blue, bright in the red:
  0.62 at 440 nm, 0.90 at 550 nm, 0.97 at 700 nm, the values skydome's ``mars`` preset has used,
  after Wolff et al. 2009, JGR 114, E00D04).
- Spheres: Mie theory (``skydome.atmosphere.mie``). Real dust is irregular; its phase function
  has the spheres' forward diffraction peak (set by size, not shape) but not their rainbow and
  glory (Pollack et al. 1995; Tomasko et al. 1999). The fit below keeps the first and smooths
  the others away: it is fitted over 1-150 deg.

Columns: wavelength_nm, k (imaginary index), ssa, c_ext_rel (extinction cross-section relative to
550 nm), asymmetry (Mie mean cosine), then hg_<g>: the weight of the Henyey-Greenstein lobe of
asymmetry g (``mie.HG_LOBES_G``, ``fit_hg_lobes``), and fit_rms (relative RMS error of the fit over 1-150 deg).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from skydome.atmosphere.mie import HG_LOBES_G, bulk_optics, fit_hg_lobes, hg_lobes

OUT = Path(__file__).resolve().parents[1] / "src/skydome/data/mars_dust.csv"
WAVELENGTHS_NM = np.union1d(np.arange(360.0, 841.0, 20.0), [550.0])  # + the albedo knee
R_EFF_UM, V_EFF, N_REAL = 1.71, 0.25, 1.5
#: Single-scattering albedo (wavelength nm, value), linear between, held outside.
SSA_SPECTRUM = ((440.0, 0.62), (550.0, 0.90), (700.0, 0.97))
#: Scattering angles of the fit: fine over the diffraction peak.
THETA_DEG = np.concatenate([np.linspace(0.0, 10.0, 101), np.linspace(10.5, 180.0, 340)])
FIT_RANGE_DEG = (1.0, 150.0)


def target_ssa(wavelength_nm: float) -> float:
    wl, ssa = zip(*SSA_SPECTRUM, strict=True)
    return float(np.interp(wavelength_nm, wl, ssa))


def solve_k(wavelength_um: float, ssa: float, mu: np.ndarray) -> float:
    """k with the distribution's albedo = ssa: bisection in ln k (the albedo falls with k)."""
    lo, hi = 1e-7, 0.2
    for _ in range(28):
        k = float(np.sqrt(lo * hi))
        if bulk_optics(N_REAL + 1j * k, wavelength_um, R_EFF_UM, V_EFF, mu, radii=160).ssa > ssa:
            lo = k
        else:
            hi = k
    return float(np.sqrt(lo * hi))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", type=Path, default=OUT)
    args = ap.parse_args()
    theta = np.radians(THETA_DEG)
    mu = np.cos(theta)
    fit = (THETA_DEG >= FIT_RANGE_DEG[0]) & (THETA_DEG <= FIT_RANGE_DEG[1])
    rows = []
    c_ext_550 = None
    for wl in np.concatenate([[550.0], WAVELENGTHS_NM]):
        k = solve_k(wl / 1000.0, target_ssa(wl), mu)
        optics = bulk_optics(N_REAL + 1j * k, wl / 1000.0, R_EFF_UM, V_EFF, mu)
        if c_ext_550 is None:
            c_ext_550 = optics.c_ext_um2
            continue
        w = fit_hg_lobes(theta[fit], optics.phase[fit])
        rel = hg_lobes(mu[fit], w) / optics.phase[fit] - 1.0
        rows.append(
            [wl, k, optics.ssa, optics.c_ext_um2 / c_ext_550, optics.asymmetry, *w,
             float(np.sqrt(np.mean(rel**2)))]
        )  # fmt: skip
        print(f"{wl:.0f} nm: k {k:.2e}, ssa {optics.ssa:.3f}, g {optics.asymmetry:.3f}, "
              f"fit rms {rows[-1][-1]:.3f}")  # fmt: skip
    header = [
        "Martian dust from Mie theory: built by tools/build_mars_dust.py (see its docstring for",
        f"the sources). Gamma size distribution r_eff {R_EFF_UM} um, v_eff {V_EFF} (Markiewicz",
        f"et al. 1999); m = {N_REAL} + i k, k solved for the single-scattering albedo; phase",
        "function fitted by Henyey-Greenstein lobes over 1-150 deg: column hg_<g> holds the weight",
        "of the lobe of asymmetry g (the weights sum to 1).",
    ]
    names = ["wavelength_nm", "k", "ssa", "c_ext_rel", "asymmetry"]
    names += [f"hg_{g:g}" for g in HG_LOBES_G] + ["fit_rms"]
    with open(args.output, "w") as f:
        for line in header:
            f.write(f"# {line}\n")
        f.write(",".join(names) + "\n")
        for row in rows:
            f.write(",".join(f"{v:.6g}" for v in row) + "\n")
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
