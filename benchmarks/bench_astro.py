"""Sun + Moon apparent topocentric alt/az for 1e5 times: skydome vs skyfield (and astropy).

Two time sets: "dense" (one year at 5.3-minute steps: an animation or a sky survey) and
"random" (1e5 random instants over 1900-2050). The series are summed at Chebyshev nodes of
fixed segments of time and interpolated where that is cheaper, and a segment's
coefficients are kept for the process's later calls (``_series.SegmentMemo``), as
skyfield's precomputed DE421 ephemeris is read from its file: so every timed run draws
fresh times (new random instants; the dense year shifted by a random fraction of its step),
and the first call of each set, which computes its segments, is printed apart ("first").
Prints the median of several runs after that first call, and the ratio to skyfield.

Usage: python benchmarks/bench_astro.py [--n 100000] [--repeat 5] [--no-astropy]
(astropy takes about a minute per call; --no-astropy leaves it out.)
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
from timing import median_ms

warnings.filterwarnings("ignore")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--no-astropy", action="store_true", help="skip the (slow) astropy column")
    args = ap.parse_args()
    n = args.n

    from skydome.astro import Observer
    from skydome.astro.time import Time

    rng = np.random.default_rng(0)
    step = 365.0 / (n - 1)
    sets = {  # each call draws fresh times of its set
        "dense (1 year)": lambda: 2460310.5 + np.linspace(0.0, 365.0, n) + rng.random() * step,
        "random 1900-2050": lambda: 2415020.5 + rng.random(n) * 54786.0,
    }
    lat, lon = 48.85, 2.35
    obs = Observer(lat, lon, 35.0)

    try:
        from skyfield.api import Loader, wgs84
        from skyfield_data import get_skyfield_data_path

        load = Loader(get_skyfield_data_path())
        ts, eph = load.timescale(builtin=True), load("de421.bsp")
        site = eph["earth"] + wgs84.latlon(lat, lon, elevation_m=35.0)
    except ImportError:
        ts = None

    try:
        if args.no_astropy:
            raise ImportError("--no-astropy")
        import astropy.units as u
        from astropy.coordinates import AltAz, EarthLocation, get_body
        from astropy.time import Time as ATime
        from astropy.utils import iers

        iers.conf.auto_download = False
        iers.conf.auto_max_age = None
        loc = EarthLocation(lat=lat * u.deg, lon=lon * u.deg, height=35 * u.m)
    except ImportError:
        ATime = None

    print(f"{n} times, Sun + Moon apparent topocentric alt/az, median of {args.repeat}")
    print(
        f"{'set':18s} {'first':>8s} {'skydome':>9s} {'skyfield':>9s} {'ratio':>7s} {'astropy':>9s}"
    )
    Observer(0.0, 0.0).sky(Time.from_jd(2451545.0), bodies=("sun", "moon"))  # imports, tables
    for label, draw in sets.items():
        # time-scale conversion excluded for every library; fresh times each call
        times = [Time.from_jd(draw()) for _ in range(args.repeat + 1)]
        t0 = time.perf_counter()
        obs.sky(times[0], bodies=("sun", "moon"))
        t_first = time.perf_counter() - t0
        runs = iter(times[1:])

        def ours(runs=runs):
            s = obs.sky(next(runs), bodies=("sun", "moon"))
            return s["sun"].alt, s["moon"].alt

        t_ours = median_ms(ours, args.repeat, warmup=0) / 1e3
        jd = times[-1].jd_tt
        t_sf = float("nan")
        if ts is not None:
            tsf = ts.tt_jd(jd)

            def sf(tsf=tsf):
                a = site.at(tsf)
                return (
                    a.observe(eph["sun"]).apparent().altaz(),
                    a.observe(eph["moon"]).apparent().altaz(),
                )

            t_sf = median_ms(sf, max(1, args.repeat // 2), warmup=1) / 1e3
        t_ap = float("nan")
        if ATime is not None:
            at = ATime(jd, format="jd", scale="tt")
            frame = AltAz(obstime=at, location=loc)

            def ap(at=at, frame=frame):
                return (
                    get_body("sun", at, loc).transform_to(frame).alt,
                    get_body("moon", at, loc).transform_to(frame).alt,
                )

            try:
                t_ap = median_ms(ap, 1, warmup=1) / 1e3
            except Exception as exc:  # astropy may lack IERS data offline
                print(f"astropy failed: {exc}")
        print(
            f"{label:18s} {t_first:7.3f}s {t_ours:8.3f}s {t_sf:8.3f}s {t_sf / t_ours:6.1f}x"
            f" {t_ap:8.3f}s"
        )


if __name__ == "__main__":
    main()
