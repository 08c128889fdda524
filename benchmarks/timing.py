"""The benchmarks' one timing rule: untimed warm-up calls, then the median of timed repeats."""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable


def median_ms(fn: Callable[[], object], repeats: int, warmup: int = 2) -> float:
    """Median wall time of ``fn()`` in milliseconds over ``repeats`` calls after ``warmup``
    untimed ones (shader compilation, allocations, caches)."""
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append((time.perf_counter() - t0) * 1e3)
    return statistics.median(times)


def draw_ms(sky, camera, size: tuple[int, int], repeats: int) -> float:
    """Median time of ``sky.draw`` into an offscreen 8-bit framebuffer of ``size`` (what a
    window gets: no read-back), the GPU work finished."""
    ctx = sky.graph.ctx
    tex = ctx.texture(size, 4, dtype="f1")
    fbo = ctx.framebuffer(color_attachments=[tex])

    def draw():
        sky.draw(fbo, camera, size=size)
        ctx.finish()

    try:
        return median_ms(draw, repeats)
    finally:
        fbo.release()
        tex.release()


def frame_args(doc: str, repeats: int = 3) -> tuple[int, tuple[int, int]]:
    """The frame benchmarks' command line (``--repeats``, ``--size WxH``, described by the first
    line of ``doc``), their values, after printing the GL device they run on."""
    from skydome.gpu import gl_info, shared_context

    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=repeats)
    ap.add_argument("--size", default="1280x720")
    args = ap.parse_args()
    print(gl_info(shared_context()))
    return args.repeats, tuple(int(v) for v in args.size.split("x"))
