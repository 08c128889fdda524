"""skydome batch's costs: N equirect 512 x 256 HDRIs (EXR, with the manifest's light: the
illuminance, the 9 spherical harmonics and the lights) in one process and on Dask.

Usage: python benchmarks/bench_batch.py [--n 1000] [--workers 1 2] [--size 512x256]

Prints, for N skies of a Sun alone at N elevations from -6 to 84 deg:
- ``loop``: the work alone, a plain loop in this process (``JobRunner.run``: a Sky, its frame,
  its light, the EXR written atomically), jobs per second;
- ``serial``: ``render_many(serial=True)``, the same with the manifest, the resume check and
  the progress: its overhead per job over the loop;
- ``dask N``: ``render_many`` on a local cluster of N worker processes (started before the
  clock; the start is printed apart): jobs per second, per worker against the loop (goal:
  within 20 %), overhead per job (goal <= 50 ms, from the 1-worker run), the workers'
  resident memory after their first 10 % of jobs and at the end (goal: flat), and the
  scaling from 1 to N workers.
The tables are computed (or loaded) once before the clock, in this process's cache.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
import psutil

from skydome import EquirectCamera, Sky
from skydome.batch import JobRunner, expand_jobs, local_cluster, parse_spec, render_many
from skydome.gpu import gl_info


def _rss_mib() -> float:
    return psutil.Process(os.getpid()).memory_info().rss / 2**20


def _in_job(rows, wall_s: float, workers: int = 1) -> str:
    """The median time in the job itself (ms: the sky, the frame, the light, the file), and
    the time each worker spent outside the jobs, per job (ms: scheduling, transfers, the
    manifest): from one run, so the machine's other load cancels."""
    inside = sum(r["job_s"] for r in rows)
    outside = (wall_s * workers - inside) / len(rows)
    median = statistics.median(r["job_s"] for r in rows)
    return f"in the job: median {1e3 * median:.0f} ms, outside the jobs {1e3 * outside:+.1f} ms/job"


def jobs_of(n: int, size: str):
    elevations = [round(float(e), 4) for e in np.linspace(-6.0, 84.0, n)]
    spec = parse_spec({
        "sky": {"sun_elevation": elevations, "sun_azimuth": [135.0]},
        "output": {"camera": "equirect", "size": size, "formats": ["exr"]},
    })  # fmt: skip
    return expand_jobs(spec)


def run_dask(jobs, workers: int, out: Path) -> dict:
    from distributed import Client

    t0 = time.perf_counter()
    cluster = local_cluster(workers)
    client = Client(cluster)
    client.wait_for_workers(workers)
    start_s = time.perf_counter() - t0
    rss: dict[str, list[float]] = {"early": [], "end": []}
    seen = [0]
    early_at = max(len(jobs) // 10, 2 * workers)

    def on_row(row):
        seen[0] += 1
        if seen[0] == early_at:
            rss["early"] = sorted(client.run(_rss_mib).values())

    try:
        t0 = time.perf_counter()
        result = render_many(
            jobs, out, scheduler=cluster.scheduler_address, progress=False, on_row=on_row
        )
        wall = time.perf_counter() - t0
        rss["end"] = sorted(client.run(_rss_mib).values())
    finally:
        client.close()
        cluster.close()
    assert not result.failed, result.failed[:1]
    first = sorted(r["job_s"] for r in result.rows)[-workers:]
    return {"wall": wall, "start": start_s, "rss": rss, "slowest": first, "rows": result.rows}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--size", default="512x256")
    args = ap.parse_args()
    jobs = jobs_of(args.n, args.size)
    n = len(jobs)
    with Sky(sun_elevation_deg=30.0) as sky:  # the tables into the cache, before the clock
        sky.render(EquirectCamera(), 64, 32)
        print(f"# device: {gl_info(sky.graph.ctx).describe()}; {os.cpu_count()} CPUs")
    print(f"# {n} equirect {args.size} HDRIs (EXR + the manifest's light)")
    tmp = Path(tempfile.mkdtemp(prefix="bench-batch-"))

    runner = JobRunner()
    (tmp / "loop").mkdir()
    runner.run(jobs[0], tmp / "loop")  # warm-up: the first sky's shaders
    rss0 = _rss_mib()
    t0 = time.perf_counter()
    rows = [runner.run(job, tmp / "loop") for job in jobs]
    loop = time.perf_counter() - t0
    rss1 = _rss_mib()
    runner.close()
    print(
        f"loop    {n / loop:7.2f} jobs/s  {1e3 * loop / n:7.1f} ms/job  "
        f"RSS {rss0:.0f} -> {rss1:.0f} MiB  {_in_job(rows, loop)}"
    )

    t0 = time.perf_counter()
    result = render_many(jobs, tmp / "serial", serial=True, progress=False)
    serial = time.perf_counter() - t0
    assert result.rendered == n and not result.failed
    print(
        f"serial  {n / serial:7.2f} jobs/s  {1e3 * serial / n:7.1f} ms/job  "
        f"overhead {1e3 * (serial - loop) / n:+.1f} ms/job over the loop  {_in_job(result.rows, serial)}"
    )

    rates = {}
    for w in args.workers:
        r = run_dask(jobs, w, tmp / f"dask{w}")
        rate = n / r["wall"]
        rates[w] = rate
        per_worker = rate / w
        rss = r["rss"]
        print(
            f"dask {w}  {rate:7.2f} jobs/s  {per_worker:7.2f} per worker "
            f"({100 * (per_worker * loop / n - 1):+.0f} % vs the loop)  "
            f"overhead {1e3 * (r['wall'] * w - loop) / n:+.1f} ms/job  "
            f"cluster start {r['start']:.1f} s  slowest jobs {', '.join(f'{s:.2f}' for s in r['slowest'])} s  "
            f"worker RSS {', '.join(f'{v:.0f}' for v in rss['early'])} -> "
            f"{', '.join(f'{v:.0f}' for v in rss['end'])} MiB  {_in_job(r['rows'], r['wall'], w)}"
        )
    if len(rates) > 1:
        ws = sorted(rates)
        print(
            "scaling "
            + ", ".join(f"{w} workers x{rates[w] / rates[ws[0]]:.2f}" for w in ws)
            + f" (from {ws[0]})"
        )


if __name__ == "__main__":
    main()
