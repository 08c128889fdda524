"""Extract the series coefficients used by ``skydome.astro`` into a package data file.

Writes ``src/skydome/data/astro_series.npz`` with:

* ``nut_args`` (63, 5) int, ``nut_dpsi`` (63, 2), ``nut_deps`` (63, 2): the IAU 1980
  nutation series as printed in Meeus, *Astronomical Algorithms* (2nd ed., 1998),
  table 22.A (multipliers of D, M, M', F, Omega; coefficients in 0.0001").
* ``vsop_<planet>_{A,B,C,coord,power}``: the VSOP87D series (Bretagnon & Francou 1988,
  heliocentric spherical variables referred to the dynamical ecliptic and equinox of
  date; A cos(B + C tau) with tau in Julian millennia TDB from J2000), coord 0 = L,
  1 = B (radians), 2 = R (au), truncated per planet: a term of power ``alpha`` is kept
  when ``A * TAU_MAX**alpha >= threshold`` (the usual VSOP87 truncation rule; TAU_MAX = 1
  millennium). Amplitudes are stored in their native units (1e-8 rad or 1e-8 au).

Source of the numbers: the PyPI package ``pymeeus`` (Dagoberto Salazar, LGPL-3), which
carries the complete VSOP87D tables and Meeus' table 22.A as Python data.
pymeeus is needed only to run this script (``pip install pymeeus``), never at run time.

The script also reports, for every planet, the largest difference between the truncated
and the complete series over 1800-2200 (heliocentric, arcsec), so the truncation error
is known.

Usage: python tools/build_astro_tables.py [--check]
"""

from __future__ import annotations

import argparse
import importlib
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "src" / "skydome" / "data" / "astro_series.npz"

PLANETS = ["mercury", "venus", "earth", "mars", "jupiter", "saturn", "uranus", "neptune"]

# Truncation thresholds in 1e-8 rad (L, B) and 1e-8 au (R). Earth is kept finer because the
# apparent Sun is checked to 1"; 1e-8 rad = 0.002". R thresholds matter only through
# distance/light time (planets) and parallax/aberration (Sun).
THRESHOLDS = {
    "earth": (10.0, 20.0, 20.0),
    "mercury": (100.0, 100.0, 50.0),
    "venus": (60.0, 60.0, 60.0),
    "mars": (60.0, 60.0, 80.0),
    "jupiter": (150.0, 150.0, 600.0),
    "saturn": (150.0, 150.0, 1000.0),
    "uranus": (200.0, 200.0, 3000.0),
    "neptune": (200.0, 200.0, 5000.0),
}
TAU_MAX = 1.0


def _series(planet: str):
    mod = importlib.import_module("pymeeus." + planet.capitalize())
    return [mod.VSOP87_L, mod.VSOP87_B, mod.VSOP87_R]


def _flatten(tables, thresholds=None):
    rows = []
    for coord, table in enumerate(tables):
        for power, terms in enumerate(table):
            for a, b, c in terms:
                if thresholds is None or abs(a) * TAU_MAX**power >= thresholds[coord]:
                    rows.append((a, b, c, coord, power))
    arr = np.array(rows, dtype=float)
    return arr[:, 0], arr[:, 1], arr[:, 2], arr[:, 3].astype(np.int8), arr[:, 4].astype(np.int8)


def _evaluate(a, b, c, coord, power, tau):
    out = np.zeros((3, tau.size))
    terms = (
        a[:, None] * np.cos(b[:, None] + c[:, None] * tau[None, :]) * tau[None, :] ** power[:, None]
    )
    for k in range(3):
        out[k] = terms[coord == k].sum(axis=0) * 1e-8
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only report truncation errors")
    args = parser.parse_args()

    from pymeeus import Coordinates

    data: dict[str, np.ndarray] = {}
    data["nut_args"] = np.array(Coordinates.NUTATION_ARG_TABLE, dtype=np.int8)
    data["nut_dpsi"] = np.array(Coordinates.NUTATION_SINE_COEF_TABLE, dtype=float)
    # pymeeus lists the cosine (Delta epsilon) coefficients only for the first 49 rows of
    # table 22.A; the remaining 14 rows have none (blank in the book): pad with zeros.
    deps = np.zeros((63, 2))
    cos_rows = np.array(Coordinates.NUTATION_COSINE_COEF_TABLE, dtype=float)
    deps[: len(cos_rows)] = cos_rows
    data["nut_deps"] = deps
    assert data["nut_args"].shape == (63, 5)

    tau = np.linspace(-0.2, 0.2, 4001)  # 1800-2200
    for planet in PLANETS:
        full = _flatten(_series(planet))
        trunc = _flatten(_series(planet), THRESHOLDS[planet])
        f = _evaluate(*full, tau)
        t = _evaluate(*trunc, tau)
        dl = np.abs(f[0] - t[0]).max() * 206264.806
        db = np.abs(f[1] - t[1]).max() * 206264.806
        dr = np.abs((f[2] - t[2]) / f[2]).max()
        print(
            f"{planet:8s} terms {len(trunc[0]):4d} of {len(full[0]):5d}: "
            f'max |dL| {dl:.3f}", |dB| {db:.3f}", |dR/R| {dr:.2e} (1800-2200)'
        )
        for name, arr in zip("ABC", trunc[:3], strict=True):
            data[f"vsop_{planet}_{name}"] = arr
        data[f"vsop_{planet}_coord"] = trunc[3]
        data[f"vsop_{planet}_power"] = trunc[4]

    if not args.check:
        OUT.parent.mkdir(parents=True, exist_ok=True)
        np.savez_compressed(OUT, **data)
        print(f"wrote {OUT} ({OUT.stat().st_size / 1024:.0f} KiB)")


if __name__ == "__main__":
    main()
