"""Generate ``tests/data/droplet_phase_miepython.json``: the cloud droplets' Mie phase function
computed with ``miepython`` alone, an independent check of ``skydome.clouds.phase.MIE_PHASE``.

Offline only (CI never runs it); ``miepython`` is no project dependency. To run it::

    .venv/bin/pip install miepython
    .venv/bin/python tools/make_droplet_phase_reference.py      # about 50 s

**The droplets** (as ``tools/build_cloud_phase.py``): liquid water spheres, m = 1.333 + 0i at
550 nm (``--wavelength-um`` and ``--index`` for the other wavelengths of
``tools/build_droplet_spectral_phase.py``: tests/data/droplet_phase_miepython_430nm.json and
_680nm.json, water's index of Hale & Querry there), the modified gamma distribution of Hansen & Travis (1974, Space Sci. Rev. 16, 527,
eq. 2.56) with r_eff = 10 um and v_eff = 0.1, n(r) ~ r^7 exp(-r / 1 um), over the same radius
range r_eff / 40 to 8 r_eff (0.25-80 um). The quadrature differs on purpose (the build uses
1000 log-spaced radii): the trapezoid rule on radii uniform in r, :data:`RADII` over
0.25-30 um and a tenth as many over 30-80 um (which hold 7e-6 of the scattering), then
twice as many of both to show convergence (the finer run is stored). Many radii are needed:
the size-averaged function at a fixed angle sums the Mie ripple and interference structure
in x (resonances far narrower than the 0.66 step in x of 1000 log-spaced radii at r_eff),
and a grid too coarse for it is off by several percent in the side and back directions.

**Mie theory**: ``miepython.S1_S2(m, x, mu, norm="qsca")`` (its numba backend), for which
i = (|S1|^2 + |S2|^2) / 2 integrates to Q_sca over the sphere; ``miepython.efficiencies_mx``
for Q_ext, Q_sca and g of each sphere. Nothing of skydome is imported.

**Normalisation** (1/sr, 1 over the sphere, as ``MIE_PHASE``): by the scattering cross-section,
no angular integration: P(theta) = sum_j w_j r_j^2 i_j(theta) / sum_j w_j r_j^2 Q_sca,j with
w_j = n(r_j) dr_j (the pi r^2 cancel). The norm="qsca" convention is checked once at x = 114
(r_eff) against the trapezoid rule on 200001 angles and the ratio recorded. Averages over the
distribution: Q_ext = sum w r^2 Q_ext / sum w r^2 and g = sum w r^2 Q_sca g / sum w r^2 Q_sca.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import sys
import time
from importlib import metadata
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "tests/data/droplet_phase_miepython.json"
WAVELENGTH_UM, R_EFF_UM, V_EFF, M_WATER = 0.55, 10.0, 0.1, 1.333
R_MIN_UM, R_MAX_UM = R_EFF_UM / 40.0, 8.0 * R_EFF_UM
#: Radii over R_MIN_UM-R_SPLIT_UM (a tenth as many beyond, to R_MAX_UM).
RADII = 100_000
R_SPLIT_UM = 30.0
#: Scattering angles (deg): the diffraction peak, the forward lobe, the side minimum, the
#: cloudbow (1 deg steps over 135-145) and the glory. All are nodes of MIE_PHASE's table.
THETA_DEG = (0.0, 0.5, 1.0, 2.0, 3.0, 5.0, 7.5, 10.0, 15.0, 20.0, 30.0, 40.0, 50.0, 60.0,
             70.0, 80.0, 90.0, 100.0, 110.0, 120.0, 130.0, *np.arange(135.0, 146.0), 150.0,
             160.0, 170.0, 175.0, 177.0, 178.0, 179.0, 179.5, 180.0)  # fmt: skip


def _miepython():
    """The miepython module, with its numba backend (chosen at import; 50 times faster)."""
    os.environ.setdefault("MIEPYTHON_USE_JIT", "1")
    import miepython

    return miepython


def radius_grid(radii: int) -> tuple[np.ndarray, np.ndarray]:
    """(radii in um, trapezoid weights dr in um): ``radii`` uniform over R_MIN_UM-R_SPLIT_UM
    and radii // 10 uniform over R_SPLIT_UM-R_MAX_UM."""
    r1, r2 = (
        np.linspace(R_MIN_UM, R_SPLIT_UM, radii),
        np.linspace(R_SPLIT_UM, R_MAX_UM, radii // 10),
    )
    w1, w2 = np.full(r1.size, r1[1] - r1[0]), np.full(r2.size, r2[1] - r2[0])
    w1[[0, -1]] *= 0.5
    w2[[0, -1]] *= 0.5
    w1[-1] += w2[0]  # the shared node R_SPLIT_UM
    return np.concatenate([r1, r2[1:]]), np.concatenate([w1, w2[1:]])


def droplet_optics(radii: int, theta_deg=THETA_DEG) -> dict:
    """The distribution's phase function (1/sr) at ``theta_deg``, asymmetry parameter g and
    mean extinction and scattering efficiencies, on :func:`radius_grid` (``radii``)."""
    mie = _miepython()
    r, w = radius_grid(radii)
    alpha = (1.0 - 3.0 * V_EFF) / V_EFF  # 7: n(r) ~ r^alpha exp(-r / (r_eff v_eff))
    w *= np.exp(alpha * np.log(r / R_EFF_UM) - (r - R_EFF_UM) / (R_EFF_UM * V_EFF))
    x = 2.0 * np.pi * r / WAVELENGTH_UM
    mu = np.cos(np.radians(np.asarray(theta_deg, float)))
    q_ext, q_sca, _, g = (np.asarray(q) for q in mie.efficiencies_mx(M_WATER, x))
    intensity = np.empty((r.size, mu.size))  # (|S1|^2 + |S2|^2) / 2, integrating to Q_sca
    for i, xi in enumerate(x):
        s1, s2 = mie.S1_S2(M_WATER, xi, mu, norm="qsca")
        intensity[i] = 0.5 * (np.abs(s1) ** 2 + np.abs(s2) ** 2)
    area = w * r**2
    c_sca = float(area @ q_sca)
    return {
        "phase_per_sr": area @ intensity / c_sca,
        "asymmetry": float(area @ (q_sca * g)) / c_sca,
        "q_ext": float(area @ q_ext / area.sum()),
        "q_sca": c_sca / float(area.sum()),
        "scattering_beyond_split": float(area[r > R_SPLIT_UM] @ q_sca[r > R_SPLIT_UM]) / c_sca,
    }


def normalisation_check(x: float | None = None) -> float:
    """The integral over the sphere of miepython's norm="qsca" unpolarised intensity of one
    sphere (size parameter ``x``; default that of r_eff) divided by its Q_sca: 1 if the
    convention holds."""
    if x is None:
        x = 2.0 * np.pi * R_EFF_UM / WAVELENGTH_UM
    mie = _miepython()
    theta = np.linspace(0.0, np.pi, 200001)
    s1, s2 = mie.S1_S2(M_WATER, x, np.cos(theta), norm="qsca")
    i = 0.5 * (np.abs(s1) ** 2 + np.abs(s2) ** 2)
    return float(np.trapezoid(2.0 * np.pi * i * np.sin(theta), theta)) / float(
        mie.efficiencies_mx(M_WATER, x)[1]
    )


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--radii", type=int, default=RADII, help="radii of the coarser run")
    ap.add_argument("-o", "--output", type=Path, default=OUT)
    ap.add_argument(
        "--wavelength-um",
        type=float,
        default=WAVELENGTH_UM,
        help="another wavelength (um; the spectral table's check)",
    )
    ap.add_argument(
        "--index", type=float, default=M_WATER, help="water's refractive index there (real part)"
    )
    ap.add_argument(
        "--r-eff", type=float, default=R_EFF_UM, help="another effective radius (um; fog's)"
    )
    args = ap.parse_args(argv)
    globals().update(WAVELENGTH_UM=args.wavelength_um, M_WATER=args.index, R_EFF_UM=args.r_eff,
                     R_MIN_UM=args.r_eff / 40.0, R_MAX_UM=8.0 * args.r_eff)  # fmt: skip
    t0 = time.time()
    coarse = droplet_optics(args.radii)
    fine = droplet_optics(2 * args.radii)
    change = np.abs(coarse["phase_per_sr"] / fine["phase_per_sr"] - 1.0)
    norm = normalisation_check()
    run_s = time.time() - t0

    def sig(v: float) -> float:
        return float(f"{v:.7g}")

    doc = {
        "description": "Size-averaged Mie phase function (1/sr, normalised to 1 over the sphere) "
        "of cloud droplets, computed with miepython only: the reference of "
        "tests/test_droplet_phase_miepython.py for skydome.clouds.phase.MIE_PHASE. Generated "
        "by tools/make_droplet_phase_reference.py; see its docstring.",
        "theta_deg": [float(t) for t in THETA_DEG],
        "phase_per_sr": [sig(v) for v in fine["phase_per_sr"]],
        "asymmetry": sig(fine["asymmetry"]),
        "q_ext": sig(fine["q_ext"]),
        "q_sca": sig(fine["q_sca"]),
        "provenance": {
            "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
            "command": " ".join(
                ["PYTHONPATH=src .venv/bin/python tools/make_droplet_phase_reference.py"]
                + (sys.argv[1:] if argv is None else argv)
            ),
            "versions": {
                "miepython": metadata.version("miepython"),
                "numba": metadata.version("numba"),
                "numpy": np.__version__,
                "python": platform.python_version(),
            },
            "droplets": {
                "refractive_index": f"{M_WATER} + 0i",
                "wavelength_um": WAVELENGTH_UM,
                "size_distribution": "modified gamma (Hansen & Travis 1974 eq. 2.56), "
                f"r_eff {R_EFF_UM} um, v_eff {V_EFF}: n(r) ~ r^7 exp(-r / {R_EFF_UM * V_EFF:g} um)",
                "radius_range_um": [R_MIN_UM, R_MAX_UM],
                "radii": f"{2 * args.radii} uniform over {R_MIN_UM}-{R_SPLIT_UM} um, "
                f"{2 * args.radii // 10} uniform over {R_SPLIT_UM}-{R_MAX_UM} um",
                "radius_quadrature": "trapezoid rule in r, weights n(r) dr",
                "scattering_beyond_split": sig(fine["scattering_beyond_split"]),
            },
            "mie": 'miepython.S1_S2(m, x, mu, norm="qsca") (numba backend) and '
            "efficiencies_mx; P = sum w r^2 (|S1|^2+|S2|^2)/2 / sum w r^2 Q_sca, "
            "g = sum w r^2 Q_sca g / sum w r^2 Q_sca, Q = sum w r^2 Q / sum w r^2",
            "normalisation_check": "integral of the norm='qsca' intensity over the sphere / "
            f"Q_sca at x = 114 (200001 angles, trapezoid): {norm:.9f}",
            "convergence": {
                "coarse_radii": args.radii,
                "max_relative_change_of_phase": sig(change.max()),
                "at_theta_deg": float(THETA_DEG[int(np.argmax(change))]),
                "asymmetry_change": sig(abs(coarse["asymmetry"] - fine["asymmetry"])),
                "q_ext_change": sig(abs(coarse["q_ext"] - fine["q_ext"])),
            },
            "run_time_s": round(run_s, 1),
            "machine": platform.machine() + " " + platform.platform(),
        },
    }
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(doc, indent=1) + "\n")
    print(json.dumps(doc["provenance"], indent=1))
    print(f"g = {doc['asymmetry']}, Q_ext = {doc['q_ext']}; wrote {args.output}")


if __name__ == "__main__":
    main()
