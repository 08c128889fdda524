"""What issue 25's light for a 3D scene costs: ``Sky.lighting()`` (the 256 x 128 map three
times, the disks' cameras, the harmonics and the median-cut lights), the prefiltered GGX cube
map (128-texel faces, all 6 mip levels, 256 samples a texel) and the split-sum BRDF table
(128 x 128, 16384 samples a texel).

Usage: python benchmarks/bench_lighting.py [--repeats 5]

Medians after warm-up (the tables built and cached, the shaders compiled once). Valletta
2018-03-01 10:00 local time (the Sun 40 deg up in the south-east).
"""

from __future__ import annotations

from timing import frame_args, median_ms

from skydome import Sky
from skydome.lighting_ibl import brdf_table


def main() -> None:
    repeats, _ = frame_args(__doc__, repeats=5)
    with Sky("Valletta", "2018-03-01T10:00") as sky:
        ctx = sky.graph.ctx
        ms = median_ms(sky.lighting, repeats)
        print(f"Sky.lighting() (256 x 128 map, SH, 16 lights): {ms:8.1f} ms")
        light = sky.lighting()
        ms = median_ms(lambda: light.prefiltered(ctx), repeats)
        print(f"prefiltered cube, 128 faces, 6 mips:           {ms:8.1f} ms")
        ms = median_ms(lambda: light.prefiltered(ctx, face_size=256), repeats)
        print(f"prefiltered cube, 256 faces, 7 mips:           {ms:8.1f} ms")
        ms = median_ms(lambda: brdf_table(ctx), repeats)
        print(f"BRDF table 128 x 128:                          {ms:8.1f} ms")


if __name__ == "__main__":
    main()
