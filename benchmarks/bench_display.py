"""What issue 26's display and eclipse work costs a still: a tone-mapped 1280 x 720 frame
with glare off, eye and lens, with each metering, and a frame of the Dallas eclipse of
2024-04-08 (outside it, in the partial phase, in totality) against the same place an hour
earlier.

Usage: python benchmarks/bench_display.py [--repeats 5] [--size 1280x720]

``Sky.render`` read back (the frame graph, the exposure, the glare, the tone map), the tables
built and cached before timing (median_ms's warm-up). Valletta 2018-03-01 17:15 UTC (dusk: the
Sun 4.5 deg down, the full Moon rising) looking at the Moon for the display passes.
"""

from __future__ import annotations

from timing import frame_args, median_ms, vs_floor

from skydome import Sky


def main() -> None:
    repeats, (w, h) = frame_args(__doc__, repeats=5)
    with Sky("Valletta", "2018-03-01T17:15Z") as sky:
        cam = sky.camera("moon", fov_deg=80, pitch_deg=12)
        base = None
        for glare in ("off", "eye", "lens"):
            ms = median_ms(
                lambda g=glare: sky.render(cam, w, h, tonemap="filmic", glare=g), repeats
            )
            base = ms if base is None else base
            print(
                f"tone-mapped frame, glare {glare:4s}: {ms:7.1f} ms (+{ms - base:.1f}){vs_floor(ms)}"
            )
        for metering in ("average", "center", "spot", "eye"):
            ms = median_ms(
                lambda m=metering: sky.render(cam, w, h, tonemap="filmic", glare="off", metering=m),
                repeats,
            )
            print(f"tone-mapped frame, metering {metering:7s}: {ms:7.1f} ms{vs_floor(ms)}")
    for label, when in (
        ("an hour before the eclipse", "2024-04-08T16:20Z"),
        ("in the partial phase, 18:05 UTC", "2024-04-08T18:05Z"),
        ("totality", "2024-04-08T18:42Z"),
    ):
        with Sky("Dallas", when) as sky:
            cam = sky.camera("sun", fov_deg=90)
            ms = median_ms(lambda s=sky, c=cam: s.render(c, w, h, exposure=None), repeats)
            print(f"Dallas, {label:32s}: {ms:7.1f} ms (HDR frame){vs_floor(ms)}")


if __name__ == "__main__":
    main()
