"""``render_many``: run jobs in this process or on Dask, skip the complete ones, collect the
rows into the manifest, show the progress.

On Dask (``pip install "skydome[batch]"``), each worker process renders with its own GL
context and tables, made in that process on its first job by :class:`SkyWorkerPlugin` (a
``distributed.WorkerPlugin``): one thread of the plugin's does every GL call, and no context
exists before a worker process starts (the local cluster's processes are spawned, never
forked). The plugin also sets glibc's allocator for frames
(:mod:`skydome.batch.worker_memory`: a nanny's worker would map every array from the kernel).
A job whose worker dies is run again on another (Dask's rescheduling, then ``retries``); its
files are written atomically by whoever runs it (a temporary file, then a rename), and only
this process, which collects the results, writes the manifest: a row per job, whatever ran
twice.
"""

from __future__ import annotations

import contextlib
import logging
import os
import time
from collections.abc import Callable, Iterable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

from rich.console import Console
from rich.progress import TextColumn

from skydome.batch.jobs import Job
from skydome.batch.manifest import Manifest, complete, job_row
from skydome.batch.runner import JobRunner
from skydome.batch.worker_memory import fit_allocator_to_frames
from skydome.errors import ParameterError
from skydome.io.atomic import remove_stale_temps
from skydome.io.progress import eta_progress

try:  # optional: pip install "skydome[batch]"
    import dask
    from distributed import Client, LocalCluster, WorkerPlugin, as_completed, get_worker
except ImportError:  # serial runs need none of it
    dask = Client = LocalCluster = as_completed = get_worker = None
    WorkerPlugin = object

__all__ = ["PLUGIN_NAME", "BatchResult", "SkyWorkerPlugin", "render_many", "run_on_worker"]

#: The name the worker plugin is registered under.
PLUGIN_NAME = "skydome-batch"
#: Seconds between two writes of the manifest while a batch runs (a stopped batch keeps
#: what was done: the next run skips it).
MANIFEST_EVERY_S = 10.0


@dataclass
class BatchResult:
    """What a batch did: ``rendered`` (jobs run now), ``skipped`` (complete before),
    ``failed`` (rows of jobs that failed now), the ``manifest`` files and ``wall_s``."""

    rendered: int = 0
    skipped: int = 0
    failed: list[dict] = field(default_factory=list)
    manifest: list[Path] = field(default_factory=list)
    rows: list[dict] = field(default_factory=list)
    wall_s: float = 0.0


class SkyWorkerPlugin(WorkerPlugin):
    """A Dask worker plugin: the worker process's :class:`JobRunner` and the one thread that
    draws with its GL context, both made in the worker (on its first job), released when the
    worker closes."""

    name = PLUGIN_NAME
    idempotent = True

    def __init__(self):
        self._runner = None
        self._thread = None

    def __getstate__(self):
        return {}

    def __setstate__(self, state):
        self.__init__()

    def setup(self, worker=None) -> None:
        # A nanny's worker allocates every frame's arrays from the kernel unless told not to.
        fit_allocator_to_frames()
        self._thread = ThreadPoolExecutor(1, thread_name_prefix="skydome-gl")

    def teardown(self, worker=None) -> None:
        if self._thread is None:
            return
        if self._runner is not None:
            self._thread.submit(self._runner.close).result()
        self._thread.shutdown(wait=True)
        self._thread = self._runner = None

    def run(self, job: Job, out_dir: str) -> dict:
        """Run ``job`` on the plugin's GL thread; its row."""
        if self._thread is None:
            self.setup()
        return self._thread.submit(self._run, job, out_dir).result()

    def _run(self, job: Job, out_dir: str) -> dict:
        if self._runner is None:
            self._runner = JobRunner()
        return self._runner.run(job, out_dir)


def run_on_worker(job: Job, out_dir: str) -> dict:
    """The Dask task: ``job`` run by this worker's plugin."""
    return get_worker().plugins[PLUGIN_NAME].run(job, out_dir)


def _failed_row(job: Job, exc: BaseException) -> dict:
    text = " ".join(str(exc).split()) or type(exc).__name__
    return {"job": job.name, "status": "failed", "error": f"{type(exc).__name__}: {text}"}


def _progress_bar(enabled: bool):
    console = Console(stderr=True)
    failed = TextColumn("{task.fields[failed]} failed")
    return eta_progress(console, "{task.description}", failed, enabled=enabled)


def render_many(
    jobs: Iterable[Job],
    out_dir: str | os.PathLike,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    serial: bool = False,
    resources: dict[str, float] | None = None,
    retries: int = 2,
    progress: bool = True,
    on_row: Callable[[dict], None] | None = None,
) -> BatchResult:
    """Render ``jobs`` (:func:`skydome.batch.expand_jobs`) into ``out_dir`` and keep its
    manifest (:mod:`skydome.batch.manifest`).

    Jobs complete in the folder (their row "ok", their files there with the checksums it
    recorded) are skipped; the others run: in this process when ``serial`` (or ``workers``
    is 0), else on Dask: the cluster at ``scheduler`` ("tcp://host:8786"), or a local
    cluster of ``workers`` processes (default: the CPU count), one thread each.
    ``resources`` (e.g. ``{"GPU": 1}``): what each job needs of a worker (a local cluster's
    workers get as much each). ``retries``: reruns of a job whose task raised (a worker that
    died is rescheduled by Dask itself). ``progress``: a bar with an ETA on stderr (on a
    terminal). ``on_row(row)`` is called with each job's row as it arrives.
    """
    t0 = time.perf_counter()
    jobs = list(jobs)
    names = [j.name for j in jobs]
    if len(set(names)) != len(names):
        raise ParameterError("render_many: the same job is given twice")
    if workers is not None and (isinstance(workers, bool) or not 0 <= int(workers) <= 4096):
        raise ParameterError(f"workers {workers!r} must be an integer from 0 to 4096")
    serial = serial or workers == 0
    if serial and scheduler is not None:
        raise ParameterError("serial runs in this process: no scheduler with it")
    out = Path(out_dir)
    remove_stale_temps(out)
    manifest = Manifest.load(out)
    todo = [j for j in jobs if not complete(j, manifest.rows.get(j.name), out)]
    result = BatchResult(skipped=len(jobs) - len(todo))
    last_write = time.monotonic()

    def collect(job: Job, row: dict) -> None:
        nonlocal last_write
        row = {**job_row(job), **row}
        manifest.add(row)
        result.rendered += 1
        if row.get("status") != "ok":
            result.failed.append(row)
        if on_row is not None:
            on_row(row)
        if time.monotonic() - last_write > MANIFEST_EVERY_S:
            manifest.write()
            last_write = time.monotonic()

    # Dask first: a scheduler that cannot be reached leaves no folder behind
    with contextlib.ExitStack() as stack:
        client = None
        if todo and not serial:
            client = stack.enter_context(_dask_client(workers, scheduler, resources))
        out.mkdir(parents=True, exist_ok=True)
        bar = stack.enter_context(_progress_bar(progress))
        task = bar.add_task("rendering", total=len(todo), failed=0)

        def advance(job: Job, row: dict) -> None:
            collect(job, row)
            bar.update(task, advance=1, failed=len(result.failed))

        try:
            if client is not None:
                _run_dask(client, todo, out, resources, retries, advance)
            elif todo:
                runner = JobRunner()
                try:
                    for job in todo:
                        advance(job, runner.run(job, out))
                finally:
                    runner.close()
        finally:
            if todo or not (out / "manifest.csv").exists():
                result.manifest = manifest.write()
            remove_stale_temps(out)
    result.rows = [manifest.rows[n] for n in names if n in manifest.rows]
    result.wall_s = time.perf_counter() - t0
    return result


def local_cluster(workers: int | None, resources: dict[str, float] | None = None):
    """A Dask ``LocalCluster`` of ``workers`` processes (default: the CPU count), one thread
    each, spawned (never forked: no GL context crosses into a worker), no dashboard."""
    _need_dask()
    n = (os.cpu_count() or 1) if workers is None else int(workers)
    with dask.config.set({"distributed.worker.multiprocessing-method": "spawn"}):
        return LocalCluster(
            n_workers=n, threads_per_worker=1, processes=True, resources=resources,
            dashboard_address=None, silence_logs=logging.ERROR,
        )  # fmt: skip


def _need_dask() -> None:
    if Client is None:
        raise ParameterError(
            'batch on Dask needs dask and distributed: pip install "skydome[batch]" (or run '
            "it in this process: --serial)"
        )


@contextlib.contextmanager
def _dask_client(workers, scheduler, resources):
    """A Dask client: of the cluster at ``scheduler``, or of a local cluster made for it
    (closed with it); the worker plugin registered."""
    _need_dask()
    cluster = None
    if scheduler is None:
        cluster = local_cluster(workers, resources)
        client = Client(cluster)
    else:
        try:
            client = Client(scheduler, timeout=30)
        except OSError as exc:
            text = " ".join(str(exc).split())
            raise ParameterError(f"--scheduler {scheduler}: cannot connect ({text})") from None
    try:
        client.register_plugin(SkyWorkerPlugin(), name=PLUGIN_NAME)
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _run_dask(client, todo, out, resources, retries, advance) -> None:
    """Run ``todo`` on the client's workers; ``advance(job, row)`` as each result comes."""
    by_key = {f"skydome-batch-{j.name}": j for j in todo}
    futures = client.map(
        run_on_worker, todo, out_dir=str(out), key=list(by_key), retries=retries,
        resources=resources, pure=False,
    )  # fmt: skip
    for future in as_completed(futures):
        job = by_key[future.key]
        try:
            row = future.result()
        except Exception as exc:  # KilledWorker after too many deaths, a lost scheduler
            row = _failed_row(job, exc)
        advance(job, row)
        future.release()
