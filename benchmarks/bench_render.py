"""Frame time of the sky renderers: median ms per frame after warm-up, read-back included.

Usage: python benchmarks/bench_render.py [--model precomputed|single]
       [--spectral fast|accurate] [--direct] [--samples 16] [--repeats 15] [--sizes 1920x1080]

Prints the GL device, then one line per frame size, e.g. ``1280x720: 13.6 ms``. For the
precomputed model, frames come from the sky-view tables (the camera turns, the tables are
kept); ``Sun moving`` lines redraw the tables every frame (the worst case: a moving light or
camera altitude), ``--direct`` looks every pixel up in the 4D tables instead; the last lines
time frames with a depth image (aerial perspective) and with shadow lengths (light shafts).
"""

from __future__ import annotations

import argparse
import functools

import numpy as np
from timing import median_ms

from skydome.atmosphere import preset
from skydome.core.cameras import FisheyeCamera, PerspectiveCamera, direction_from_angles
from skydome.gpu import gl_info

VIEW = PerspectiveCamera(fov_deg=90.0, yaw_deg=200.0, pitch_deg=15.0)
CASES = [
    ("640x360", VIEW, 640, 360),
    ("1280x720", VIEW, 1280, 720),
    ("1920x1080", VIEW, 1920, 1080),
    ("fisheye 512x512", FisheyeCamera(), 512, 512),
]


def make_renderer(args):
    params = preset(args.atmosphere)
    if args.model == "single":
        from skydome.atmosphere.single import SingleScatteringRenderer

        return SingleScatteringRenderer(params, spectral=args.spectral, view_samples=args.samples)
    from skydome.atmosphere.precompute_config import PrecomputeConfig
    from skydome.atmosphere.precomputed import PrecomputedRenderer

    return PrecomputedRenderer(
        params, PrecomputeConfig(wavelengths=args.spectral), sky_view=not args.direct
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", default="precomputed", choices=("precomputed", "single"))
    ap.add_argument("--spectral", default="accurate", help="fast (4 wavelengths) or accurate (16)")
    ap.add_argument("--direct", action="store_true", help="precomputed: no sky-view tables")
    ap.add_argument("--samples", type=int, default=16)
    ap.add_argument("--atmosphere", default="earth", help="preset name, e.g. earth_bruneton")
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--sizes", default="", help="extra sizes, e.g. 3840x2160")
    args = ap.parse_args()
    cases = list(CASES)
    for s in filter(None, args.sizes.split(",")):
        w, h = (int(v) for v in s.split("x"))
        cases.append((s, VIEW, w, h))
    renderer = make_renderer(args)
    path = "sky-view tables" if getattr(renderer, "sky_view", None) else "per-pixel lookups"
    print(f"# device: {gl_info(renderer.ctx).describe()}")
    print(f"# model {args.model}, spectral {args.spectral}, ", end="")
    print(path if args.model == "precomputed" else f"{args.samples} samples per view ray")
    if args.model == "precomputed":
        # Reload of the tables from the disk cache (warm: the renderer above stored them).
        from skydome.atmosphere.precompute_config import PrecomputeConfig
        from skydome.atmosphere.tables import load_tables

        config = PrecomputeConfig(wavelengths=args.spectral)

        def reload():
            tables, loaded = load_tables(renderer.ctx, preset(args.atmosphere), config)
            tables.release()
            assert loaded

        print(f"reload from cache: {median_ms(reload, 5, warmup=0):.1f} ms")
    sun = direction_from_angles(25.0, 200.0)
    for label, cam, w, h in cases:
        ms = median_ms(
            functools.partial(renderer.render, cam, w, h, sun_direction=sun), args.repeats
        )
        print(f"{label}: {ms:.1f} ms")
    if getattr(renderer, "sky_view", None):
        step = [0]

        def moving(w: int, h: int):
            step[0] += 1
            moved = direction_from_angles(25.0 + 1e-3 * step[0], 200.0)
            renderer.render(VIEW, w, h, sun_direction=moved)

        for w, h in ((640, 360), (1280, 720)):
            ms = median_ms(functools.partial(moving, w, h), args.repeats)
            print(f"{w}x{h} Sun moving: {ms:.1f} ms")
    if args.model == "precomputed":
        # Per-pixel inputs (always per-pixel lookups): aerial perspective for a scene 5 km
        # away, light shafts with 2 km of shadow along every ray.
        w, h = 1280, 720
        for label, key, value in (
            ("depth image", "depth_m", 5000.0),
            ("shadow lengths", "shadow_length_m", 2000.0),
        ):
            image = np.full((h, w), value)
            render = functools.partial(
                renderer.render, VIEW, w, h, sun_direction=sun, **{key: image}
            )
            print(f"{w}x{h} with {label}: {median_ms(render, args.repeats):.1f} ms")


if __name__ == "__main__":
    main()
