"""The benchmarks' one timing rule: untimed warm-up calls, then the median of timed repeats."""

from __future__ import annotations

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
