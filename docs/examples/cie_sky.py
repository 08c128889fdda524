"""How-to: the CIE standard general skies (ISO 15469 / CIE S 011). For the Sun 40 deg up and
a diffuse horizontal illuminance of 20 000 lx: each type's zenith luminance and its
luminance at the 145 patches of a sky scanner, written as cie-sky-types.csv, and the 15
skies as upward fisheye maps in one exposure, cie-sky-types.png (the output folder is the
first argument, or $SKYDOME_EXAMPLES_OUT, or ./out)."""

import os
import sys
from pathlib import Path

import numpy as np

from skydome.atmosphere.cie import CIE_SKY_TYPES, horizontal_illuminance_factor, sky_luminance
from skydome.io.png import write_png

out = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SKYDOME_EXAMPLES_OUT", "out"))
out.mkdir(parents=True, exist_ok=True)
SUN_ZENITH, SUN_AZIMUTH, DIFFUSE_LX = 50.0, 180.0, 20_000.0

# the sky scanner's 145 patches (Tregenza 1987): 7 bands of altitude, then the zenith
zen, az = [], []
for altitude, n in zip((6, 18, 30, 42, 54, 66, 78), (30, 30, 24, 24, 18, 12, 6), strict=True):
    zen += [90.0 - altitude] * n
    az += list(np.arange(n) * 360.0 / n)
zen, az = np.array(zen + [0.0]), np.array(az + [0.0])

rows = ["type,zenith_luminance_cd_m2,horizontal_per_zenith_sr," + ",".join(
    f"L{k}" for k in range(145))]  # fmt: skip
for t in CIE_SKY_TYPES:
    lum = sky_luminance(t.number, zen, az, SUN_ZENITH, SUN_AZIMUTH,
                        horizontal_illuminance=DIFFUSE_LX)  # fmt: skip
    factor = horizontal_illuminance_factor(t.number, SUN_ZENITH)
    rows.append(f"{t.number},{lum[-1]:.1f},{factor:.4f}," + ",".join(f"{v:.1f}" for v in lum))
    print(f"type {t.number:2d} ({t.description}): zenith {lum[-1]:6.0f} cd/m^2")
(out / "cie-sky-types.csv").write_text("\n".join(rows) + "\n")

# fisheye maps (equal-angle, north up, east left as seen from below), 5 x 3
n = 96
x, y = np.meshgrid((np.arange(n) + 0.5) / n * 2 - 1, (np.arange(n) + 0.5) / n * 2 - 1)
r = np.hypot(x, y)
inside = r <= 1.0
zenith_deg = np.minimum(r, 1.0) * 90.0
azimuth_deg = np.degrees(np.arctan2(-x, -y)) % 360.0
sheet = np.zeros((3 * n, 5 * n, 3), dtype=np.uint8)
for k, t in enumerate(CIE_SKY_TYPES):
    lum = sky_luminance(t.number, zenith_deg, azimuth_deg, SUN_ZENITH, SUN_AZIMUTH,
                        horizontal_illuminance=DIFFUSE_LX)  # fmt: skip
    # one exposure for all: 12 000 cd/m^2 maps to white, sRGB-encoded
    v = np.clip(lum / 12_000.0, 0.0, 1.0)
    v = np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)
    tile = np.where(inside, np.round(v * 255), 0).astype(np.uint8)
    row, col = divmod(k, 5)
    sheet[row * n : (row + 1) * n, col * n : (col + 1) * n] = tile[..., None]
write_png(out / "cie-sky-types.png", sheet, {"views": "CIE standard general skies 1-15"})
print(f"wrote {out / 'cie-sky-types.csv'} and {out / 'cie-sky-types.png'}")
