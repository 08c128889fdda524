"""Precomputation of the multiple-scattering tables: time per stage, memory, and accuracy.

Prints the median over several runs after a warm-up (the warm-up also compiles the shaders,
reported as "first run") of each stage's time and the total, and the tables' memory, for the
default configuration (16 wavelengths, 4 orders) unless options say otherwise.

With ``--accuracy`` it also measures what each shortcut costs: sky luminance over a set of
directions, cameras at 0 and 10 km and Suns from 60 to -12 degrees, of the default tables and
of variants (each undoing one shortcut), against a reference run with every shortcut undone
(larger tables, more nodes, orders >= 2 at all 16 wavelengths; minutes on a CPU rasterizer).

With ``--split`` each stage's time is split into its passes (the GPU finished before and
after each) and the rest (read-backs, NumPy), the least of the runs.

    python benchmarks/bench_precompute.py [--runs 3] [--orders 4] [--spectral accurate]
    python benchmarks/bench_precompute.py --split --runs 5
    python benchmarks/bench_precompute.py --accuracy
"""

from __future__ import annotations

import argparse
import statistics
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from skydome.atmosphere import precompute_probe as probe
from skydome.atmosphere import preset
from skydome.atmosphere.precompute import precompute
from skydome.atmosphere.precompute_config import REFERENCE, PrecomputeConfig
from skydome.core.cameras import direction_from_angles
from skydome.gpu import gl_info, shared_context
from skydome.reference import ms as mc
from skydome.spectra import LINEAR_SRGB_TO_XYZ


def time_config(ctx, params, config: PrecomputeConfig, runs: int) -> None:
    t0 = time.perf_counter()
    first = precompute(ctx, params, config)
    first_s = time.perf_counter() - t0
    first.release()
    timings = []
    for _ in range(runs):
        t0 = time.perf_counter()
        pa = precompute(ctx, params, config)
        # the whole call: the stages and the NumPy work between them (the orders' sum)
        timings.append({**pa.timings, "wall (the call)": time.perf_counter() - t0})
        pa.release()
    stages = list(timings[0])
    print(f"{'stage':<20} {'median s':>9} {'min s':>8} {'max s':>8}")
    for stage in stages:
        v = [t.get(stage, 0.0) for t in timings]
        print(f"{stage:<20} {statistics.median(v):>9.3f} {min(v):>8.3f} {max(v):>8.3f}")
    print(f"{'first run (compile)':<20} {first_s:>9.3f}")
    mem = config.memory_bytes()
    print(
        "memory: "
        + ", ".join(f"{k} {v / 2**20:.2f} MB" for k, v in mem.items())
        + f"; total {sum(mem.values()) / 2**20:.2f} MB"
    )


def luminance_samples(pa) -> np.ndarray:
    """Y over 300 sky directions x cameras at 0 and 10 km x Suns at 60, 20, 5, 0, -6, -12."""
    rng = np.random.default_rng(1)
    dirs = rng.normal(size=(300, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    dirs[:, 2] = np.abs(dirs[:, 2])
    out = []
    for alt in (0.0, 10_000.0):
        for el in (60.0, 20.0, 5.0, 0.0, -6.0, -12.0):
            sun = direction_from_angles(el, 90.0)
            keep = np.degrees(np.arccos(np.clip(dirs @ sun, -1, 1))) > 2.0
            L, _ = probe.sky_radiance(pa, dirs[keep], sun, altitude_m=alt)
            y = L[:, :3] @ LINEAR_SRGB_TO_XYZ[1]
            out.append((alt, el, y))
    return out


def accuracy(ctx, params, base: PrecomputeConfig) -> None:
    print("\nreference run (slow)...", flush=True)
    t0 = time.perf_counter()
    ref = precompute(ctx, params, replace(base, **REFERENCE))
    print(f"reference: {time.perf_counter() - t0:.1f} s")
    want = luminance_samples(ref)
    variants = {
        "default": {},
        "orders >= 2 at 16 wavelengths": {"ms_wavelengths": "same"},
        "2x directions for J": {"directions": (24, 12, 32)},
        "2x grid of J": {"ms_size": (32, 128, 128, 8)},
        "2x table of orders >= 2": {"multiple_size": (64, 128, 128, 8)},
        "2x single-scattering table": {"scattering_size": (48, 256, 48, 16)},
        "3x nodes along rays": {"single_samples": 48, "ms_samples": 48},
        "float32 tables": {"dtype": "f4", "ms_dtype": "f4"},
    }
    print(
        f"\nsky luminance vs reference: relative RMS / max (%) over 300 directions, "
        f"cameras 0 and 10 km, for the Sun at {[e for _, e, _ in want[:6]]} deg"
    )
    for name, change in variants.items():
        t0 = time.perf_counter()
        pa = precompute(ctx, params, replace(base, **change))
        dt = time.perf_counter() - t0
        got = luminance_samples(pa)
        pa.release()
        cells = []
        for (_, _, g), (_, _, w) in zip(got, want, strict=True):
            rel = (g - w) / (np.abs(w) + 0.01 * np.abs(w).mean())
            cells.append(f"{100 * np.sqrt(np.mean(rel**2)):.2f}/{100 * np.abs(rel).max():.1f}")
        print(f"{name:<32} {dt:5.1f} s  " + "  ".join(cells))


def monte_carlo(ctx, base: PrecomputeConfig) -> None:
    """The default tables (10 orders, spectral at 440/550/680 nm) against the Monte Carlo
    reference of tests/data (reference/ms.py), if present, for the atmosphere it was traced
    in (its ``preset``)."""
    path = Path(__file__).resolve().parents[1] / "tests" / "data" / "ms_reference_earth.npz"
    if not path.exists():
        print(f"\n(no {path.name}: Monte Carlo comparison skipped)")
        return
    data = dict(np.load(path))
    params = preset(str(data["preset"]))
    wl = tuple(float(w) for w in data["wavelengths_nm"]) + (700.0,)
    pa = precompute(ctx, params, replace(base, wavelengths=wl, output="spectral", orders=10))
    dirs = data["view_dirs"]
    print(
        f"\nvs Monte Carlo ({path.name}, {data['preset']}), relative RMS over sky directions (%)"
        f" at {wl[:3]} nm,"
        " and the reference's own standard error"
    )
    for ia, alt in enumerate(data["camera_altitude_m"]):
        for js, el in enumerate(data["sun_elevation_deg"]):
            sun = mc.sun_direction(float(data["sun_zenith_rad"][js]))
            away = np.degrees(np.arccos(np.clip(dirs @ sun, -1, 1))) > 3
            r = params.bottom_radius_m + float(alt)
            sky = dirs[:, 2] > -np.sqrt(1 - (params.bottom_radius_m / r) ** 2)
            ok = data["view_valid"][ia] & away & sky
            want, err = data["radiance"][ia, js][ok], data["stderr"][ia, js][ok]
            got, _ = probe.sky_radiance(pa, dirs[ok], sun, altitude_m=float(alt))
            rms = 100 * np.sqrt(np.mean((got[:, :3] / want - 1) ** 2, axis=0))
            se = 100 * np.sqrt(np.mean((err / want) ** 2, axis=0))
            print(
                f"camera {alt / 1e3:4.0f} km, Sun {el:+5.1f} deg: RMS {np.round(rms, 2)}  "
                f"reference error {np.round(se, 2)}"
            )
    pa.release()


def split_stages(ctx, params, config: PrecomputeConfig, runs: int) -> None:
    """Each stage's time, its passes' and the rest's, the least of ``runs`` calls (after one
    untimed): the passes are timed with the GPU finished before and after each draw, so the
    rest is what the CPU does alone (the passes' time includes their overlap with it)."""
    from skydome.atmosphere import precompute as pc
    from skydome.gpu import FullscreenPass

    current = ["-"]
    passes: dict[str, float] = {}
    draw, stage_run = FullscreenPass.draw, pc._Stages.run

    def timed_draw(self, *args, **kwargs):
        ctx.finish()
        t = time.perf_counter()
        draw(self, *args, **kwargs)
        ctx.finish()
        passes[current[0]] = passes.get(current[0], 0.0) + time.perf_counter() - t

    def named_run(self, stage, *args):
        current[0] = stage
        return stage_run(self, stage, *args)

    FullscreenPass.draw, pc._Stages.run = timed_draw, named_run
    try:
        precompute(ctx, params, config).release()
        best: dict[str, tuple[float, float]] = {}
        walls = []
        for _ in range(runs):
            passes.clear()
            t0 = time.perf_counter()
            pa = precompute(ctx, params, config)
            walls.append(time.perf_counter() - t0)
            for stage, t in pa.timings.items():
                if stage != "total" and (stage not in best or t < best[stage][0]):
                    best[stage] = (t, passes.get(stage, 0.0))
            pa.release()
    finally:
        FullscreenPass.draw, pc._Stages.run = draw, stage_run
    print(f"{'stage (least of runs)':<22} {'all ms':>7} {'passes':>7} {'rest':>6}")
    for stage, (t, g) in best.items():
        print(f"{stage:<22} {t * 1e3:>7.0f} {g * 1e3:>7.0f} {(t - g) * 1e3:>6.0f}")
    print(f"{'the call (least)':<22} {min(walls) * 1e3:>7.0f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--orders", type=int, default=4)
    ap.add_argument("--spectral", default="accurate", help="accurate | fast")
    ap.add_argument("--atmosphere", default="earth")
    ap.add_argument(
        "--accuracy", action="store_true", help="also measure the error of each shortcut"
    )
    ap.add_argument(
        "--split", action="store_true", help="also split each stage into its passes and the rest"
    )
    args = ap.parse_args()
    ctx = shared_context()
    params = preset(args.atmosphere)
    config = PrecomputeConfig(wavelengths=args.spectral, orders=args.orders)
    print(
        f"{args.atmosphere}, {args.spectral} ({len(config.render_wavelengths)} wavelengths), "
        f"{args.orders} orders, median of {args.runs} runs, {gl_info(ctx).describe()}"
    )
    time_config(ctx, params, config, args.runs)
    if args.split:
        split_stages(ctx, params, config, args.runs)
    if args.accuracy:
        monte_carlo(ctx, config)
        accuracy(ctx, params, config)


if __name__ == "__main__":
    main()
