"""Apparent places of the whole star catalogue at one instant: median ms after warm-up.

Usage: python benchmarks/bench_stars.py [--repeats 20] [--times 1]

Prints the catalogue load time (first call in the process, includes reading the
packaged file), then the median of ``--repeats`` runs of
:func:`skydome.astro.stars.apparent_places` for all stars at ``--times`` instants, and
of :func:`~skydome.astro.stars.horizontal_coordinates` (alt/az) for one instant.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np
from timing import median_ms

from skydome.astro import stars


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--times", type=int, default=1, help="instants per call")
    args = ap.parse_args()

    t0 = time.perf_counter()
    cat = stars.catalog()
    stars.apparent_places(2460000.5)  # builds the cached kinematic vectors too
    load_ms = (time.perf_counter() - t0) * 1e3
    print(
        f"# {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
        f"NumPy {np.__version__}"
    )
    print(f"# {cat.n} stars; first call (load + kinematics + one epoch): {load_ms:.0f} ms")

    rng = np.random.default_rng(0)
    jd = 2451545.0 + rng.uniform(0.0, 50 * 365.25, size=args.times)
    jd_arg = jd[0] if args.times == 1 else jd
    ms = median_ms(lambda: stars.apparent_places(jd_arg), args.repeats)
    print(f"apparent_places, {cat.n} stars x {args.times} time(s): {ms:.1f} ms")
    lat, lst = np.radians(48.0), np.radians(120.0)
    ms = median_ms(lambda: stars.horizontal_coordinates(jd[0], lst, lat), args.repeats)
    print(f"horizontal_coordinates, {cat.n} stars x 1 time: {ms:.1f} ms")


if __name__ == "__main__":
    main()
