"""The benchmarks' one timing rule: untimed warm-up calls, then the median of timed repeats;
and the floor every GPU figure is printed beside: a bare lookup-table pass measured in the
same run, so that figures from a noisy or a different machine compare (issue 27 item 6)."""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable

import numpy as np

#: The floor's pass: per pixel, 4 trilinear fetches from a 32^3 RGBA float table (what the
#: sky's own lookups cost at the least), written to a float target.
_FLOOR_VERTEX = """#version 330
in vec2 in_pos;
out vec2 v_uv;
void main() { v_uv = in_pos * 0.5 + 0.5; gl_Position = vec4(in_pos, 0.0, 1.0); }
"""
_FLOOR_FRAGMENT = """#version 330
uniform sampler3D u_table;
in vec2 v_uv;
out vec4 colour;
void main() {
    vec4 sum = vec4(0.0);
    for (int i = 0; i < 4; ++i) sum += texture(u_table, vec3(v_uv, 0.2 + 0.2 * float(i)));
    colour = sum;
}
"""


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
    line of ``doc``), their values, after printing the GL device they run on and the floor."""
    from skydome.gpu import gl_info, shared_context

    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=repeats)
    ap.add_argument("--size", default="1280x720")
    args = ap.parse_args()
    ctx = shared_context()
    print(gl_info(ctx))
    print_floor(ctx)
    return args.repeats, tuple(int(v) for v in args.size.split("x"))


def floor_ms(ctx, size: tuple[int, int] = (1280, 720), repeats: int = 15) -> float:
    """The lookup-table floor (ms): a full-screen pass of 4 fetches from a 3D float table at
    ``size``, GPU work finished, its median after warm-up. Every GL object is released."""
    rng = np.random.default_rng(0)
    table = ctx.texture3d((32, 32, 32), 4, rng.random((32, 32, 32, 4), "f4").tobytes(), dtype="f4")
    target = ctx.texture(size, 4, dtype="f4")
    fbo = ctx.framebuffer(color_attachments=[target])
    prog = ctx.program(vertex_shader=_FLOOR_VERTEX, fragment_shader=_FLOOR_FRAGMENT)
    quad = ctx.buffer(np.array([-1, -1, 1, -1, -1, 1, 1, 1], "f4").tobytes())
    vao = ctx.vertex_array(prog, [(quad, "2f", "in_pos")])

    def draw():
        fbo.use()
        table.use(0)
        prog["u_table"].value = 0
        vao.render(mode=ctx.TRIANGLE_STRIP)
        ctx.finish()

    try:
        return median_ms(draw, repeats)
    finally:
        for obj in (vao, quad, prog, fbo, target, table):
            obj.release()


#: This run's floor (ms), once ``print_floor`` measured it.
_floor: list[float] = []


def print_floor(ctx, size: tuple[int, int] = (1280, 720)) -> float:
    """Measure and print the lookup-table floor (kept for ``vs_floor``); returns it (ms)."""
    _floor[:] = [floor_ms(ctx, size)]
    print(f"# floor (4-fetch 3D-table pass, {size[0]}x{size[1]}): {_floor[0]:.2f} ms")
    return _floor[0]


def floor_measured() -> bool:
    """Whether this run's floor is measured."""
    return bool(_floor)


def vs_floor(ms: float) -> str:
    """`` [41 x floor]``: a figure (ms) over this run's floor ('' before it is measured)."""
    return f" [{ms / _floor[0]:.1f} x floor]" if _floor else ""
