#!/usr/bin/env python
"""Build ``src/skydome/data/constellations.json``, the constellation figures (developer tool).

Source: d3-celestial by Olaf Frohn (https://github.com/ofrohn/d3-celestial, commit
``7e720a3de062059d4c5400a379146a601d9010e0``, 2022-07-05), BSD-3-Clause:

- ``data/constellations.lines.json``: the stick figures of the 88 IAU constellations (after
  the IAU's constellation charts, with some lines modified by the author), a GeoJSON
  MultiLineString per constellation, vertices at the stars' J2000 positions (degrees,
  right ascension as longitude in [-180, 180]);
- ``data/constellations.json``: each constellation's IAU name, genitive, a "rank" (1 = the
  prominent ones, 3 = the faint ones) and a label point (J2000 degrees) chosen for a chart.

Serpens comes as two features (Caput and Cauda) sharing the id ``Ser``; both are kept, with
their own names and label points.

Each vertex is matched to the star of skydome's catalogue (``skydome.astro.stars.catalog``,
Hipparcos 2 with Hp <= 8) nearest to it at epoch J2000.0 (the catalogue's J1991.25 place
moved by its proper motion over 8.75 years). Of the 757 distinct vertices of the source, 756 lie
within 1.2" of a catalogue star (99 % within 0.25"), and the next star is always more than
9" away, so the match is unambiguous; a vertex farther than ``MATCH_ARCSEC`` from any star (ksi UMa: Hipparcos 2 has
no solution for HIP 55203) is kept as its J2000 position. The figures are stored as line
segments, each end a HIP number or a ``[ra_deg, dec_deg]`` J2000 position, deduplicated
(a segment drawn twice in the source, in either direction, is stored once).

Usage::

    .venv/bin/python tools/build_constellations.py [--source DIR] [--out PATH]

``DIR`` holds the two JSON files (and the repository's ``LICENSE``); without ``--source``
they are read from a local mirror of the repository (``--mirror``, a git directory) at the
commit above. The output is deterministic.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

REPO = "ofrohn/d3-celestial"
COMMIT = "7e720a3de062059d4c5400a379146a601d9010e0"
FILES = ("constellations.lines.json", "constellations.json")
#: Largest distance (arcsec) of a vertex from its catalogue star.
MATCH_ARCSEC = 5.0
J2000_JD = 2451545.0
FORMAT_VERSION = 1
OUT = Path(__file__).resolve().parents[1] / "src" / "skydome" / "data" / "constellations.json"


def read_sources(source: Path | None, mirror: Path | None) -> dict[str, bytes]:
    """The raw bytes of the two source files, from a folder or a git mirror."""
    out = {}
    for name in FILES:
        if source is not None:
            out[name] = (source / name).read_bytes()
        else:
            if mirror is None:
                raise SystemExit("give --source DIR or --mirror GITDIR")
            out[name] = subprocess.run(
                ["git", "--git-dir", str(mirror), "show", f"{COMMIT}:data/{name}"],
                check=True,
                capture_output=True,
            ).stdout
    return out


def _unit(ra_deg, dec_deg) -> np.ndarray:
    ra, dec = np.radians(ra_deg), np.radians(dec_deg)
    return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], -1)


def catalogue_j2000() -> tuple[np.ndarray, np.ndarray]:
    """HIP numbers and unit vectors (ICRS) of the catalogue stars at epoch J2000.0."""
    from skydome.astro import stars

    cat = stars.catalog()
    kin = stars._kinematics()
    p = kin.u0 + kin.w * (J2000_JD - cat.epoch_jd_tt)
    return np.asarray(cat.hip), p / np.linalg.norm(p, axis=-1, keepdims=True)


def build(raw: dict[str, bytes]) -> tuple[dict, dict]:
    """The output document and a report of the matching."""
    lines = json.loads(raw["constellations.lines.json"])
    info = json.loads(raw["constellations.json"])
    hip, cat_u = catalogue_j2000()

    figures: dict[str, list] = {}
    for feature in lines["features"]:
        figures.setdefault(feature["id"], []).extend(feature["geometry"]["coordinates"])

    verts = sorted({(lon, lat) for polys in figures.values() for p in polys for lon, lat in p})
    v = _unit(np.array([a for a, _ in verts]), np.array([b for _, b in verts]))
    dots = v @ cat_u.T
    order = np.argsort(-dots, axis=1)[:, :2]
    rows = np.arange(len(verts))
    sep = np.degrees(np.arccos(np.clip(dots[rows[:, None], order], -1.0, 1.0))) * 3600.0
    match: dict[tuple, object] = {}
    unmatched = []
    for i, vert in enumerate(verts):
        if sep[i, 0] <= MATCH_ARCSEC:
            match[vert] = int(hip[order[i, 0]])
        else:
            ra = vert[0] % 360.0
            match[vert] = [round(ra, 4), vert[1]]
            unmatched.append((vert, float(sep[i, 0])))

    out = []
    for feature in info["features"]:
        abbr = feature["id"]
        props = feature["properties"]
        lon, lat = feature["geometry"]["coordinates"]
        out.append(
            {
                "abbr": abbr,
                "name": props["name"],
                "genitive": props["gen"],
                "rank": int(props["rank"]),
                "label_ra_deg": round(lon % 360.0, 4),
                "label_dec_deg": lat,
            }
        )
    segments: dict[str, list] = {}
    for abbr, polys in figures.items():
        seen = set()
        segs = []
        for poly in polys:
            for a, b in zip(poly[:-1], poly[1:], strict=True):
                ea, eb = match[tuple(a)], match[tuple(b)]
                key = tuple(sorted((json.dumps(ea), json.dumps(eb))))
                if ea == eb or key in seen:
                    continue
                seen.add(key)
                segs.append([ea, eb])
        segments[abbr] = segs
    # Serpens' two parts share one figure ("Ser"): its segments go with the first.
    done = set()
    for entry in out:
        entry["segments"] = [] if entry["abbr"] in done else segments[entry["abbr"]]
        done.add(entry["abbr"])

    digest = {name: hashlib.sha256(raw[name]).hexdigest() for name in FILES}
    doc = {
        "format_version": FORMAT_VERSION,
        "source": f"https://github.com/{REPO} commit {COMMIT}, data/{FILES[0]} and data/{FILES[1]}",
        "licence": "BSD-3-Clause, Copyright (c) 2015, Olaf Frohn (see constellations.txt)",
        "sha256": digest,
        "epoch": "J2000.0 (positions in degrees, ICRS)",
        "segment_ends": "a Hipparcos number of skydome's catalogue, or [ra_deg, dec_deg]",
        "constellations": out,
    }
    report = {
        "vertices": len(verts),
        "matched": len(verts) - len(unmatched),
        "max_sep_arcsec": float(sep[sep[:, 0] <= MATCH_ARCSEC, 0].max()),
        "min_second_arcsec": float(sep[:, 1].min()),
        "unmatched": unmatched,
        "segments": sum(len(s) for s in segments.values()),
    }
    return doc, report


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--source", type=Path, default=None, help="folder with the two JSON files")
    p.add_argument(
        "--mirror",
        type=Path,
        default=Path("/work/.mirror/ofrohn+d3-celestial/repo"),
        help="git directory of a clone of ofrohn/d3-celestial",
    )
    p.add_argument("--out", type=Path, default=OUT)
    args = p.parse_args(argv)
    doc, report = build(read_sources(args.source, args.mirror))
    text = json.dumps(doc, ensure_ascii=False, separators=(",", ":"))
    # One constellation per line: readable diffs.
    text = text.replace(',{"abbr"', ',\n{"abbr"')
    args.out.write_text(text + "\n", encoding="utf-8")
    print(json.dumps(report, indent=1), file=sys.stderr)
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
