"""The optics' costs: ice halos in a cirrus frame (1280 x 720) against the same cirrus without
them, and the halo tables' tracing (the first at a process's start, a new light elevation).

Usage: python benchmarks/bench_optics.py [--repeats 3] [--size 1280x720]

A cirrostratus (the "cirrus" preset at 0.9 coverage), the Sun 20 deg up in the south, a 110
deg perspective camera looking at it, ``Sky.render`` read back, full cloud quality; the two
frames interleaved (this machine's speed drifts between runs). Budgets (issue 24): the
optics add <= 10 % to a frame with weather, tables build in <= 30 s on llvmpipe.
"""

from __future__ import annotations

import argparse
import statistics
import time

from skydome import Sky
from skydome.clouds import halos
from skydome.clouds.params import Clouds
from skydome.core.basis import SpectralBasis
from skydome.gpu import gl_info, shared_context
from skydome.spectra import ACCURATE_NM


def table_s(elevation_deg: float) -> float:
    """Seconds to trace the default mixture's table for a light at ``elevation_deg``."""
    basis = SpectralBasis.for_wavelengths(ACCURATE_NM)
    start = time.perf_counter()
    halos.halo_table(halos.DEFAULT_HALOS, elevation_deg, basis.wavelengths_nm, basis.to_output)
    return time.perf_counter() - start


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--size", default="1280x720")
    args = ap.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    print(gl_info(shared_context()))
    print(f"halo table, first in the process (random crystals' phase function too): "
          f"{table_s(20.0):.1f} s")  # fmt: skip
    print(f"halo table, a new light elevation: {table_s(21.0):.1f} s")
    skies = {
        name: Sky(sun_elevation_deg=20.0, clouds=Clouds("cirrus", cirrus=0.9, halos=spec))
        for name, spec in (("without halos", "none"), ("with halos", halos.DEFAULT_HALOS))
    }
    times: dict[str, list[float]] = {name: [] for name in skies}
    try:
        cameras = {name: sky.camera("sun", fov_deg=110) for name, sky in skies.items()}
        for name, sky in skies.items():  # warm-up: programs, tables, the halo table
            sky.render(cameras[name], *size)
        for _ in range(args.repeats):
            for name, sky in skies.items():
                start = time.perf_counter()
                sky.render(cameras[name], *size)
                times[name].append(1e3 * (time.perf_counter() - start))
    finally:
        for sky in skies.values():
            sky.release()
    base = statistics.median(times["without halos"])
    for name, values in times.items():
        ms = statistics.median(values)
        print(f"cirrus frame {name}: {ms:.0f} ms ({100.0 * (ms / base - 1.0):+.1f} %)")


if __name__ == "__main__":
    main()
