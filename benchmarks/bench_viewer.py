"""The viewer's frame rate in its window: ``skydome view``'s own frame timer over a span of
seconds, under Xvfb when there is no display.

Usage: python benchmarks/bench_viewer.py [--seconds 10] [--size 1280x720] [--frame-budget MS]

Prints the GL device, then for each case the median frames per second over ``--seconds``
(after 1 s of warm-up), with the median CPU time per stage (ms) and, where timed, the GPU
time per pass (ms). The scene is Valletta, 2018-03-09 06:00 UTC (the Sun 7 deg and a waning
Moon 33 deg up, as benchmarks/bench_scene.py), ``night=False`` (the atmosphere, the Sun and
the Moon), auto exposure, filmic, looking at the Sun with a 90 deg field of view:

- ``static``: the time stands still, no panel (the viewer shows its kept frame: one blit);
- ``static + panel``: with the control panel drawn;
- ``turning``: the camera turns by 0.05 deg a frame, as while dragging the view (a new view
  every frame: the layers, the exposure and the tone map drawn; the tables not re-aimed);
- ``playing 1 min/s``: the time runs (a new SkyState and re-aimed tables each time the Sun
  or the Moon has moved by half a pixel, about every 0.14 s; the kept frame in between);
- ``playing 1 day/s`` (a new SkyState and re-aimed tables every frame);
- ``turning, GPU timing``: ``turning`` with the per-pass GPU timer queries (each pass
  finished before its query ends: the cost of knowing);
- ``night playing 10 min/s``: Paranal at night (every night layer), the time running;
- ``clouds turning``: ``turning`` with ``clouds="fair"`` at the viewer's interactive cloud
  quality (what ``skydome view`` uses on a CPU rasterizer).

``--frame-budget MS`` is the viewer's dynamic resolution (``skydome view --frame-budget``;
default 33 ms; 0: every frame at full resolution, the viewer before it). A case's line ends
with the median render scale of its frames drawn anew.

The target is >= 30 fps at 1280 x 720 on llvmpipe (aim: 60).
"""

from __future__ import annotations

import argparse
import os
import statistics

from timing import floor_measured, print_floor, vs_floor

from skydome import Sky
from skydome.gpu import gl_info

PLACE = (35.8989, 14.5146, 56.0)
TIME = "2018-03-09T06:00Z"
#: The turning cases' turn per frame (deg).
TURN_DEG = 0.05


#: The night case: Paranal, a moonless hour (every night layer drawn).
NIGHT = ("Paranal", "2024-07-05T03:00Z")


def measure(
    size, seconds: float, *, panel: bool, speed: float | None, gpu: bool, turn: bool = False,
    budget_ms: float = 33.0, night: bool = False, clouds: str | None = None,
):  # fmt: skip
    from skydome.viewer.app import ViewerWindow
    from skydome.viewer.controls import Controls
    from skydome.viewer.frame_timer import FrameTimer
    from skydome.viewer.scene import ViewerScene, initial_state

    with ViewerWindow(*size, panel=panel) as win:
        if night:
            sky = Sky(*NIGHT, ctx=win.ctx)
            fields = dict(yaw_deg=180.0, pitch_deg=30.0, fov_deg=90.0)
        else:
            extra = {} if clouds is None else dict(clouds=clouds, cloud_quality="interactive")
            sky = Sky(PLACE, TIME, ctx=win.ctx, night=False, **extra)
            look = sky.camera("sun")
            fields = dict(yaw_deg=look.yaw_deg, pitch_deg=look.pitch_deg, fov_deg=90.0)
        if speed is not None:
            fields.update(playing=True, speed=speed)
        scene = ViewerScene(sky, Controls(initial_state(sky, **fields)))
        scene.frame_budget_ms = budget_ms
        if panel:
            win.panel.configure(sky.description)
        scales = []

        def turning(_win, _i):
            scene.controls.set(yaw_deg=scene.controls.state.yaw_deg + TURN_DEG)
            if scene.redrew:
                scales.append(scene.render_scale)

        def watching(_win, _i):
            if scene.redrew:
                scales.append(scene.render_scale)

        on_frame = turning if turn else watching
        win.timer = FrameTimer(win.ctx, gpu=gpu)
        win.run(scene, duration_s=1.0, on_frame=on_frame)  # warm-up: shaders, targets
        win.timer = FrameTimer(win.ctx, gpu=gpu, window=1_000_000)
        scales.clear()
        timer = win.run(scene, duration_s=seconds, on_frame=on_frame)
        frames = len(timer.frame_ms)
        median = statistics.median(timer.frame_ms)
        report = timer.report()
        scene.release()
        info = gl_info(win.ctx).describe()
        if not floor_measured():
            print_floor(win.ctx)
    scale = statistics.median(scales) if scales else None
    return 1e3 / median, frames, report, info, scale


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--frame-budget", type=float, default=33.0, help="ms; 0: off")
    ap.add_argument("--cases", default="", help="comma list of case names (default: all)")
    args = ap.parse_args()
    w, h = (int(v) for v in args.size.lower().split("x"))
    xvfb = None
    if not os.environ.get("DISPLAY"):
        from skydome.viewer.xvfb import start_xvfb

        xvfb, os.environ["DISPLAY"] = start_xvfb(f"{max(w, 1920)}x{max(h, 1080)}x24")
    try:
        cases = [
            ("static", dict(panel=False, speed=None, gpu=False)),
            ("static + panel", dict(panel=True, speed=None, gpu=False)),
            ("turning", dict(panel=False, speed=None, gpu=False, turn=True)),
            ("playing 1 min/s", dict(panel=False, speed=60.0, gpu=False)),
            ("playing 1 day/s", dict(panel=False, speed=86400.0, gpu=False)),
            ("turning, GPU timing", dict(panel=False, speed=None, gpu=True, turn=True)),
            ("night playing 10 min/s", dict(panel=False, speed=600.0, gpu=False, night=True)),
            ("clouds turning", dict(panel=False, speed=None, gpu=False, turn=True,
                                    clouds="fair")),
        ]  # fmt: skip
        if args.cases:
            wanted = {c.strip() for c in args.cases.split(",")}
            cases = [c for c in cases if c[0] in wanted]
        printed = False
        for name, kw in cases:
            fps, frames, report, info, scale = measure(
                (w, h), args.seconds, budget_ms=args.frame_budget, **kw
            )
            if not printed:
                print(
                    f"device: {info}; window {w}x{h}, {args.seconds:g} s per case, "
                    f"frame budget {args.frame_budget:g} ms"
                )
                printed = True
            cpu = ", ".join(f"{k} {v:.1f}" for k, v in report["cpu"].items())
            line = (
                f"{name:20s} {fps:5.1f} fps ({frames} frames){vs_floor(1e3 / fps)}; cpu ms: {cpu}"
            )
            if report["gpu"]:
                line += "; gpu ms: " + ", ".join(f"{k} {v:.1f}" for k, v in report["gpu"].items())
            if scale is not None:
                line += f"; scale {scale:g}"
            print(line, flush=True)
    finally:
        if xvfb is not None:
            xvfb.terminate()


if __name__ == "__main__":
    main()
