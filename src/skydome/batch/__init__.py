"""Skies by the thousand: a spec (TOML or YAML: places x times x weathers x cameras) expanded
into jobs with deterministic names, rendered in this process or on Dask, resumable, with a
manifest in Parquet and CSV (parameters, illuminance, the Sun's place, the sky's spherical
harmonics, timings, failures).

>>> from skydome.batch import load_spec, expand_jobs, render_many   # doctest: +SKIP
>>> jobs = expand_jobs(load_spec("spec.toml"))
>>> result = render_many(jobs, "out/", workers=2)
"""

from skydome.batch.engine import BatchResult, SkyWorkerPlugin, local_cluster, render_many
from skydome.batch.jobs import Job, expand_jobs
from skydome.batch.manifest import COLUMNS, Manifest, complete
from skydome.batch.runner import JobRunner, ground_illuminance, run_job
from skydome.batch.spec import FORMATS, BatchSpec, load_spec, parse_spec

__all__ = [
    "COLUMNS",
    "FORMATS",
    "BatchResult",
    "BatchSpec",
    "Job",
    "JobRunner",
    "Manifest",
    "SkyWorkerPlugin",
    "complete",
    "expand_jobs",
    "ground_illuminance",
    "load_spec",
    "local_cluster",
    "parse_spec",
    "render_many",
    "run_job",
]
