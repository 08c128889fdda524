"""Tone-mapping speed: NumPy reference vs the GLSL pass, per operator.

Prints the median of several runs after a warm-up, in ms, for a 1280x720 frame:
``numpy`` (float64 reference, exposure + operator + sRGB + quantize), ``gl array`` (upload,
draw, read back) and ``gl texture`` (draw from a texture already on the GPU, read back).

    python benchmarks/bench_tonemap.py [--width 1280 --height 720 --runs 7]
"""

from __future__ import annotations

import argparse

import numpy as np
from timing import median_ms

from skydome.display import TONEMAPS, GpuToneMapper, auto_exposure, tonemap, upload_frame
from skydome.gpu import gl_info


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--width", type=int, default=1280)
    ap.add_argument("--height", type=int, default=720)
    ap.add_argument("--runs", type=int, default=7)
    args = ap.parse_args()

    rng = np.random.default_rng(0)
    h, w = args.height, args.width
    lum = 10.0 ** rng.uniform(-2, 6, (h, w, 1))
    frame = np.concatenate([rng.uniform(0, 1, (h, w, 3)) * lum, lum], -1).astype(np.float32)
    scale = auto_exposure(frame)
    mapper = GpuToneMapper()
    tex = upload_frame(mapper.ctx, frame)
    print(f"{w}x{h}, median of {args.runs} runs, {gl_info(mapper.ctx).describe()}")
    print(f"{'operator':<12} {'numpy ms':>10} {'gl array ms':>12} {'gl texture ms':>14}")
    for name in TONEMAPS:
        t_np = median_ms(lambda n=name: tonemap(frame, n, scale), args.runs, warmup=1)
        t_gl = median_ms(lambda n=name: mapper.render(frame, n, scale), args.runs, warmup=1)
        t_tex = median_ms(lambda n=name: mapper.render(tex, n, scale), args.runs, warmup=1)
        print(f"{name:<12} {t_np:>10.1f} {t_gl:>12.1f} {t_tex:>14.1f}")
    tex.release()
    mapper.release()


if __name__ == "__main__":
    main()
