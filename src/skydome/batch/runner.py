"""Running jobs in one process: a sky per job (as ``Sky(...)`` makes it), its files written
atomically with their checksums, and the physical quantities of the manifest.

A :class:`JobRunner` belongs to one process and renders on one thread: the headless GL
context of that thread (``skydome.gpu.shared_context``), made on its first job. It keeps the
last sky of each kind of air and clouds alive (at most :data:`HELD_SKIES`), so that the
atmosphere's tables and the cloud noise, which skies share while one holds them, are loaded
once per process and not once per job; every other sky is released when its job is done.
"""

from __future__ import annotations

import hashlib
import json
import os
import socket
import time
from collections import OrderedDict
from datetime import datetime
from pathlib import Path

import numpy as np

from skydome.astro.places import time_zone
from skydome.batch.jobs import Job
from skydome.io.atomic import atomic_write
from skydome.io.outputs import WRITERS
from skydome.sky import Sky
from skydome.weather_illuminance import ground_illuminance

__all__ = ["HELD_SKIES", "JobRunner", "file_sha256", "ground_illuminance", "run_job"]

#: Skies a runner keeps alive for their tables (one per kind of air, weather and clouds).
HELD_SKIES = 4
#: frame.info keys left out of the files' metadata: timings differ run to run, and the files
#: of the same job are the same bytes in every run.
_VOLATILE = ("render_ms",)


def file_sha256(path: str | os.PathLike) -> str:
    """The SHA-256 of a file's bytes (hex)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _write_file(path: Path, fmt: str, data: np.ndarray, metadata: dict) -> str:
    """Write one file atomically (a temporary file beside it, then a rename: a reader, or a
    killed writer, never leaves a partial file under its name); return its SHA-256."""
    digest = {}

    def write(tmp: Path) -> None:
        WRITERS["." + fmt].write(tmp, data, metadata)
        digest["sha256"] = file_sha256(tmp)

    atomic_write(path, write)
    return digest["sha256"]


def _one_line(text: object) -> str:
    return " ".join(str(text).split())


class JobRunner:
    """Renders jobs in this process, on the thread that calls :meth:`run` (always the same
    one: the GL context is that thread's). :meth:`close` releases the skies it holds."""

    def __init__(self, held: int = HELD_SKIES):
        self._held: OrderedDict[tuple, Sky] = OrderedDict()
        self._max_held = held
        self.worker = f"{socket.gethostname()}:{os.getpid()}"

    def close(self) -> None:
        """Release every sky held (their GPU memory, the tables when no other sky holds
        them)."""
        while self._held:
            _, sky = self._held.popitem()
            sky.release()

    def _hold(self, job: Job, sky: Sky) -> None:
        key = (job.abstract, job.atmosphere, job.weather, job.clouds, job.night)
        old = self._held.pop(key, None)
        self._held[key] = sky
        if old is not None:
            old.release()
        while len(self._held) > self._max_held:
            _, sky = self._held.popitem(last=False)
            sky.release()

    def run(self, job: Job, out_dir: str | os.PathLike) -> dict:
        """Render ``job`` into ``out_dir`` and return its manifest row (a dict; see
        :mod:`skydome.batch.manifest`): ``status`` "ok", or "failed" with the ``error``
        text (a failure does not raise: one bad job does not stop a batch)."""
        t0 = time.perf_counter()
        row: dict = {"job": job.name, "worker": self.worker}
        sky = None
        try:
            sky = Sky(job.description())
            t1 = time.perf_counter()
            frame = None
            if job.formats:
                png = "png" in job.formats
                frame = sky.render(
                    job.make_camera(sky.state), job.width, job.height,
                    exposure=job.exposure, tonemap=job.tonemap if png else None,
                )  # fmt: skip
            t2 = time.perf_counter()
            light = sky.lighting(job.lighting_size, job.lights)
            row.update(ground_illuminance(sky))
            t3 = time.perf_counter()
            row.update(_state_columns(sky, job))
            row.update(_light_columns(light))
            if frame is not None:
                row["exposure_ev100"] = float(frame.info["exposure_ev100"])
                meta = {k: v for k, v in frame.info.items() if k not in _VOLATILE}
                meta["job"] = job.parameters()
                out = Path(out_dir)
                size = 0
                for fmt, name in job.files().items():
                    data = frame.data if WRITERS["." + fmt].hdr else frame.image
                    row[f"sha256_{fmt}"] = _write_file(out / name, fmt, data, meta)
                    row[f"file_{fmt}"] = name
                    size += (out / name).stat().st_size
                row["bytes"] = size
            t4 = time.perf_counter()
            row.update(status="ok", error="", setup_s=t1 - t0, render_s=t2 - t1,
                       lighting_s=t3 - t2, write_s=t4 - t3)  # fmt: skip
            self._hold(job, sky)
            sky = None
        except Exception as exc:  # the job fails, the batch goes on; the row says why
            row.update(status="failed", error=f"{type(exc).__name__}: {_one_line(exc)}")
        finally:
            if sky is not None:
                sky.release()
        row["job_s"] = time.perf_counter() - t0
        return row


def _state_columns(sky: Sky, job: Job) -> dict:
    s = sky.state
    out = {
        "sun_altitude_deg": float(s.sun.elevation_deg),
        "sun_azimuth_deg": float(s.sun.azimuth_deg),
    }
    if s.moon is not None:
        out["moon_altitude_deg"] = float(s.moon.elevation_deg)
        out["moon_azimuth_deg"] = float(s.moon.azimuth_deg)
    if s.moon_view is not None:
        out["moon_illuminated_fraction"] = float(s.moon_view.illuminated_fraction)
    if s.time is not None and job.timezone:
        utc = datetime.fromisoformat(job.time_utc.replace("Z", "+00:00"))
        out["time_local"] = utc.astimezone(time_zone(job.timezone)).isoformat()
    return out


def _light_columns(light) -> dict:
    out = {}
    sh = np.asarray(light.sh, dtype=np.float64)
    for i in range(9):
        for c, ch in enumerate("rgb"):
            out[f"sh_{i}_{ch}"] = float(sh[i, c])
    out["sun_normal_lux"] = None if light.sun is None else light.sun.illuminance_lux
    out["moon_normal_lux"] = None if light.moon is None else light.moon.illuminance_lux
    out["lights"] = json.dumps([li.as_dict() for li in light.lights])
    return out


def run_job(job: Job, out_dir: str | os.PathLike, runner: JobRunner | None = None) -> dict:
    """Run one job in this process (a runner of its own unless given) and return its row."""
    own = runner is None
    runner = runner or JobRunner()
    try:
        return runner.run(job, out_dir)
    finally:
        if own:
            runner.close()
