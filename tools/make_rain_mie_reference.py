"""Generate ``tests/data/rain_mie_miepython.json``: rain drops' scattering over the primary bow
computed with ``miepython`` alone, an independent check of tools/build_rain_mie_phase.py's
``drop_light`` (skydome's own Mie series, summed in chunks) and of its efficiencies.

Offline only (CI never runs it); ``miepython`` is no project dependency. To run it::

    .venv/bin/pip install miepython
    .venv/bin/python tools/make_rain_mie_reference.py        # about a minute

What it computes: for RADII_UM at 550 nm (water's index there, Hale & Querry as the tool's),
``miepython.S1_S2(m, x, mu, norm="wiscombe")`` (the unnormalised amplitude functions of
Bohren & Huffman) at the tool's angles: bins of 0.05 deg over 136-141 deg, each the mean of 4
angles; dC/dOmega = (|S1|^2 + |S2|^2) / (2 k^2) in um^2/sr; and ``miepython.efficiencies_mx``'s
Q_ext and Q_sca.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import build_rain_mie_phase as tool  # noqa: E402

from skydome.physics.sphere_optics import water_index  # noqa: E402

OUT = ROOT / "tests/data/rain_mie_miepython.json"
RADII_UM = (60.0, 97.0, 150.0, 230.0, 400.0)
WAVELENGTH_NM = 550.0
EDGES_DEG = np.round(np.arange(136.0, 141.0 + 0.025, 0.05), 6)


def main() -> None:
    import miepython

    n = float(water_index(WAVELENGTH_NM))
    k = 2.0 * math.pi / (WAVELENGTH_NM / 1e3)
    angles = tool.sample_angles_deg(EDGES_DEG)
    mu = np.cos(np.radians(angles.ravel()))
    light, q_ext, q_sca = [], [], []
    for r in RADII_UM:
        x = k * r
        s1, s2 = miepython.S1_S2(complex(n, 0.0), x, mu, norm="wiscombe")
        i = (np.abs(s1) ** 2 + np.abs(s2) ** 2) / (2.0 * k * k)
        light.append(i.reshape(angles.shape).mean(-1).tolist())
        qe, qs, _, _ = miepython.efficiencies_mx(complex(n, 0.0), x)[:4]
        q_ext.append(float(qe))
        q_sca.append(float(qs))
        print(f"  {r:g} um (x = {x:.0f})", flush=True)
    OUT.write_text(json.dumps({
        "about": "Rain drops' dC/dOmega (um^2/sr) over 136-141 deg (0.05 deg bins, each the mean "
                 "of 4 angles) and Mie efficiencies at 550 nm by miepython "
                 f"{miepython.__version__} (S1_S2 norm='wiscombe', efficiencies_mx); made by "
                 "tools/make_rain_mie_reference.py",
        "wavelength_nm": WAVELENGTH_NM, "index": n, "radii_um": list(RADII_UM),
        "edges_deg": EDGES_DEG.tolist(), "light_um2_sr": light, "q_ext": q_ext, "q_sca": q_sca,
    }, indent=1))  # fmt: skip
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
