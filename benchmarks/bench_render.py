"""Frame time of the sky: median ms per frame after warm-up, read-back included.

Usage: python benchmarks/bench_render.py [--model precomputed|single]
       [--spectral fast|accurate] [--direct] [--samples 16] [--repeats 15] [--sizes 1920x1080]

Prints the GL device, then one line per frame size, e.g. ``1280x720: 13.6 ms``. Each frame
is what a user gets: ``Sky(sun_elevation_deg=25, layers=[AtmosphereLayer(...)])`` rendered
through the frame graph in cd/m^2 (no exposure, no tone mapping), read back. For the
precomputed model, frames come from the sky-view tables (the camera turns, the tables are
kept); ``Sun moving`` lines draw a new SkyState every frame through the same graph (the
sky-view tables redrawn: the worst case, a moving light), ``--direct`` looks every pixel up
in the 4D tables instead; the last lines time frames with a depth image (aerial
perspective) and with shadow lengths (light shafts).
"""

from __future__ import annotations

import argparse
import functools

import numpy as np
from timing import median_ms, print_floor, vs_floor

from skydome import Sky
from skydome.atmosphere import preset
from skydome.atmosphere.layer import AtmosphereLayer
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.atmosphere.tables import load_tables
from skydome.core.cameras import FisheyeCamera, PerspectiveCamera
from skydome.gpu import gl_info
from skydome.scene.state import abstract_state

VIEW = PerspectiveCamera(fov_deg=90.0, yaw_deg=200.0, pitch_deg=15.0)
CASES = [
    ("640x360", VIEW, 640, 360),
    ("1280x720", VIEW, 1280, 720),
    ("1920x1080", VIEW, 1920, 1080),
    ("fisheye 512x512", FisheyeCamera(), 512, 512),
]
SUN_ELEVATION_DEG, SUN_AZIMUTH_DEG = 25.0, 200.0


def make_sky(args) -> Sky:
    """The sky over a flat Earth-like ground lit by the Sun alone: the atmosphere layer only
    (no Sun disk), the model and its settings from the command line."""
    air = AtmosphereLayer(
        preset(args.atmosphere),
        model=args.model,
        config=PrecomputeConfig(wavelengths=args.spectral),
        sky_view=not args.direct,
        samples=args.samples,
        spectral=args.spectral,
        jitter=False,
    )
    return Sky(sun_elevation_deg=SUN_ELEVATION_DEG, sun_azimuth_deg=SUN_AZIMUTH_DEG, layers=[air])


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
    sky = make_sky(args)
    ctx = sky.graph.ctx
    precomputed = args.model == "precomputed"
    path = "per-pixel lookups" if args.direct else "sky-view tables"
    print(f"# device: {gl_info(ctx).describe()}")
    print_floor(ctx)
    print(f"# model {args.model}, spectral {args.spectral}, ", end="")
    print(path if precomputed else f"{args.samples} samples per view ray")
    if precomputed:
        # Reload of the tables from the disk cache (warm: the sky above stored them).
        config = PrecomputeConfig(wavelengths=args.spectral)

        def reload():
            tables, loaded = load_tables(ctx, preset(args.atmosphere), config)
            tables.release()
            assert loaded

        print(f"reload from cache: {median_ms(reload, 5, warmup=0):.1f} ms")
    for label, cam, w, h in cases:
        frame = functools.partial(sky.render, cam, w, h, exposure=None)
        ms = median_ms(frame, args.repeats)
        print(f"{label}: {ms:.1f} ms{vs_floor(ms)}")
    if precomputed and not args.direct:
        step = [0]

        def moving(w: int, h: int):
            step[0] += 1
            state = abstract_state(SUN_ELEVATION_DEG + 1e-3 * step[0], SUN_AZIMUTH_DEG)
            sky.graph.render(state, VIEW, w, h, altitude_m=sky.altitude_m())

        for w, h in ((640, 360), (1280, 720)):
            ms = median_ms(functools.partial(moving, w, h), args.repeats)
            print(f"{w}x{h} Sun moving: {ms:.1f} ms{vs_floor(ms)}")
    if precomputed:
        # Per-pixel inputs (always per-pixel lookups): aerial perspective for a scene 5 km
        # away, light shafts with 2 km of shadow along every ray.
        w, h = 1280, 720
        for label, key, value in (
            ("depth image", "depth_m", 5000.0),
            ("shadow lengths", "shadow_length_m", 2000.0),
        ):
            image = np.full((h, w), value)
            render = functools.partial(sky.render, VIEW, w, h, exposure=None, **{key: image})
            ms = median_ms(render, args.repeats)
            print(f"{w}x{h} with {label}: {ms:.1f} ms{vs_floor(ms)}")
    sky.release()


if __name__ == "__main__":
    main()
