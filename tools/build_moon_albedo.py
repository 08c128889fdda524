#!/usr/bin/env python
"""Build ``src/skydome/data/moon_albedo.npz``, the Moon's relative albedo map (developer tool).

Source: the colour map of NASA's CGI Moon Kit (NASA Scientific Visualization Studio, Ernie
Wright (USRA) and Noah Petro (NASA/GSFC), 2019, https://svs.gsfc.nasa.gov/4720), file
``lroc_color_poles_2k.tif``: 2048 x 1024 8-bit RGB, equirectangular, built from the LROC WAC
Hapke-normalised colour mosaic (Sato et al. 2014, JGR Planets 119, 1775; normalised to
incidence 60 deg, emission 0 deg, phase 60 deg), 70 N to 70 S, the poles filled from
monochrome LROC data and LOLA's albedo map. NASA SVS imagery is public domain (credit asked).
SHA-256 of the file used: ``13b79742...7052c4a`` (full value in ``SOURCE_SHA256``); the same
hash is recorded for NASA's download by an unrelated public project, so the copy is NASA's
file byte for byte.

Display encoding undone (as the SVS page describes it): the linear LROC reflectance ``L`` of
each channel was raised to 1/2.8 ("a gamma of 2.8"), multiplied by (0.935, 1.005, 1.04)
(R, G, B), and the range 0.16 to 0.40 mapped to 0-255. Hence, per channel,

    L = ((0.16 + 0.24 * v / 255) / m) ** 2.8.

(The page does not say whether the channel factors came before or after the gamma; this tool
takes the order in which the page lists them. The other order changes only the weights of the
three channels, by up to 7 %, and the normalisation below absorbs the overall scale.) Read
this way the near-side disk mean is I/F = 0.029 at the Hapke geometry, which at phase 60 deg
matches a normal albedo of about 0.12; the sRGB curve or a plain gamma would give a
highland/mare contrast of 4 to 5 instead of the measured 1.6 to 2.

The three channels (643 nm; combinations of 566 and 415 nm centred near 532 and 472 nm) are
combined into one relative albedo with the Rec. 709 luminance weights (0.2126, 0.7152,
0.0722), i.e. an albedo near 550 nm; the wavelength dependence is
``skydome.celestial.moon_albedo.moon_spectral_albedo``.

Output grid: selenographic latitude and east-positive longitude, equirectangular, pixel
centres at lon = -180 + (i + 0.5) * 360 / W deg (left to right) and lat = 90 - (j + 0.5) *
180 / H deg (top to bottom). Each output cell is the area-weighted mean of the source cells it
covers (linear reflectance; cell area proportional to the difference of sin(latitude) across
the row). The map is scaled so that its mean over the near side, weighted by cos(psi) times
cell area, where psi is the angle from the sub-Earth point (0, 0) (so each element of the
full Moon's projected disk counts alike), is 1. It is stored as uint16 with albedo =
value * ``albedo_scale`` (1/16384; step 6e-5).

Usage::

    .venv/bin/python tools/build_moon_albedo.py [SOURCE_TIFF] [--width 1024] [--out PATH]

SOURCE_TIFF defaults to ``build/moon/lroc_color_poles_2k.tif`` (``build/`` is git-ignored).
The output is deterministic.
"""

from __future__ import annotations

import argparse
import hashlib
import io
import json
import sys
from pathlib import Path

import numpy as np
from PIL import Image

REPO = Path(__file__).resolve().parent.parent
DEFAULT_SOURCE = REPO / "build" / "moon" / "lroc_color_poles_2k.tif"
DEFAULT_OUT = REPO / "src" / "skydome" / "data" / "moon_albedo.npz"
FORMAT_VERSION = 1

SOURCE_URL = "https://svs.gsfc.nasa.gov/vis/a000000/a004700/a004720/lroc_color_poles_2k.tif"
SOURCE_PAGE = "https://svs.gsfc.nasa.gov/4720"
SOURCE_SHA256 = "13b797422e8c4b8607ff2b2623ac3a046a6da0132d567c2d272d92fad7052c4a"
LICENCE = "public domain (NASA Scientific Visualization Studio imagery; credit requested)"
CREDIT = (
    "NASA's Scientific Visualization Studio, CGI Moon Kit (Ernie Wright, USRA; Noah Petro, "
    "NASA/GSFC), from LRO LROC WAC and LOLA data (NASA/GSFC/Arizona State University)"
)

# Display encoding of the CGI Moon Kit colour map (SVS page 4720, "Color" section).
GAMMA = 2.8
RANGE_LO, RANGE_HI = 0.16, 0.40
CHANNEL_FACTORS = np.array([0.935, 1.005, 1.04])  # R, G, B
# Rec. ITU-R BT.709 luminance weights (R, G, B).
LUMA_WEIGHTS = np.array([0.2126, 0.7152, 0.0722])
ALBEDO_SCALE = 1.0 / 16384.0


def decode(rgb8: np.ndarray) -> np.ndarray:
    """8-bit display values (H, W, 3) -> linear reflectance per channel (same shape)."""
    encoded = RANGE_LO + (RANGE_HI - RANGE_LO) * rgb8.astype(np.float64) / 255.0
    return (encoded / CHANNEL_FACTORS) ** GAMMA


def cell_latitude_edges_rad(height: int) -> np.ndarray:
    """Latitudes of the row edges of an equirectangular grid, north to south (H + 1,)."""
    return np.radians(90.0 - np.arange(height + 1) * 180.0 / height)


def area_average(y: np.ndarray, out_h: int, out_w: int) -> np.ndarray:
    """Area-weighted block mean of an equirectangular map onto a grid out_h x out_w."""
    h, w = y.shape
    if h % out_h or w % out_w:
        raise SystemExit(f"source {w}x{h} is not an integer multiple of {out_w}x{out_h}")
    fy, fx = h // out_h, w // out_w
    edges = cell_latitude_edges_rad(h)
    row_area = np.sin(edges[:-1]) - np.sin(edges[1:])  # (h,), all > 0
    weighted = (y * row_area[:, None]).reshape(out_h, fy, out_w, fx).sum(axis=(1, 3))
    weights = row_area.reshape(out_h, fy).sum(axis=1)[:, None] * fx
    return weighted / weights


def near_side_weights(height: int, width: int) -> np.ndarray:
    """cos(angle from the sub-Earth point) x cell area for the near side, 0 elsewhere."""
    edges = cell_latitude_edges_rad(height)
    area = (np.sin(edges[:-1]) - np.sin(edges[1:]))[:, None] * np.ones((1, width))
    lat = np.radians(90.0 - (np.arange(height) + 0.5) * 180.0 / height)
    lon = np.radians(-180.0 + (np.arange(width) + 0.5) * 360.0 / width)
    cos_psi = np.cos(lat)[:, None] * np.cos(lon)[None, :]
    return np.where(cos_psi > 0.0, cos_psi * area, 0.0)


def build(source: Path, width: int, expect_sha256: str | None) -> tuple[bytes, dict]:
    raw = source.read_bytes()
    digest = hashlib.sha256(raw).hexdigest()
    if expect_sha256 is not None and digest != expect_sha256:
        raise SystemExit(
            f"{source}: SHA-256 {digest} is not the expected {expect_sha256} "
            "(pass --sha256 any to build from another copy of the CGI Moon Kit map)"
        )
    with Image.open(io.BytesIO(raw)) as im:
        rgb = np.asarray(im.convert("RGB"))
    h, w = rgb.shape[:2]
    if w != 2 * h:
        raise SystemExit(f"{source}: {w}x{h} is not an equirectangular 2:1 map")
    height = width // 2

    linear = decode(rgb)
    lum = linear @ LUMA_WEIGHTS
    small = area_average(lum, height, width)

    wts = near_side_weights(height, width)
    mean_if = float((small * wts).sum() / wts.sum())
    rel = small / mean_if
    q = np.round(rel / ALBEDO_SCALE)
    if q.max() > np.iinfo(np.uint16).max:
        raise SystemExit(f"relative albedo {rel.max():.3f} does not fit the uint16 scale")
    q = q.astype(np.uint16)
    stored = q * ALBEDO_SCALE
    stored_mean = float((stored * wts).sum() / wts.sum())

    meta = {
        "format_version": FORMAT_VERSION,
        "quantity": "relative albedo (luminance-weighted, near 550 nm)",
        "albedo_scale": ALBEDO_SCALE,
        "normalisation": (
            "mean over the near side weighted by cos(angle from sub-Earth point 0,0) x cell "
            "area (the full Moon's projected disk) = 1"
        ),
        "near_side_disk_mean": stored_mean,
        "decoded_near_side_mean_i_over_f": mean_if,
        "decoded_geometry": "LROC WAC Hapke-normalised, incidence 60, emission 0, phase 60 deg",
        "longitude": "selenographic, east-positive; columns -180 to +180 deg, left to right",
        "latitude": "selenographic; rows +90 (top) to -90 deg (bottom)",
        "pixel_centres": "lon = -180 + (i + 0.5) * 360 / W, lat = 90 - (j + 0.5) * 180 / H",
        "width": width,
        "height": height,
        "source": f"{SOURCE_URL} ({SOURCE_PAGE}), {w}x{h} RGB",
        "source_sha256": digest,
        "decoding": (
            f"L = (({RANGE_LO} + {RANGE_HI - RANGE_LO:.2f} * v / 255) / m) ** {GAMMA}, "
            f"m = {CHANNEL_FACTORS.tolist()} (R, G, B); Y = {LUMA_WEIGHTS.tolist()} . L; "
            "area-weighted block mean"
        ),
        "licence": LICENCE,
        "credit": CREDIT,
    }
    buf = io.BytesIO()
    np.savez_compressed(buf, albedo_u16=q, meta_json=np.array(json.dumps(meta, sort_keys=True)))
    return buf.getvalue(), meta


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("source", nargs="?", type=Path, default=DEFAULT_SOURCE)
    p.add_argument("--width", type=int, default=1024, help="output width (height = width / 2)")
    p.add_argument("--out", type=Path, default=DEFAULT_OUT)
    p.add_argument(
        "--sha256", default=SOURCE_SHA256, help="expected SHA-256 of the source, or 'any'"
    )
    args = p.parse_args(argv)
    if not args.source.is_file():
        print(
            f"{args.source}: not found; download {SOURCE_URL} (SHA-256 {SOURCE_SHA256}) there",
            file=sys.stderr,
        )
        return 2
    if args.width <= 0 or args.width % 2:
        print(f"--width {args.width}: must be a positive even number", file=sys.stderr)
        return 2
    blob, meta = build(args.source, args.width, None if args.sha256 == "any" else args.sha256)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_bytes(blob)
    print(
        f"wrote {args.out}: {meta['width']}x{meta['height']}, {len(blob) / 1024:.0f} KiB, "
        f"decoded near-side mean I/F {meta['decoded_near_side_mean_i_over_f']:.4f}, "
        f"stored near-side mean {meta['near_side_disk_mean']:.6f}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
