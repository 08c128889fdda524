"""The clouds' costs: a still frame at full quality, and the interactive mode (a reduced,
temporally accumulated march) over a turning camera, with the image error it costs.

Usage: python benchmarks/bench_clouds.py [--repeats 5] [--size 1280x720] [--frames 30]

Prints the GL device, then:
- ``full``: ``Sky.render`` of fair-weather cumulus (preset "fair", seed 3) over Valletta at
  2021-06-21 09:00 UTC (the Sun 60 deg up), a 90 deg perspective camera 15 deg up, read
  back; the sky probe and the light map made afresh (``CloudLayer.sky_probe``,
  ``CloudLayer.light_map``); the same frame without clouds; the ``best`` quality (every pixel marched) and the
  full frame's error against it; the full frame with 2 x 2 rays a pixel (``supersample=2``);
- ``interactive``: ``Sky.draw`` into an offscreen framebuffer (no read-back) while the camera
  turns 0.5 deg per frame, median over ``--frames`` frames; then, with the camera still, the
  relative error of the accumulated frame's luminance after 16 frames (``refine=False``)
  against the full-quality frame without light shafts (the accumulating frames draw none;
  median and 95th percentile over the pixels, and the mean bias); then the default
  (``refine=True``): the frames until the still view stops settling, the refining frame's
  time and its error against the full-quality frame with shafts.
Budgets (llvmpipe): full <= 2 s, interactive <= 100 ms per frame at 1280 x 720, the sky
probe <= 10 % of a full frame.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from timing import median_ms, print_floor, vs_floor

from skydome import Sky
from skydome.clouds.layer import CloudLayer
from skydome.clouds.params import Clouds
from skydome.core.cameras import PerspectiveCamera
from skydome.gpu import gl_info

PLACE = (35.8989, 14.5146, 56.0)
TIME = "2021-06-21T09:00Z"


def sky_with(quality: str, shafts: bool | None = None, refine: bool = True) -> Sky:
    layer = CloudLayer(Clouds("fair", seed=3), quality=quality, shafts=shafts, refine=refine)
    return Sky(PLACE, TIME, night=False, clouds=layer)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--frames", type=int, default=30)
    args = ap.parse_args()
    w, h = (int(v) for v in args.size.split("x"))
    full = sky_with("full")
    ctx = full.graph.ctx
    print(f"# device: {gl_info(ctx).describe()}")
    print_floor(ctx)
    yaw = full.state.sun.azimuth_deg + 40.0
    cam = PerspectiveCamera(fov_deg=90.0, yaw_deg=yaw, pitch_deg=15.0)
    ms = median_ms(lambda: full.render(cam, w, h, exposure=None), args.repeats, warmup=1)
    print(
        f"full {w}x{h}: {ms:.0f} ms per frame{vs_floor(ms)} (median of {args.repeats}; the "
        "march at half the resolution)"
    )
    layer = full.layer("clouds")

    def probe():
        layer._probe = None  # made afresh, as when the time or the light changes
        layer.sky_probe()

    probe_ms = median_ms(probe, args.repeats, warmup=1)
    print(
        f"  the sky probe (made when the sky changes): {probe_ms:.0f} ms, {probe_ms / ms:.1%} of it"
    )
    cloud, textures = layer.cloud_inputs(), layer.texture_inputs()

    def light_map():
        layer._light_map = (None, *layer._light_map[1:])  # drawn afresh, as for a new time
        layer.light_map(cloud, textures)
        full.graph.ctx.finish()

    map_ms = median_ms(light_map, args.repeats, warmup=1)
    print(f"  the light map (made when the sky changes): {map_ms:.0f} ms, {map_ms / ms:.1%} of it")
    layer.enabled = False
    bare = median_ms(lambda: full.render(cam, w, h, exposure=None), args.repeats, warmup=1)
    print(f"  the same frame without clouds: {bare:.0f} ms{vs_floor(bare)}")
    layer.enabled = True
    reference = full.render(cam, w, h, exposure=None).data[..., 1]
    best = sky_with("best")
    best_ms = median_ms(lambda: best.render(cam, w, h, exposure=None), 1, warmup=1)
    best_y = best.render(cam, w, h, exposure=None).data[..., 1]
    rel = np.abs(reference - best_y) / np.maximum(best_y, 1e-3)
    print(
        f"best {w}x{h} (every pixel, finer steps): {best_ms:.0f} ms; full against it: "
        f"median {np.median(rel):.1%}, 95th percentile {np.percentile(rel, 95):.1%}"
    )
    best.graph.release()
    ss_ms = median_ms(lambda: full.render(cam, w, h, exposure=None, supersample=2), 1, warmup=1)
    print(f"full {w}x{h}, 2 x 2 rays a pixel (supersample=2): {ss_ms:.0f} ms{vs_floor(ss_ms)}")

    inter = sky_with("interactive")
    tex = ctx.texture((w, h), 4, dtype="f1")
    fbo = ctx.framebuffer(color_attachments=[tex])
    times = []
    for i in range(args.frames + 3):
        moving = PerspectiveCamera(fov_deg=90.0, yaw_deg=yaw + 0.5 * i, pitch_deg=15.0)
        t0 = time.perf_counter()
        inter.draw(fbo, moving, size=(w, h), exposure=15.0)
        ctx.finish()
        if i >= 3:
            times.append((time.perf_counter() - t0) * 1e3)
    print(
        f"interactive {w}x{h}, turning 0.5 deg/frame: {statistics.median(times):.0f} ms per "
        f"frame{vs_floor(statistics.median(times))} (median of {len(times)})"
    )
    accumulating = sky_with("interactive", refine=False)
    for _ in range(16):
        frame = accumulating.render(cam, w, h, exposure=None)
    accumulating.release()
    flat = sky_with("full", shafts=False)  # the accumulating frames draw no light shafts
    flat_y = flat.render(cam, w, h, exposure=None).data[..., 1]
    flat.release()
    rel = np.abs(frame.data[..., 1] - flat_y) / np.maximum(flat_y, 1e-3)
    bias = float(np.mean(frame.data[..., 1]) / np.mean(flat_y) - 1.0)
    print(
        f"  accumulated (refine=False), error against full quality (no shafts) after 16 "
        f"still frames: median {np.median(rel):.1%}, "
        f"95th percentile {np.percentile(rel, 95):.1%}, mean luminance {bias:+.1%}"
    )
    layer = inter.layer("clouds")
    still_ms = []
    while not still_ms or layer.settling:
        t0 = time.perf_counter()
        inter.draw(fbo, cam, size=(w, h), exposure=15.0)
        ctx.finish()
        still_ms.append((time.perf_counter() - t0) * 1e3)
    refined = inter.render(cam, w, h, exposure=None).data[..., 1]
    rel = np.abs(refined - reference) / np.maximum(reference, 1e-3)
    print(
        f"  refined (the default): settled after {len(still_ms)} still frames, the refining "
        f"frame {still_ms[-1]:.0f} ms; against full quality: max {rel.max():.1e}"
    )
    fbo.release()
    tex.release()


if __name__ == "__main__":
    main()
