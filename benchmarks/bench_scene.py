"""The scene's costs: a frame with the Sun and the Moon against the atmosphere alone, a new
time, a window draw, and a 24-hour time-lapse.

Usage: python benchmarks/bench_scene.py [--repeats 9] [--no-timelapse]

Prints the GL device, then:
- frames at 1280 x 720 of a Sky at Valletta, 2018-03-09 06:00 UTC (the Sun 7 deg and a
  waning Moon 33 deg up, both in the view), read back: the scene (both disks), its
  atmosphere layer alone, and, for scale, a Sky of the atmosphere layer alone lit by the Sun
  only; the budget is scene <= 1.15 x the atmosphere alone (the Sun this high outshines the
  Moon's light on the air, which is left out: atmosphere.layer.MOON_OUTSHONE_ABOVE_DEG);
- ``at(t)``: a new time (astronomy, the sky-view tables re-aimed at the lights that moved;
  the Moon's disk integral comes at the first draw that sees the disk), GPU work finished;
  a whole Sky's life (made, a first small frame, released);
- ``draw 1920x1080``: Sky.draw into an offscreen 8-bit framebuffer (no read-back; GPU
  exposure and tone mapping), GPU work finished;
- ``timelapse``: ``skydome timelapse`` of 24 hours at 1-minute steps (1441 frames) at
  640 x 360 to MP4, wall time of the command (a process of its own).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from timing import draw_ms, median_ms, print_floor, vs_floor

from skydome import Sky
from skydome.atmosphere.layer import AtmosphereLayer
from skydome.celestial.moon import MoonLayer
from skydome.celestial.sun import SunLayer
from skydome.core.cameras import PerspectiveCamera
from skydome.gpu import gl_info
from skydome.scene.state import state_series

PLACE = (35.8989, 14.5146, 56.0)
TIME = "2018-03-09T06:00Z"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=9)
    ap.add_argument("--no-timelapse", action="store_true")
    args = ap.parse_args()
    sky = Sky(PLACE, TIME, night=False)  # the Sun and the Moon (bench_night.py: the night)
    ctx = sky.graph.ctx
    print(f"# device: {gl_info(ctx).describe()}")
    print_floor(ctx)
    # Both disks in view: look between them.
    sun, moon = sky.state.sun, sky.state.moon
    cam = PerspectiveCamera(
        fov_deg=120.0, yaw_deg=0.5 * (sun.azimuth_deg + moon.azimuth_deg), pitch_deg=20.0
    )
    air = sky.layer("atmosphere")
    # The same air and tables, lit by the Sun alone (its direction and distance this morning).
    alone = Sky(
        sun_elevation_deg=sun.elevation_deg, sun_azimuth_deg=sun.azimuth_deg, ctx=ctx,
        layers=[AtmosphereLayer(air.params, config=air.sky.config)],
    )  # fmt: skip

    def renderer_frame():
        alone.render(cam, 1280, 720, altitude_m=sky.altitude_m(), exposure=None)

    def scene_frame():
        sky.render(cam, 1280, 720, exposure=None)

    disks = [sky.layer("sun"), sky.layer("moon")]

    def atmosphere_layer_frame():
        for layer in disks:
            layer.enabled = False
        try:
            sky.render(cam, 1280, 720, exposure=None)
        finally:
            for layer in disks:
                layer.enabled = True

    # Interleaved, so that a machine's drift hits all alike; the median of three medians.
    runs = {"renderer": [], "air": [], "scene": []}
    for _ in range(3):
        runs["renderer"].append(median_ms(renderer_frame, args.repeats // 3 or 1))
        runs["air"].append(median_ms(atmosphere_layer_frame, args.repeats // 3 or 1))
        runs["scene"].append(median_ms(scene_frame, args.repeats // 3 or 1))
    r_ms, a_ms, s_ms = (sorted(v)[1] for v in runs.values())
    print(f"atmosphere layer lit by the Sun alone 1280x720: {r_ms:.1f} ms{vs_floor(r_ms)}")
    print(
        f"atmosphere layer alone 1280x720 (the Sun outshines the Moon): {a_ms:.1f} ms"
        f"{vs_floor(a_ms)}"
    )
    print(
        f"scene frame 1280x720 (+ Sun and Moon disks): {s_ms:.1f} ms, "
        f"{s_ms / a_ms:.3f} x the atmosphere layer alone{vs_floor(s_ms)}"
    )

    minute = iter(range(1, 10_000))

    def new_time(base: Sky):
        """A callable: the next minute's sky, its layers updated and the atmosphere's
        sky-view tables re-aimed at the lights, the GPU work finished."""

        def step():
            later = base.at(f"2018-03-09T07:{next(minute) % 60:02d}:00Z")
            later.graph.update(later.state)
            layer = later.layer("atmosphere")
            layer.sky.frame_plan(later.altitude_m(), layer.lights())
            ctx.finish()
            later.release()

        return step

    at_ms = median_ms(new_time(sky), args.repeats)
    print(f"at(t) (astronomy + sky-view tables re-aimed): {at_ms:.1f} ms{vs_floor(at_ms)}")
    air_small = AtmosphereLayer(air.params, sky_view_size=(128, 128))
    small = Sky(PLACE, TIME, layers=[SunLayer(), MoonLayer(), air_small])
    small_ms = median_ms(new_time(small), args.repeats)
    print(f"  with 128x128 sky-view tables (time-lapses): {small_ms:.1f} ms")
    one = median_ms(lambda: state_series(sky.observer, [TIME]), args.repeats)
    batch = [f"2018-03-09T06:{m:02d}:30Z" for m in range(40)]
    many = median_ms(lambda: state_series(sky.observer, batch), 3) / len(batch)
    print(f"  astronomy alone: {one:.1f} ms for one time, {many:.2f} ms per time in a batch of 40")

    def lifetime():
        """A whole Sky's life: made (tables shared), a first 64 x 32 frame (its shaders
        compiled, its textures uploaded), released."""
        with Sky(PLACE, f"2018-03-09T08:{next(minute) % 60:02d}:00Z", ctx=ctx) as one:
            one.render(width=64, height=32, exposure=None)

    life_ms = median_ms(lifetime, args.repeats)
    print(f"a Sky made, drawn once at 64x32 and released: {life_ms:.1f} ms")

    drawn = draw_ms(sky, cam, (1920, 1080), args.repeats)
    print(f"draw 1920x1080 (no read-back): {drawn:.1f} ms{vs_floor(drawn)}")

    if not args.no_timelapse:
        with tempfile.TemporaryDirectory() as d:
            out = Path(d) / "day.mp4"
            t0 = time.perf_counter()
            r = subprocess.run(
                [sys.executable, "-m", "skydome", "timelapse", "--lat", "35.8989",
                "--lon", "14.5146", "--start", "2018-03-01T00:00Z", "--end", "2018-03-02T00:00Z", "--step", "1min",
                "--size", "640x360", "-o", str(out)],
                capture_output=True, text=True,
            )  # fmt: skip
            wall = time.perf_counter() - t0
            if r.returncode != 0:
                raise SystemExit(r.stderr)
            print(
                f"timelapse 24 h at 1 min (1441 frames) 640x360 to MP4: {wall:.1f} s "
                f"({out.stat().st_size / 1e6:.2f} MB); {r.stdout.strip().splitlines()[-1]}"
            )


if __name__ == "__main__":
    main()
