"""Issue 27 item 5 in one run: the figures a GPU is judged by, each beside its goal.

Made for a device machine's short lease (`benchmarks/gpu_check.sh` runs it there), and
runnable anywhere (on a CPU rasterizer at reduced sizes, to check it works):

- the scene: ``Sky.draw`` of a clear sky (16 wavelengths, the Sun 30 deg up) into an 8-bit
  offscreen framebuffer at 1920x1080 (goal <= 0.5 ms);
- clouds: fair cumulus, ``Sky.draw`` at 1280x720 in the interactive mode with the camera
  turning (goal <= 1 ms), and a full-quality still frame read back (goal <= 10 ms);
- the precomputation: ``precompute()``, 16 wavelengths, 4 orders, warm (goal <= 50 ms), and
  its first call in the process;
- the viewer's frame: ``Sky.draw`` of Paranal's night (every night layer) at 1280x720 with the
  time moving 10 min per frame, as ``skydome view`` draws it.

Each figure is the median wall time of the call with the GPU finished (``ctx.finish``), and
for draws also the GPU's own time (a GL timer query around the call), beside the floor (a bare
4-fetch lookup pass at 1280x720) measured in the same run.

    python benchmarks/bench_gpu.py [--repeats 20] [--scale 1.0]

``--scale`` multiplies every frame size (0.25 for a quick check on a CPU rasterizer).
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

from timing import print_floor, vs_floor

from skydome import Sky
from skydome.atmosphere import preset
from skydome.atmosphere.precompute import precompute
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.clouds.layer import CloudLayer
from skydome.clouds.params import Clouds
from skydome.core.cameras import PerspectiveCamera
from skydome.gpu import gl_info, shared_context

VALLETTA = (35.8989, 14.5146, 56.0)
PARANAL = (-24.6272, -70.4039, 2635.0)


def timed(ctx, fn: Callable[[], object], repeats: int, warmup: int = 2) -> tuple[float, float]:
    """(median wall ms, median GPU ms) of ``fn()`` with the GPU finished after each call: the
    wall time from the call to the finish, the GPU's from a timer query around both."""
    for _ in range(warmup):
        fn()
        ctx.finish()
    wall, gpu = [], []
    query = ctx.query(time=True)
    for _ in range(repeats):
        t0 = time.perf_counter()
        with query:
            fn()
        ctx.finish()
        wall.append((time.perf_counter() - t0) * 1e3)
        gpu.append(query.elapsed / 1e6)
    return statistics.median(wall), statistics.median(gpu)


def report(what: str, goal_ms: float, wall_ms: float, gpu_ms: float | None = None) -> None:
    met = "met" if wall_ms <= goal_ms else "not met"
    gpu = f", GPU {gpu_ms:.3f} ms" if gpu_ms is not None else ""
    print(f"{what}: {wall_ms:.3f} ms{gpu}{vs_floor(wall_ms)}; goal <= {goal_ms:g} ms: {met}")


def draw_target(ctx, size: tuple[int, int]):
    tex = ctx.texture(size, 4, dtype="f1")
    return tex, ctx.framebuffer(color_attachments=[tex])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--scale", type=float, default=1.0)
    args = ap.parse_args()

    def size(w: int, h: int) -> tuple[int, int]:
        return max(int(w * args.scale), 8), max(int(h * args.scale), 8)

    ctx = shared_context()
    print(f"# device: {gl_info(ctx).describe()}")
    print_floor(ctx)
    n = args.repeats

    # the scene: a clear sky, the Sun 30 deg up
    with Sky(VALLETTA, "2021-06-21T08:00Z", night=False) as sky:
        cam = PerspectiveCamera(fov_deg=90.0, yaw_deg=sky.state.sun.azimuth_deg, pitch_deg=15.0)
        s = size(1920, 1080)
        tex, fbo = draw_target(ctx, s)
        wall, gpu = timed(ctx, lambda: sky.draw(fbo, cam, size=s, exposure=12.0), n)
        report(f"scene {s[0]}x{s[1]} (Sky.draw, clear, 16 wavelengths)", 0.5, wall, gpu)
        fbo.release()
        tex.release()

    # clouds: interactive while turning, and a full-quality still
    s = size(1280, 720)
    layer = CloudLayer(Clouds("fair", seed=3), quality="interactive")
    with Sky(VALLETTA, "2021-06-21T09:00Z", night=False, clouds=layer) as sky:
        yaw = [sky.state.sun.azimuth_deg + 40.0]
        tex, fbo = draw_target(ctx, s)

        def turning():
            yaw[0] += 0.5
            moving = PerspectiveCamera(fov_deg=90.0, yaw_deg=yaw[0], pitch_deg=15.0)
            sky.draw(fbo, moving, size=s, exposure=15.0)

        wall, gpu = timed(ctx, turning, n, warmup=4)
        report(f"clouds interactive {s[0]}x{s[1]}, turning 0.5 deg a frame", 1.0, wall, gpu)
        fbo.release()
        tex.release()
    with Sky(VALLETTA, "2021-06-21T09:00Z", night=False, clouds=Clouds("fair", seed=3)) as sky:
        cam = PerspectiveCamera(fov_deg=90.0, yaw_deg=sky.state.sun.azimuth_deg + 40, pitch_deg=15)
        wall, gpu = timed(ctx, lambda: sky.render(cam, *s, exposure=None), max(n // 4, 3), 1)
        report(f"clouds full quality {s[0]}x{s[1]} (Sky.render, read back)", 10.0, wall, gpu)

    # the precomputation
    params, config = preset("earth"), PrecomputeConfig()
    t0 = time.perf_counter()
    precompute(ctx, params, config).release()
    first_ms = (time.perf_counter() - t0) * 1e3
    calls = []
    for _ in range(max(n // 4, 3)):
        t0 = time.perf_counter()
        tables = precompute(ctx, params, config)
        calls.append((time.perf_counter() - t0) * 1e3)
        stages = tables.timings
        tables.release()
    report("precompute, 16 wavelengths, 4 orders (least of the calls)", 50.0, min(calls))
    print(
        f"  first call in the process {first_ms:.0f} ms; the last call's stages: "
        + ", ".join(f"{k} {v * 1e3:.1f}" for k, v in stages.items())
        + " ms"
    )

    # the viewer's frame: Paranal's night, the time moving 10 min a frame (a new state and
    # re-aimed tables each frame: Sky.at), every night layer
    with Sky(PARANAL, "2024-05-01T03:00Z") as base:
        cam = PerspectiveCamera(fov_deg=90.0, yaw_deg=180.0, pitch_deg=30.0)
        tex, fbo = draw_target(ctx, s)
        minutes = iter(range(10, 100_000, 10))

        def night():
            m = next(minutes) % (20 * 60)
            later = base.at(f"2024-05-01T{3 + m // 60:02d}:{m % 60:02d}:00Z")
            later.draw(fbo, cam, size=s)
            later.release()

        wall, gpu = timed(ctx, night, n)
        report(f"viewer's night frame {s[0]}x{s[1]}, 10 min a frame", 1000 / 60, wall, gpu)
        fbo.release()
        tex.release()


if __name__ == "__main__":
    main()
