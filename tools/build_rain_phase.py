"""Build the rain drops' phase function: skydome/data/rain_drop_phase.csv (what the renderer
scatters rain with, skydome.weather.rain_phase.RAIN_PHASE).

Usage::

    python tools/build_rain_phase.py          # about 40 s

Model (each input's source)
---------------------------
- Drops: water spheres far larger than the wavelength (a rain drop's size parameter at 550 nm
  is ~1000-30000), scattering as their rays do: skydome.physics.sphere_optics (reflection,
  transmission and up to six internal reflections, Fresnel-weighted per polarisation; van de
  Hulst 1957 ch. 12). Water's index: Hale & Querry (1973), 1.339 at 400 nm to 1.331 at 700 nm.
- Colour: the phase functions at 400-700 nm every 10 nm, averaged with the photopic
  luminous efficiency V(lambda) (CIE 1924, skydome/data/cie_luminous_efficiency_5nm.csv)
  over a flat spectrum: the renderer's rain is grey, so its bows are the white light's
  (their colours are the optics issue's).
- Diffraction is not in the table: it holds the other half of a large drop's extinction
  (efficiency 2), in a peak a few hundredths of a degree wide, which the renderer counts as
  unscattered light with the rest of what falls within its truncation angle.

Columns: theta_deg (bin centres, 0.25 deg bins), phase (1/sr, normalised over the sphere:
the refracted and reflected light only).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from skydome.io.packaged import read_packaged_csv
from skydome.physics.sphere_optics import MAX_ORDER, geometric_phase, water_index

OUTPUT = Path(__file__).resolve().parents[1] / "src" / "skydome" / "data" / "rain_drop_phase.csv"
#: Bin edges (deg) and the wavelengths (nm) averaged.
EDGES_DEG = np.linspace(0.0, 180.0, 721)
WAVELENGTHS_NM = np.arange(400.0, 701.0, 10.0)
RAYS = 1_000_000


def build_text() -> str:
    v = read_packaged_csv("cie_luminous_efficiency_5nm.csv")
    weights = np.interp(WAVELENGTHS_NM, v["wavelength_nm"], v["V_photopic"])
    phase = np.zeros(EDGES_DEG.size - 1)
    for wl, w in zip(WAVELENGTHS_NM, weights, strict=True):
        phase += w * geometric_phase(float(water_index(wl)), EDGES_DEG, rays=RAYS)
    phase /= weights.sum()
    centres = 0.5 * (EDGES_DEG[1:] + EDGES_DEG[:-1])
    header = [
        "Rain drops' phase function (1/sr) by geometric optics, diffraction apart: the light",
        f"water spheres reflect and refract (orders 0-{MAX_ORDER}, Fresnel, van de Hulst 1957",
        "ch. 12), index Hale & Querry (1973), averaged over 400-700 nm (10 nm) with CIE",
        f"V(lambda), {RAYS} rays per wavelength, 0.25 deg bins (centres). Built by",
        "tools/build_rain_phase.py.",
    ]
    lines = [f"# {h}" for h in header] + ["theta_deg,phase"]
    lines += [f"{t:.3f},{p:.6e}" for t, p in zip(centres, phase, strict=True)]
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--output", type=Path, default=OUTPUT)
    args = ap.parse_args()
    args.output.write_text(build_text())
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
