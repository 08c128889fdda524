"""Build the rain drops' phase functions: skydome/data/rain_drop_phase.npz (what the renderer
scatters rain with: skydome.clouds.phase.load_rain_phases, made into one phase function per
output channel by rain_channel_phases).

Usage::

    python tools/build_rain_phase.py          # about a minute

Model (each input's source)
---------------------------
- Drops: water spheres far larger than the wavelength (a rain drop's size parameter at 550 nm
  is ~1000-30000), scattering as their rays do: skydome.physics.sphere_optics (reflection,
  transmission and up to six internal reflections, Fresnel-weighted per polarisation; van de
  Hulst 1957 ch. 12). Water's index: Hale & Querry (1973), 1.343 at 350 nm to 1.329 at 800 nm.
- Wavelengths: 350-800 nm every 10 nm (the bows move by ~0.1 deg between neighbours).
- Angles: bins of 0.25 deg, 0.05 deg over 120-145 deg where the bows are (the rays' caustic
  at each bow's minimum deviation falls in the bin of Descartes' angle).
- Diffraction is not in the table: it holds the other half of a large drop's extinction
  (efficiency 2), in a peak a few hundredths of a degree wide, which the renderer counts as
  unscattered light with the rest of what falls within its truncation angle.

Arrays: ``phase`` (W, A; 1/sr, each row normalised over the sphere: the refracted and
reflected light only) and ``meta_json``: the format version, the wavelengths (nm), the
angles (deg, the bins' centres) and this provenance.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from skydome.io.packaged import write_packaged_npz
from skydome.physics.sphere_optics import MAX_ORDER, geometric_phase, water_index

OUTPUT = Path(__file__).resolve().parents[1] / "src" / "skydome" / "data" / "rain_drop_phase.npz"
WAVELENGTHS_NM = np.arange(350.0, 801.0, 10.0)
EDGES_DEG = np.concatenate(
    [np.arange(0.0, 120.0, 0.25), np.arange(120.0, 145.0, 0.05), np.arange(145.0, 180.01, 0.25)]
)
RAYS = 1_000_000


#: The file's layout (skydome.clouds.phase.RAIN_PHASE_FORMAT).
FORMAT_VERSION = 1


def build() -> dict:
    phase = np.stack([geometric_phase(float(water_index(wl)), EDGES_DEG, rays=RAYS)
                      for wl in WAVELENGTHS_NM])  # fmt: skip
    meta = {
        "format_version": FORMAT_VERSION,
        "about": "Rain drops' phase functions (1/sr, rows: wavelengths; columns: angles) by "
        f"geometric optics, diffraction apart: water spheres' reflected and refracted rays "
        f"(orders 0-{MAX_ORDER}, Fresnel, van de Hulst 1957 ch. 12), index Hale & Querry "
        f"(1973), {RAYS} rays per wavelength. Built by tools/build_rain_phase.py.",
        "wavelength_nm": [float(w) for w in WAVELENGTHS_NM],
        "theta_deg": [round(float(t), 4) for t in 0.5 * (EDGES_DEG[1:] + EDGES_DEG[:-1])],
    }
    return {"phase": phase.astype(np.float32), "meta": meta}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--output", type=Path, default=OUTPUT)
    args = ap.parse_args()
    table = build()
    write_packaged_npz(args.output, table.pop("meta"), **table)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
