"""The night sky's cost: the night layers against the atmosphere-only frame, per layer, and
the display passes.

Usage: python benchmarks/bench_night.py [--repeats 9]

Prints the GL device, then, for a Sky at La Palma on the new Moon of 2019-04-05 at 01:04 UTC
(the Sun 55 deg down; every night layer has work: ~19,000 stars above the horizon, the
Milky Way rising in the east), frames at 1280 x 720 (a 90 deg perspective camera looking
east, 30 deg up) read back:
- the atmosphere-only frame (the Sun, the Moon and the air; the night layers off) and the
  frame with every night layer (stars, planets, Milky Way, zodiacal light, airglow): the
  budget is night <= 1.30 x atmosphere-only, measured in the same run;
- each night layer alone on top of the atmosphere-only frame;
- the display passes on the tone-mapped image: night vision, overlays (lines, labels, grid);
- ``update``: a new time (astronomy, the stars' apparent places rotated to the horizon);
- a new time drawn: ``Sky.at`` then ``render`` at 640 x 360 (what a loop over times pays:
  the tables re-aimed, the layers' first draw), beside the same sky drawn again;
- ``draw 1920x1080``: Sky.draw with every layer, no read-back, GPU work finished.
"""

from __future__ import annotations

import argparse

from timing import draw_ms, median_ms, print_floor, vs_floor

from skydome import Sky
from skydome.core.cameras import PerspectiveCamera
from skydome.gpu import gl_info
from skydome.sky import NIGHT_LAYERS

PLACE = (28.7606, -17.8816, 2396.0)
TIME = "2019-04-05T01:04Z"
CAMERA = PerspectiveCamera(fov_deg=90.0, yaw_deg=90.0, pitch_deg=30.0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=9)
    args = ap.parse_args()
    sky = Sky(PLACE, TIME)
    ctx = sky.graph.ctx
    print(f"# device: {gl_info(ctx).describe()}")
    print_floor(ctx)

    def frame(on: tuple[str, ...], **kw):
        kw.setdefault("exposure", -8.0 if "tonemap" in kw else None)

        def run():
            for name in NIGHT_LAYERS:
                sky.layer(name).enabled = name in on
            sky.render(CAMERA, 1280, 720, **kw)
            ctx.finish()

        return run

    # Interleaved, so that a machine's drift hits both alike; the median of three medians.
    runs = {"air": [], "night": []}
    for _ in range(3):
        runs["air"].append(median_ms(frame(()), args.repeats // 3 or 1))
        runs["night"].append(median_ms(frame(NIGHT_LAYERS), args.repeats // 3 or 1))
    air_ms, night_ms = (sorted(v)[1] for v in runs.values())
    print(f"atmosphere-only frame 1280x720 (Sun, Moon, air): {air_ms:.1f} ms{vs_floor(air_ms)}")
    print(
        f"night frame 1280x720 (+ {', '.join(NIGHT_LAYERS)}): {night_ms:.1f} ms, "
        f"{night_ms / air_ms:.3f} x the atmosphere-only frame{vs_floor(night_ms)}"
    )
    for name in NIGHT_LAYERS:
        # Each layer alone, interleaved with the atmosphere-only frame: the median of the
        # differences of three pairs of medians.
        pairs = [
            median_ms(frame((name,)), args.repeats // 3 or 1)
            - median_ms(frame(()), args.repeats // 3 or 1)
            for _ in range(3)
        ]
        print(f"  + {name}: {sorted(pairs)[1]:+.1f} ms")
    tonemapped = median_ms(frame(NIGHT_LAYERS, tonemap="filmic"), args.repeats)
    sky.night_vision = True
    seen = median_ms(frame(NIGHT_LAYERS, tonemap="filmic"), args.repeats)
    sky.night_vision = False
    sky.overlays = "lines,labels,grid"
    drawn = median_ms(frame(NIGHT_LAYERS, tonemap="filmic"), args.repeats)
    sky.overlays = ()
    print(f"tone-mapped night frame: {tonemapped:.1f} ms; night vision {seen - tonemapped:+.1f} ms")
    print(f"  overlays (lines, labels, grid): {drawn - tonemapped:+.1f} ms")

    minute = iter(range(1, 10_000))

    def new_time():
        later = sky.at(f"2019-04-05T02:{next(minute) % 60:02d}:00Z")
        later.graph.update(later.state)
        ctx.finish()

    print(f"update (a new time, every layer): {median_ms(new_time, args.repeats):.1f} ms")

    def new_time_drawn():
        later = sky.at(f"2019-04-05T02:{next(minute) % 60:02d}:00Z")
        later.render(CAMERA, 640, 360)
        later.release()

    drawn_ms = median_ms(new_time_drawn, args.repeats)
    alone_ms = median_ms(lambda: sky.render(CAMERA, 640, 360), args.repeats)
    print(
        f"a new time drawn (Sky.at + render 640x360, auto exposure): {drawn_ms:.1f} ms; "
        f"the same sky drawn again {alone_ms:.1f} ms"
    )
    drawn = draw_ms(sky, CAMERA, (1920, 1080), args.repeats)
    print(f"draw 1920x1080 (every layer, no read-back): {drawn:.1f} ms{vs_floor(drawn)}")


if __name__ == "__main__":
    main()
