"""Build the cloud and fog droplets' phase functions by wavelength: skydome/data/
cloud_droplet_spectral_phase.npz (what the renderer's single scattering by droplets uses per
output channel: skydome.clouds.phase.droplet_channel_phases; the cloudbow's and the fogbow's
rims, the glory's rings).

Usage::

    python tools/build_droplet_spectral_phase.py          # about 40 minutes on 2 cores

Model: the droplets of ``tools/build_cloud_phase.py`` (liquid water spheres, the modified
gamma distribution of Hansen & Travis 1974 with v_eff 0.1, 16000 radii from r_eff / 40 to
8 r_eff; Mie theory by ``skydome.atmosphere.mie.bulk_optics``) of effective radii
:data:`R_EFFS_UM` (the clouds' 10 um; fog's and mist's droplets of 5-20 um), at
:data:`WAVELENGTHS_NM`, water's index at each from Hale & Querry (1973)
(``skydome.physics.sphere_optics.water_index``). Angles 5-180 deg every 0.05 deg (the
renderer counts what scatters within 5 deg as unscattered); each row is normalised by the
distribution's scattering cross-section (so over the whole sphere, the diffraction peak
included, it integrates to 1: the rows' share beyond 5 deg is what the renderer keeps).

Arrays: ``phase`` (K, W, A; 1/sr: effective radius, wavelength, angle) and ``meta_json``: the
format version, the effective radii (um), the wavelengths (nm), the angles (deg), the
extinction and scattering cross-sections (K, W) and this provenance.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from skydome.atmosphere.mie import bulk_optics
from skydome.io.packaged import write_packaged_npz
from skydome.physics.sphere_optics import water_index

OUTPUT = Path(__file__).resolve().parents[1] / "src/skydome/data/cloud_droplet_spectral_phase.npz"
WAVELENGTHS_NM = (380.0, 430.0, 480.0, 530.0, 580.0, 630.0, 680.0, 730.0, 780.0)
THETA_DEG = np.linspace(5.0, 180.0, 3501)
R_EFFS_UM, V_EFF, RADII = (5.0, 10.0, 20.0), 0.1, 16000
FORMAT_VERSION = 2


def build_rows(r_eff_um: float) -> tuple[np.ndarray, list, list]:
    """The phase functions (W, A) of droplets of ``r_eff_um`` and their cross-sections."""
    rows, c_ext, c_sca = [], [], []
    t0 = time.time()
    for wl in WAVELENGTHS_NM:
        m = complex(float(water_index(wl)), 0.0)
        optics = bulk_optics(m, wl / 1000.0, r_eff_um, V_EFF, np.cos(np.radians(THETA_DEG)),
                             radii=RADII)  # fmt: skip
        rows.append(optics.phase)
        c_ext.append(float(optics.c_ext_um2))
        c_sca.append(float(optics.c_sca_um2))
        print(f"r_eff {r_eff_um:g} um, {wl:.0f} nm: n = {m.real:.3f}, "
              f"{time.time() - t0:.0f} s", flush=True)  # fmt: skip
    return np.asarray(rows, np.float32), c_ext, c_sca


def assemble(rows: list, c_ext: list, c_sca: list, r_effs=R_EFFS_UM) -> dict:
    """The file's arrays from each effective radius's (rows, cross-sections)."""
    meta = {
        "format_version": FORMAT_VERSION,
        "about": "Cloud/fog droplets' Mie phase functions (1/sr, normalised by the "
        "scattering cross-section) by effective radius and wavelength: modified gamma "
        f"distributions v_eff {V_EFF}, {RADII} radii each, water index Hale & Querry (1973); "
        "skydome.atmosphere.mie. Built by tools/build_droplet_spectral_phase.py.",
        "r_eff_um": [float(r) for r in r_effs],
        "wavelength_nm": list(WAVELENGTHS_NM),
        "theta_deg": [round(float(t), 4) for t in THETA_DEG],
        "c_ext_um2": c_ext,
        "c_sca_um2": c_sca,
    }
    return {"phase": np.stack(rows), "meta": meta}


def build() -> dict:
    built = [build_rows(r) for r in R_EFFS_UM]
    return assemble(*(list(parts) for parts in zip(*built, strict=True)))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--output", type=Path, default=OUTPUT)
    args = ap.parse_args()
    table = build()
    write_packaged_npz(args.output, table.pop("meta"), **table)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
