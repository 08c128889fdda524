"""Frame time of the sky renderer: median ms per frame after warm-up, read-back included.

Usage: python benchmarks/bench_render.py [--model single] [--spectral fast|accurate]
       [--samples 16] [--repeats 10]

Prints one line per frame size, e.g. ``640x360: 48.1 ms``, and the GL device first.
"""

from __future__ import annotations

import argparse
import statistics
import time

from skydome.atmosphere import preset
from skydome.gpu import gl_info
from skydome.render import FisheyeCamera, PerspectiveCamera, direction_from_angles, get_renderer

CASES = [
    ("640x360", PerspectiveCamera(fov_deg=90.0, yaw_deg=200.0, pitch_deg=15.0), 640, 360),
    ("1280x720", PerspectiveCamera(fov_deg=90.0, yaw_deg=200.0, pitch_deg=15.0), 1280, 720),
    ("fisheye 512x512", FisheyeCamera(), 512, 512),
]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", default="single")
    ap.add_argument("--spectral", default="fast", help="fast (4 wavelengths) or accurate (16)")
    ap.add_argument("--samples", type=int, default=16)
    ap.add_argument("--repeats", type=int, default=10)
    ap.add_argument("--sizes", default="", help="extra sizes, e.g. 1920x1080")
    args = ap.parse_args()
    cases = list(CASES)
    for s in filter(None, args.sizes.split(",")):
        w, h = (int(v) for v in s.split("x"))
        cases.append((s, PerspectiveCamera(fov_deg=90.0, yaw_deg=200.0, pitch_deg=15.0), w, h))
    renderer = get_renderer(
        args.model, preset("earth"), spectral=args.spectral, samples=args.samples
    )
    print(f"# device: {gl_info(renderer.ctx).describe()}")
    print(f"# model {args.model}, spectral {args.spectral}, {args.samples} samples per view ray")
    if args.model == "precomputed":
        # Reload of the tables from the disk cache (warm: the renderer above stored them).
        from skydome.atmosphere.precompute_config import PrecomputeConfig
        from skydome.atmosphere.tables import load_tables

        config = PrecomputeConfig(wavelengths=args.spectral)
        reloads = []
        for _ in range(5):
            t0 = time.perf_counter()
            tables, loaded = load_tables(renderer.ctx, preset("earth"), config)
            reloads.append((time.perf_counter() - t0) * 1e3)
            tables.release()
            assert loaded
        print(f"reload from cache: {statistics.median(reloads):.1f} ms")
    sun = direction_from_angles(25.0, 200.0)
    for label, cam, w, h in cases:
        for _ in range(2):  # warm-up: shader compilation, target allocation
            renderer.render(cam, w, h, sun_direction=sun)
        times = []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            renderer.render(cam, w, h, sun_direction=sun)
            times.append((time.perf_counter() - t0) * 1e3)
        print(f"{label}: {statistics.median(times):.1f} ms")


if __name__ == "__main__":
    main()
