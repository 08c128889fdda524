"""The weather's costs on a 1280 x 720 frame: fog, rain, snow and a thunderstorm against the
clear sky and against the same clouds without their weather, the falling particles alone, and
the tables of hazy air (orders until they converge) against the clear air's.

Usage: python benchmarks/bench_weather.py [--repeats 3] [--size 1280x720]

A Sun alone 30 deg up (20 deg for the fog), a 90 deg perspective camera looking south 10 deg
up, ``Sky.render`` read back, full cloud quality. A fog alone is drawn from a table of view
directions kept while the camera's height, the time and the lights stay: timed kept (a
still view, the viewer turning) and marched afresh each frame (a time-lapse). Budgets
(issue 23, llvmpipe): fog or rain adds <= 30 % to a frame, the particles <= 10 %, the hazy
tables <= 2x the clear ones.
"""

from __future__ import annotations

import time

from timing import frame_args, median_ms, vs_floor

from skydome import Sky
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.atmosphere.presets import preset
from skydome.atmosphere.tables import load_tables
from skydome.gpu import shared_context
from skydome.weather import Weather
from skydome.weather_effects import weathered


def frame_ms(size, repeats, *, particles: bool = True, fresh_table: bool = False,
             **settings) -> float:  # fmt: skip
    """A frame's median time; ``fresh_table``: a fog alone's direction table marched for
    every frame (as for a time-lapse, whose Sun moves), else kept from the warm-up."""
    with Sky(sun_elevation_deg=settings.pop("sun", 30.0), **settings) as sky:
        camera = sky.camera("south", fov_deg=90, pitch_deg=10)
        for layer in sky.graph.layers:
            if layer.name == "precipitation":
                layer.enabled = particles

        def frame():
            if fresh_table:
                sky.layer("clouds")._table = None
            sky.render(camera, *size)

        return median_ms(frame, repeats, warmup=1)


def main() -> None:
    r, size = frame_args(__doc__)
    clear = frame_ms(size, r)
    print(f"clear sky: {clear:.0f} ms{vs_floor(clear)}")
    for label, weather, sun in (("fog (200 m, 150 m deep)", "fog", 20.0),
                                ("mist (2.5 km, 300 m deep)", "mist", 30.0)):  # fmt: skip
        kept = frame_ms(size, r, sun=sun, weather=weather)
        fresh = frame_ms(size, r, sun=sun, weather=weather, fresh_table=True)
        print(
            f"{label}: {kept:.0f} ms (+{100 * (kept / clear - 1):.0f} %) with its direction "
            f"table kept{vs_floor(kept)}, {fresh:.0f} ms (+{100 * (fresh / clear - 1):.0f} %) "
            f"marching it{vs_floor(fresh)}"
        )
    for name, clouds in (("rain", "nimbostratus"), ("snow", "nimbostratus"),
                         ("thunderstorm", "storm")):  # fmt: skip
        alone = frame_ms(size, r, clouds=clouds)
        bare = frame_ms(size, r, weather=name, particles=False)
        full = frame_ms(size, r, weather=name)
        print(
            f"{name}: {clouds} alone {alone:.0f} ms, with the {name} volume {bare:.0f} ms "
            f"(+{100 * (bare / alone - 1):.0f} %), with its particles {full:.0f} ms "
            f"(+{100 * (full / bare - 1):.0f} %){vs_floor(full)}"
        )
    ctx = shared_context()
    for label, weather in (("clear air (4 orders)", None), ("hazy, 8 km", Weather("hazy")),
                           ("mist's air", Weather("mist"))):  # fmt: skip
        air, _, config = weathered(weather, preset("earth"), None, PrecomputeConfig())
        t0 = time.perf_counter()
        tables, _ = load_tables(ctx, air, config, cache=False)
        seconds = time.perf_counter() - t0
        print(f"tables, {label}: {seconds:.2f} s, {tables.orders_computed} orders")
        tables.release()


if __name__ == "__main__":
    main()
