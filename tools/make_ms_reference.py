"""Generate ``tests/data/ms_reference_earth.npz``: float64 Monte Carlo sky radiance, all orders.

The reference against which the GLSL multiple-scattering tables (Bruneton 2017) are tested.
Computed with :mod:`skydome.reference.ms` for the ``earth_bruneton`` preset (the
seeds' Earth; the files were made when it was named ``earth``) at 440, 550 and 680 nm, a
camera at 0 m and 10 000 m, the Sun at elevations -6°, 0°, 5°, 20° and 60° (due east,
azimuth 90°), on a fixed set of 61 view directions (:func:`view_directions`):

* 48 directions of a Fibonacci set over the upper hemisphere: elevation asin((i + 1/2)/48),
  azimuth i·137.5078° (the golden angle) measured from north towards east, i = 0..47;
* the zenith;
* elevations 2° and 10° towards the Sun (azimuth 90°) and away from it (azimuth 270°);
* below the horizon, elevations -1°, -4°, -10° and -30° at azimuths 90° and 270° (for the
  10 km camera, whose horizon is 3.2° below the horizontal; -1° looks at the sky above the
  limb, the others at the ground). They are not computed for the camera at 0 m (``view_valid``
  is False there and the values are 0: the ground surface itself is excluded by convention).

Quantities are per unit solar irradiance (sr^-1; multiply by ``solar_irradiance`` for
W m^-2 sr^-1 nm^-1), the direct Sun and the ground surface excluded (module docstring of
``reference.ms``). Arrays in the file (A = altitudes, S = Sun elevations, V = views,
W = wavelengths, B = order bins):

* ``radiance``, ``stderr`` (A, S, V, W): every order, and its standard error;
* ``radiance_orders``, ``stderr_orders`` (A, S, V, W, B): cumulative over orders, bin k holds
  orders 1..k+1 (``order_bins`` gives the highest order of each bin, -1 = all);
* ``single`` (A, S, V, W): single scattering by deterministic quadrature;
  ``single_mc``/``single_mc_stderr``: the Monte Carlo order 1 of the same paths;
* ``view_dirs`` (V, 3) ENU unit vectors, ``view_elevation_deg``, ``view_azimuth_deg``,
  ``view_valid`` (A, V); ``wavelengths_nm``, ``camera_altitude_m``, ``sun_elevation_deg``,
  ``sun_zenith_rad``, ``solar_irradiance`` (W m^-2 nm^-1), ``n_paths`` (A, S) per view;
* ``digest`` (``preset("earth_bruneton").digest()``), ``preset`` and ``settings`` (JSON: seeds,
  path counts, the tracer's quadrature and sampling constants, versions, run time).

Paths per view are set per configuration from pilot runs so that the relative standard error
is about 0.5% for most directions in daylight (measured: median 0.33-0.49%, 80th percentile
0.43-0.64% per configuration); twilight (-6°) is noisier per path and gets more paths but
stays at about 1% (median 0.9-1.0%, 80th percentile 1.4-1.7%, worst 6-12% in the faint
antisolar sky). Results are deterministic (seeded per task) whatever the number of workers.
57 M paths; 23 minutes with 2 workers on a shared 2-core machine (``--scale 0.01``: 15 s).

``--luminance`` writes ``tests/data/ms_reference_earth_luminance.npz`` instead, for the
default (luminance) tables and the frames: the same tracer at exactly the 16 ``accurate``
render wavelengths (380-755 nm), so that the tests convert both sides with the same spectral
-> XYZ matrix and compare the tables alone (their orders >= 2 are computed at 4 wavelengths
and interpolated), the same cameras and Sun elevations, on 21 of the 61 views
(:func:`luminance_view_directions`: every 6th Fibonacci direction, the zenith, the 4 low ones
and the 8 below the horizon; from 0 m the latter all see the ground at the camera, from 10 km
-1° sees the sky above the limb and the others the ground 17-150 km away). Arrays:

* ``radiance``, ``stderr`` (A, S, V, W): the air's light, as above (0 where ``view_traced`` is
  False: from 0 m below the horizon there is no air in front of the ground);
* ``ground_radiance``, ``ground_stderr`` (A, S, V, W): the lit Lambertian ground itself seen
  through the air (``reference.ms.ground_radiance_mc``, 0 for rays that miss it), so that
  radiance + ground_radiance is what a frame shows along any direction but the Sun's disk;
* ``view_dirs``, ``view_elevation_deg``, ``view_azimuth_deg``, ``view_traced`` and
  ``view_hits_ground`` (A, V), ``wavelengths_nm``, ``camera_altitude_m``,
  ``sun_elevation_deg``, ``sun_zenith_rad``, ``n_paths`` and ``n_paths_ground`` (A, S),
  ``digest``, ``preset``, ``settings``.

Paths per view: 8 192 in daylight, 32 768 at -6°; per ground irradiance 16 384 and 32 768
(far fewer than above: 16 wavelengths cost twice as much per path; the tests account for
the larger standard errors, ``stderr`` and ``ground_stderr``).

Usage::

    python tools/make_ms_reference.py [--workers 2] [--scale 1.0] [--out PATH] [--luminance]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

import numpy as np

from skydome.atmosphere import preset
from skydome.reference import ms as rms
from skydome.spectra import wavelengths

PRESET = "earth_bruneton"
WAVELENGTHS_NM = (440.0, 550.0, 680.0)
CAMERA_ALTITUDES_M = (0.0, 10_000.0)
SUN_ELEVATIONS_DEG = (-6.0, 0.0, 5.0, 20.0, 60.0)
#: Paths per view direction for each (camera altitude, Sun elevation), from pilot runs of the
#: per-path relative standard deviation (about 1 in daylight, 1.5 at 10 km with a high Sun
#: where ground-reflected light dominates, 3 to 6 at twilight).
PATHS_PER_VIEW = {
    (0.0, -6.0): 300_000,
    (0.0, 0.0): 72_000,
    (0.0, 5.0): 42_000,
    (0.0, 20.0): 36_000,
    (0.0, 60.0): 36_000,
    (10_000.0, -6.0): 300_000,
    (10_000.0, 0.0): 42_000,
    (10_000.0, 5.0): 42_000,
    (10_000.0, 20.0): 60_000,
    (10_000.0, 60.0): 72_000,
}
BASE_SEED = 20_251_123
VIEWS_PER_TASK = 8
N_FIBONACCI = 48
GOLDEN_ANGLE_DEG = 180.0 * (3.0 - math.sqrt(5.0))  # 137.5078°

DEFAULT_OUT = Path(__file__).resolve().parents[1] / "tests" / "data" / "ms_reference_earth.npz"


def _dir(elevation_deg: float, azimuth_deg: float) -> tuple[float, float, float]:
    el, az = math.radians(elevation_deg), math.radians(azimuth_deg)
    return (math.cos(el) * math.sin(az), math.cos(el) * math.cos(az), math.sin(el))


def view_directions() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The 61 view directions: (dirs (61, 3) ENU, elevation_deg, azimuth_deg)."""
    el, az = [], []
    for i in range(N_FIBONACCI):
        el.append(math.degrees(math.asin((i + 0.5) / N_FIBONACCI)))
        az.append((i * GOLDEN_ANGLE_DEG) % 360.0)
    el.append(90.0)
    az.append(0.0)
    for e in (2.0, 10.0):
        for a in (90.0, 270.0):
            el.append(e)
            az.append(a)
    for e in (-1.0, -4.0, -10.0, -30.0):
        for a in (90.0, 270.0):
            el.append(e)
            az.append(a)
    dirs = np.array([_dir(e, a) for e, a in zip(el, az, strict=True)])
    dirs[N_FIBONACCI] = (0.0, 0.0, 1.0)  # exact zenith
    return dirs, np.array(el), np.array(az)


def _task_seed(ia: int, isun: int, ichunk: int) -> int:
    return int(np.random.SeedSequence([BASE_SEED, ia, isun, ichunk]).generate_state(1)[0])


def _run_task(task):
    ia, isun, ichunk, views, n_paths = task
    params = preset(PRESET)
    dirs, _, _ = view_directions()
    alt = CAMERA_ALTITUDES_M[ia]
    sz = math.radians(90.0 - SUN_ELEVATIONS_DEG[isun])
    t0 = time.perf_counter()
    res = rms.sky_radiance_mc_orders(
        params, WAVELENGTHS_NM, alt, sz, dirs[views], n_paths=n_paths,
        seed=_task_seed(ia, isun, ichunk),
    )  # fmt: skip
    single = rms.single_scattering_quadrature(params, WAVELENGTHS_NM, alt, sz, dirs[views])
    return ia, isun, views, res.radiance, res.stderr, single, time.perf_counter() - t0


# ------------------------------------------------------------------------------------------
# --luminance: the 16 render wavelengths, the ground too
# ------------------------------------------------------------------------------------------

LUM_WAVELENGTHS = "accurate"
LUM_BASE_SEED = 20_260_214
LUM_TWILIGHT_DEG = 0.0  # Sun elevations below this get the twilight path counts
LUM_PATHS_DAY = 8_192
LUM_PATHS_TWILIGHT = 32_768
LUM_GROUND_PATHS_DAY = 16_384
LUM_GROUND_PATHS_TWILIGHT = 32_768
LUM_VIEWS_PER_TASK = 5

LUMINANCE_OUT = (
    Path(__file__).resolve().parents[1] / "tests" / "data" / "ms_reference_earth_luminance.npz"
)


def luminance_view_directions() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The 21 views: (indices into the spectral reference's 61, dirs (21, 3), elevation_deg,
    azimuth_deg)."""
    dirs, el, az = view_directions()
    idx = np.concatenate([np.arange(0, N_FIBONACCI, 6), np.arange(N_FIBONACCI, len(dirs))])
    return idx, dirs[idx], el[idx], az[idx]


def _lum_task_seed(kind: int, ia: int, isun: int, ichunk: int) -> int:
    seq = np.random.SeedSequence([LUM_BASE_SEED, kind, ia, isun, ichunk])
    return int(seq.generate_state(1)[0])


def _run_luminance_task(task):
    kind, ia, isun, ichunk, views, n_paths = task
    params = preset(PRESET)
    wl = wavelengths(LUM_WAVELENGTHS)
    _, dirs, _, _ = luminance_view_directions()
    alt = CAMERA_ALTITUDES_M[ia]
    sz = math.radians(90.0 - SUN_ELEVATIONS_DEG[isun])
    seed = _lum_task_seed(kind, ia, isun, ichunk)
    t0 = time.perf_counter()
    if kind == 0:
        res = rms.sky_radiance_mc_orders(
            params, wl, alt, sz, dirs[views], n_paths=n_paths, seed=seed
        )
        rad, err = res.total, res.total_stderr
    else:
        rad, err = rms.ground_radiance_mc(
            params, wl, alt, sz, dirs[views], n_paths=n_paths, seed=seed
        )
    return kind, ia, isun, views, rad, err, time.perf_counter() - t0


def main_luminance(args: argparse.Namespace) -> int:
    """Write the 16-wavelength reference (``--luminance``, see the module docstring)."""

    params = preset(PRESET)
    wl = wavelengths(LUM_WAVELENGTHS)
    idx, dirs, el, az = luminance_view_directions()
    nA, nS, nV, nW = len(CAMERA_ALTITUDES_M), len(SUN_ELEVATIONS_DEG), len(dirs), len(wl)
    traced = np.zeros((nA, nV), dtype=bool)
    ground = np.zeros((nA, nV), dtype=bool)
    for ia, alt in enumerate(CAMERA_ALTITUDES_M):
        r = params.bottom_radius_m + alt
        horizon = -math.sqrt(max(0.0, 1.0 - (params.bottom_radius_m / r) ** 2))
        ground[ia] = dirs[:, 2] < horizon if alt > 0.0 else dirs[:, 2] < 0.0
        traced[ia] = dirs[:, 2] > 0.0 if alt == 0.0 else True

    def paths(day: int, twilight: int, sel: float) -> int:
        return max(nW, int(round((day if sel >= LUM_TWILIGHT_DEG else twilight) * args.scale)))

    n_paths = np.zeros((nA, nS), dtype=np.int64)
    n_ground = np.zeros((nA, nS), dtype=np.int64)
    tasks = []
    for ia in range(nA):
        for isun, sel in enumerate(SUN_ELEVATIONS_DEG):
            n_paths[ia, isun] = paths(LUM_PATHS_DAY, LUM_PATHS_TWILIGHT, sel) // nW * nW
            n_ground[ia, isun] = paths(LUM_GROUND_PATHS_DAY, LUM_GROUND_PATHS_TWILIGHT, sel)
            for kind, sel_views, n in (
                (0, np.nonzero(traced[ia])[0], n_paths[ia, isun]),
                # from 0 m every ground view sees the same point: one estimate, copied
                (1, np.nonzero(ground[ia])[0][: 1 if CAMERA_ALTITUDES_M[ia] == 0.0 else None],
                 n_ground[ia, isun]),
            ):  # fmt: skip
                for ichunk, k in enumerate(range(0, sel_views.size, LUM_VIEWS_PER_TASK)):
                    tasks.append((kind, ia, isun, ichunk, sel_views[k : k + LUM_VIEWS_PER_TASK], n))
    tasks.sort(key=lambda t: -t[5] * len(t[4]))
    print(f"{len(tasks)} tasks, {args.workers} workers", flush=True)

    rad = np.zeros((nA, nS, nV, nW))
    err = np.zeros_like(rad)
    g_rad = np.zeros_like(rad)
    g_err = np.zeros_like(rad)
    t_start = time.perf_counter()
    with ProcessPoolExecutor(max_workers=args.workers) as ex:
        futures = [ex.submit(_run_luminance_task, t) for t in tasks]
        for k, fut in enumerate(as_completed(futures), 1):
            kind, ia, isun, views, r, e, dt = fut.result()
            (rad if kind == 0 else g_rad)[ia, isun, views] = r
            (err if kind == 0 else g_err)[ia, isun, views] = e
            print(
                f"[{k:3d}/{len(tasks)}] {'air' if kind == 0 else 'ground'} alt "
                f"{CAMERA_ALTITUDES_M[ia]:7.0f} m, Sun {SUN_ELEVATIONS_DEG[isun]:+5.1f}°, "
                f"{len(views)} views: {dt:6.1f} s; elapsed {time.perf_counter() - t_start:6.0f} s",
                flush=True,
            )
    for ia, alt in enumerate(CAMERA_ALTITUDES_M):
        if alt == 0.0:
            first = np.nonzero(ground[ia])[0][0]
            g_rad[ia][:, ground[ia]] = g_rad[ia][:, first : first + 1]
            g_err[ia][:, ground[ia]] = g_err[ia][:, first : first + 1]
    runtime = time.perf_counter() - t_start

    settings = {
        "preset": PRESET,
        "tool": "tools/make_ms_reference.py --luminance",
        "base_seed": LUM_BASE_SEED,
        "seed_rule": "SeedSequence([base_seed, kind (0 air, 1 ground), altitude index, "
        "sun index, chunk index]); ground: per view SeedSequence([task seed, view])",
        "views": "indices into tools/make_ms_reference.py view_directions(): "
        + ",".join(str(int(i)) for i in idx),
        "scale": args.scale,
        "views_per_task": LUM_VIEWS_PER_TASK,
        "numpy": np.__version__,
        "python": sys.version.split()[0],
        "runtime_s": round(runtime, 1),
        "workers": args.workers,
        "conventions": "per unit solar irradiance; radiance: the air's light, the direct Sun "
        "and the ground excluded; ground_radiance: the ground seen through the air",
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.out.with_suffix(".tmp.npz")
    np.savez_compressed(
        tmp,
        radiance=rad,
        stderr=err,
        ground_radiance=g_rad,
        ground_stderr=g_err,
        view_dirs=dirs,
        view_elevation_deg=el,
        view_azimuth_deg=az,
        view_traced=traced,
        view_hits_ground=ground,
        wavelengths_nm=wl,
        camera_altitude_m=np.array(CAMERA_ALTITUDES_M),
        sun_elevation_deg=np.array(SUN_ELEVATIONS_DEG),
        sun_zenith_rad=np.radians(90.0 - np.array(SUN_ELEVATIONS_DEG)),
        n_paths=n_paths,
        n_paths_ground=n_ground,
        digest=np.array(params.digest()),
        preset=np.array(PRESET),
        settings=np.array(json.dumps(settings, sort_keys=True)),
    )
    os.replace(tmp, args.out)
    print(f"wrote {args.out} ({args.out.stat().st_size / 1024:.0f} kB) in {runtime:.0f} s")
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=min(2, os.cpu_count() or 1))
    ap.add_argument("--scale", type=float, default=1.0, help="multiply every path count")
    ap.add_argument(
        "--luminance",
        action="store_true",
        help=f"the 16-wavelength reference of the default tables ({LUMINANCE_OUT.name})",
    )
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args(argv)
    if args.luminance:
        args.out = args.out or LUMINANCE_OUT
        return main_luminance(args)
    args.out = args.out or DEFAULT_OUT

    params = preset(PRESET)
    dirs, el, az = view_directions()
    nA, nS, nV, nW = (
        len(CAMERA_ALTITUDES_M),
        len(SUN_ELEVATIONS_DEG),
        len(dirs),
        len(WAVELENGTHS_NM),
    )
    nB = rms.N_ORDER_BINS
    valid = np.ones((nA, nV), dtype=bool)
    for ia, alt in enumerate(CAMERA_ALTITUDES_M):
        if alt == 0.0:
            valid[ia] = dirs[:, 2] > 0.0
    n_paths = np.zeros((nA, nS), dtype=np.int64)
    tasks = []
    for ia, alt in enumerate(CAMERA_ALTITUDES_M):
        for isun, sel in enumerate(SUN_ELEVATIONS_DEG):
            n = max(nW, int(round(PATHS_PER_VIEW[(alt, sel)] * args.scale / nW)) * nW)
            n_paths[ia, isun] = n
            views = np.nonzero(valid[ia])[0]
            for ichunk, k in enumerate(range(0, views.size, VIEWS_PER_TASK)):
                tasks.append((ia, isun, ichunk, views[k : k + VIEWS_PER_TASK], n))
    # longest first for load balance (cost ~ paths x views)
    tasks.sort(key=lambda t: -t[4] * len(t[3]))
    total_paths = sum(t[4] * len(t[3]) for t in tasks)
    print(
        f"{len(tasks)} tasks, {total_paths / 1e6:.1f} M paths, {args.workers} workers", flush=True
    )

    rad = np.zeros((nA, nS, nV, nW, nB))
    err = np.zeros_like(rad)
    single = np.zeros((nA, nS, nV, nW))
    t_start = time.perf_counter()
    done_paths = 0
    with ProcessPoolExecutor(max_workers=args.workers) as ex:
        futures = [ex.submit(_run_task, t) for t in tasks]
        for k, fut in enumerate(as_completed(futures), 1):
            ia, isun, views, r, e, s1, dt = fut.result()
            rad[ia, isun, views] = r
            err[ia, isun, views] = e
            single[ia, isun, views] = s1
            done_paths += n_paths[ia, isun] * len(views)
            rel = e[..., -1] / np.where(r[..., -1] > 0, r[..., -1], np.inf)
            elapsed = time.perf_counter() - t_start
            eta = elapsed * (total_paths / done_paths - 1.0)
            print(
                f"[{k:3d}/{len(tasks)}] alt {CAMERA_ALTITUDES_M[ia]:7.0f} m, Sun "
                f"{SUN_ELEVATIONS_DEG[isun]:+5.1f}°, {len(views)} views x {n_paths[ia, isun]} "
                f"paths: {dt:6.1f} s, max rel. stderr {rel.max():.4f}; elapsed {elapsed:6.0f} s, "
                f"eta {eta:6.0f} s",
                flush=True,
            )
    runtime = time.perf_counter() - t_start

    settings = {
        "preset": PRESET,
        "tool": "tools/make_ms_reference.py",
        "base_seed": BASE_SEED,
        "views_per_task": VIEWS_PER_TASK,
        "seed_rule": "SeedSequence([base_seed, altitude index, sun index, chunk index])",
        "scale": args.scale,
        "paths_per_view": {
            f"{a:g} m, {s:+g} deg": int(n_paths[i, j])
            for i, a in enumerate(CAMERA_ALTITUDES_M)
            for j, s in enumerate(SUN_ELEVATIONS_DEG)
        },  # fmt: skip
        "tracer": {
            name: getattr(rms, name)
            for name in (
                "SEG_SUB",
                "SEG_GL",
                "PARTIAL_GL",
                "NEE_SUB",
                "NEE_GL",
                "CHUNK_PATHS",
                "N_ORDER_BINS",
                "NEE_GUIDE_FLOOR",
                "VERTEX_GUIDE_FLOOR",
                "SUN_TABLE_NU",
                "SUN_TABLE_NX",
                "GUIDE_ALPHA",
                "BAND_SUN_ELEVATION_MAX",
                "BAND_E_LO",
                "BAND_E_HI",
                "BAND_E_SCALE",
                "BAND_RHO",
            )
        },  # fmt: skip
        "quadrature": {"single_scattering_quadrature": "defaults (n_sub=96, n_gl=8)"},
        "conventions": "per unit solar irradiance; direct Sun and ground surface excluded; "
        "Sun at azimuth 90 deg (east); ENU view directions",
        "numpy": np.__version__,
        "python": sys.version.split()[0],
        "runtime_s": round(runtime, 1),
        "workers": args.workers,
    }
    order_bins = np.array(list(range(1, nB)) + [-1])
    args.out.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.out.with_suffix(".tmp.npz")
    np.savez_compressed(
        tmp,
        radiance=rad[..., -1],
        stderr=err[..., -1],
        radiance_orders=rad,
        stderr_orders=err,
        order_bins=order_bins,
        single=single,
        single_mc=rad[..., 0],
        single_mc_stderr=err[..., 0],
        view_dirs=dirs,
        view_elevation_deg=el,
        view_azimuth_deg=az,
        view_valid=valid,
        wavelengths_nm=np.array(WAVELENGTHS_NM),
        camera_altitude_m=np.array(CAMERA_ALTITUDES_M),
        sun_elevation_deg=np.array(SUN_ELEVATIONS_DEG),
        sun_zenith_rad=np.radians(90.0 - np.array(SUN_ELEVATIONS_DEG)),
        solar_irradiance=params.solar_irradiance.at(np.array(WAVELENGTHS_NM)),
        n_paths=n_paths,
        digest=np.array(params.digest()),
        preset=np.array(PRESET),
        settings=np.array(json.dumps(settings, sort_keys=True)),
    )
    os.replace(tmp, args.out)
    tot, se = rad[..., -1], err[..., -1]
    rel = se / np.where(tot > 0, tot, np.inf)
    print(f"wrote {args.out} ({args.out.stat().st_size / 1024:.0f} kB) in {runtime:.0f} s")
    for ia, alt in enumerate(CAMERA_ALTITUDES_M):
        for isun, sel in enumerate(SUN_ELEVATIONS_DEG):
            r = rel[ia, isun][valid[ia]]
            print(
                f"  {alt:7.0f} m, Sun {sel:+5.1f}°: rel. stderr median {np.median(r):.4f}, "
                f"80% {np.percentile(r, 80):.4f}, max {r.max():.4f}"
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
