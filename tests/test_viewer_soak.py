"""A soak of the viewer's window: frames at changing times, places and parameters, with
resizes and atmosphere swaps, for SKYDOME_SOAK_S seconds (default 90). The process's
memory (RSS: llvmpipe's textures live in it too) stays within 5 % of its level after the
warm-up, and no GL object is left alive: the moderngl objects alive at the end, in the
state of the baseline, are those of the baseline."""

from __future__ import annotations

import gc
import os
import random
import time

import numpy as np
import pytest

from tests.conftest import TINY_TABLES
from tests.viewer_support import x_display  # noqa: F401  (fixture)

pytest.importorskip("glfw", reason="the viewer's window needs glfw")
pytest.importorskip("imgui_bundle", reason="the panel needs imgui-bundle")

#: Soak duration (s): SKYDOME_SOAK_S, default 90 (about 2 minutes with the set-up).
SOAK_S = float(os.environ.get("SKYDOME_SOAK_S", "90"))
#: The share of the soak spent warming up (every path visited once) before the baseline.
WARM_UP_SHARE = 0.25


def rss_bytes() -> int:
    """The resident set size of this process (bytes), from /proc (Linux), after the C
    heap's free pages are handed back (glibc's malloc_trim): what is still allocated, not
    what the allocator keeps for reuse (llvmpipe's shader JIT churns through it)."""
    import ctypes
    import ctypes.util

    gc.collect()
    try:
        ctypes.CDLL(ctypes.util.find_library("c")).malloc_trim(0)
    except (OSError, AttributeError):  # not glibc: the plain RSS
        pass
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def live_gl_objects(detail: dict | None = None) -> int:
    """moderngl objects alive and not released (textures, buffers, programs...); with
    ``detail``, their count per type goes there."""
    import moderngl

    kinds = (
        moderngl.Texture, moderngl.Texture3D, moderngl.TextureArray, moderngl.TextureCube,
        moderngl.Buffer, moderngl.Framebuffer, moderngl.Renderbuffer, moderngl.Program,
        moderngl.VertexArray, moderngl.Sampler,
    )  # fmt: skip
    gc.collect()
    live = [
        o
        for o in gc.get_objects()
        if isinstance(o, kinds) and type(o.mglo).__name__ != "InvalidObject"
    ]
    if detail is not None:
        for o in live:
            key = type(o).__name__
            if isinstance(o, moderngl.Texture):
                key += f" {o.size} {o.dtype}"
            detail[key] = detail.get(key, 0) + 1
    return len(live)


@pytest.mark.soak
@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="needs /proc (Linux)")
def test_soak_keeps_memory_flat_and_leaks_no_gl_objects(x_display):  # noqa: F811
    from skydome import Sky
    from skydome.viewer.app import ViewerWindow
    from skydome.viewer.controls import PROJECTIONS, Controls
    from skydome.viewer.rebuild import build_sky
    from skydome.viewer.scene import ViewerScene, initial_state

    rng = random.Random(13)
    win = ViewerWindow(320, 180, visible=False, panel=True)
    try:
        sky = Sky("Paranal", "2024-07-05T00:00Z", ctx=win.ctx, config=TINY_TABLES)
        params = sky.layer("atmosphere").params
        hazy = params.with_aerosol(aod_550=0.4)
        win.panel.configure(sky.description)
        scene = ViewerScene(sky, Controls(initial_state(sky, speed=3600.0)))
        c = scene.controls
        jd0 = c.state.jd_utc
        baseline_state = c.state
        sizes = [(320, 180), (256, 160), (320, 200)]
        marks: dict = {"frames": 0, "swaps": 0, "resizes": 0}

        def change(win, i):
            r = rng.random()
            if i % 5 == 0:  # a new time within a year, anywhere in the day
                c.set(jd_utc=jd0 + rng.uniform(0.0, 365.0))
            if i % 7 == 0:
                c.set(
                    yaw_deg=rng.uniform(0, 360),
                    pitch_deg=rng.uniform(-30, 89),
                    fov_deg=rng.uniform(10, 150),
                    projection=rng.choice(PROJECTIONS),
                )
            if i % 11 == 0:
                c.set(
                    exposure_mode=rng.choice(("auto", "ev", "adapt")),
                    ev100=rng.uniform(-5, 16),
                    tonemap=rng.choice(("filmic", "reinhard", "hvs", "linear")),
                    night_vision=r < 0.3,
                    overlays=rng.choice(((), ("grid",), ("lines", "labels"))),
                    layers_off=rng.choice(
                        (frozenset(), frozenset({"moon"}), frozenset({"stars", "milky_way"}))
                    ),  # fmt: skip
                    altitude_m=rng.choice((None, 1000.0, 40000.0)),
                    playing=r < 0.5,
                )
            if i % 13 == 0:  # walk a little
                c.set(latitude_deg=-24.6 + rng.uniform(-1, 1), longitude_deg=-70.4)

        def run_for(seconds: float) -> None:
            end = time.monotonic() + seconds
            while time.monotonic() < end:
                if marks["frames"] % 40 == 39:  # resize
                    w, h = sizes[marks["resizes"] % len(sizes)]
                    marks["resizes"] += 1
                    win.glfw.set_window_size(win.window, w, h)
                    win.glfw.poll_events()
                if marks["frames"] % 300 == 299:  # swap the atmosphere (tables from the cache)
                    swap = hazy if marks["swaps"] % 2 == 0 else params
                    marks["swaps"] += 1
                    scene.replace_sky(build_sky(scene.base, swap, TINY_TABLES))
                win.run(scene, frames=1, on_frame=lambda w_, _i: change(w_, marks["frames"]))
                marks["frames"] += 1

        def settle() -> tuple[int, int]:
            """Back to the baseline's state, size and atmosphere; a few frames; counts."""
            win.glfw.set_window_size(win.window, 320, 180)
            for _ in range(20):
                win.glfw.poll_events()
                if win.framebuffer_size() == (320, 180):
                    break
                time.sleep(0.05)
            # A fresh sky of the baseline's atmosphere: its layers compile only the passes
            # the baseline's frames use (a graph keeps each pass it compiled: one per camera
            # model and display choice met).
            scene.replace_sky(build_sky(scene.base, params, TINY_TABLES))
            c.state = baseline_state
            win.run(scene, frames=3)
            frame = scene.render(80, 45)
            assert np.isfinite(frame.data).all()
            return rss_bytes(), live_gl_objects()

        run_for(SOAK_S * WARM_UP_SHARE)
        rss0, objects0 = settle()
        run_for(SOAK_S * (1.0 - WARM_UP_SHARE))
        rss1, objects1 = settle()
        print(
            f"soak {SOAK_S:.0f} s: {marks}, RSS {rss0 / 2**20:.1f} -> {rss1 / 2**20:.1f} MiB, "
            f"GL objects {objects0} -> {objects1}"
        )
        assert marks["swaps"] >= 1 and marks["resizes"] >= 2, marks
        assert objects1 <= objects0, f"GL objects {objects0} -> {objects1}"
        growth = (rss1 - rss0) / rss0
        assert growth <= 0.05, f"RSS {rss0 / 2**20:.0f} -> {rss1 / 2**20:.0f} MiB ({growth:+.1%})"
        scene.release()
    finally:
        win.close()
