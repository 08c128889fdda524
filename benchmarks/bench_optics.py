"""The optics' costs: ice halos in a cirrus frame (1280 x 720) against the same cirrus without
them, diamond dust with and without halos, a fog of 5 um droplets (their own phase function)
against one of the clouds' 10 um, and the halo tables' tracing (the first at a process's
start, a new light elevation).

Usage: python benchmarks/bench_optics.py [--repeats 3] [--size 1280x720]

A cirrostratus (the "cirrus" preset at 0.9 coverage), the Sun 20 deg up in the south, a 110
deg perspective camera looking at it, ``Sky.render`` read back, full cloud quality; the two
frames interleaved (this machine's speed drifts between runs). Budgets (issue 24): the
optics add <= 10 % to a frame with weather, tables build in <= 30 s on llvmpipe.
"""

from __future__ import annotations

import statistics
import time

from timing import frame_args, vs_floor

from skydome import Sky
from skydome.clouds import halos
from skydome.clouds.params import Clouds
from skydome.core.basis import SpectralBasis
from skydome.spectra import ACCURATE_NM
from skydome.weather import Weather


def table_s(elevation_deg: float) -> float:
    """Seconds to trace the default mixture's table for a light at ``elevation_deg``."""
    basis = SpectralBasis.for_wavelengths(ACCURATE_NM)
    start = time.perf_counter()
    halos.halo_table(halos.DEFAULT_HALOS, elevation_deg, basis.wavelengths_nm, basis.to_output)
    return time.perf_counter() - start


def main() -> None:
    repeats, size = frame_args(__doc__)
    print(f"halo table, first in the process (random crystals' phase function too): "
          f"{table_s(20.0):.1f} s")  # fmt: skip
    print(f"halo table, a new light elevation: {table_s(21.0):.1f} s")
    pairs = {
        "cirrus": {
            name: dict(sun_elevation_deg=20.0, clouds=Clouds("cirrus", cirrus=0.9, halos=spec))
            for name, spec in (("without halos", "none"), ("with halos", halos.DEFAULT_HALOS))
        },
        "diamond dust": {
            name: dict(
                sun_elevation_deg=15.0,
                weather=Weather("diamond-dust"),
                clouds=Clouds("clear", halos=spec),
            )  # fmt: skip
            for name, spec in (("without halos", "none"), ("with halos", halos.DEFAULT_HALOS))
        },
        "fog 150 m, 300 m visibility": {
            name: dict(
                sun_elevation_deg=10.0, weather=Weather("fog", visibility_km=0.3, fog_droplet_um=um)
            )  # fmt: skip
            for name, um in (("10 um droplets", 10.0), ("5 um droplets", 5.0))
        },
    }
    for label, settings in pairs.items():
        times = interleaved(settings, size, repeats)
        base = statistics.median(next(iter(times.values())))
        for name, values in times.items():
            ms = statistics.median(values)
            print(
                f"{label} frame {name}: {ms:.0f} ms ({100.0 * (ms / base - 1.0):+.1f} %){vs_floor(ms)}"
            )


def interleaved(settings: dict, size, repeats: int) -> dict[str, list[float]]:
    """Each sky's frame times (ms), the skies drawn in turn after a warm-up each."""
    skies = {name: Sky(**kw) for name, kw in settings.items()}
    times: dict[str, list[float]] = {name: [] for name in skies}
    try:
        cameras = {name: sky.camera("sun", fov_deg=110) for name, sky in skies.items()}
        for name, sky in skies.items():  # warm-up: programs, tables, the halo table
            sky.render(cameras[name], *size)
        for _ in range(repeats):
            for name, sky in skies.items():
                start = time.perf_counter()
                sky.render(cameras[name], *size)
                times[name].append(1e3 * (time.perf_counter() - start))
    finally:
        for sky in skies.values():
            sky.release()
    return times


if __name__ == "__main__":
    main()
