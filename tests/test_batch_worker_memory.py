"""A Dask nanny's worker (MALLOC_TRIM_THRESHOLD_ set) allocates frames as a plain process
does once the worker plugin has set glibc's thresholds: counted as page faults, not timed."""

from __future__ import annotations

import os
import platform
import subprocess
import sys

import pytest

# In a child process started as Dask's nanny starts a worker: make and free a 3 MiB array
# (a 512 x 256 RGB float64 frame) 40 times and count the minor page faults, before and
# after fit_allocator_to_frames().
_CHILD = """
import resource, numpy as np
from skydome.batch.worker_memory import fit_allocator_to_frames
def faults_per_frame():
    np.ones((256, 512, 3)).sum()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for _ in range(40):
        np.ones((256, 512, 3)).sum()
    return (resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before) / 40

print(faults_per_frame(), fit_allocator_to_frames(), faults_per_frame())
"""


@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="glibc's mallopt")
def test_a_nanny_worker_stops_faulting_in_every_frame():
    env = dict(os.environ, MALLOC_TRIM_THRESHOLD_="65536")
    out = subprocess.run(
        [sys.executable, "-c", _CHILD], env=env, capture_output=True, text=True, check=True
    ).stdout.split()
    before, fitted, after = float(out[0]), out[1], float(out[2])
    # 3 MiB is 768 pages of 4 KiB: with the mmap threshold stuck at 128 KiB each frame maps
    # fresh pages and faults in every one of them (>= 700 a frame); from a reused heap,
    # almost none (< 50: a little slack for the interpreter's own allocations).
    assert fitted == "True"
    assert before >= 700
    assert after < 50


def test_a_plain_process_is_left_alone():
    # Without the nanny's variable glibc's dynamic thresholds are on: nothing to set. (In a
    # child: a local cluster's nanny puts the variable into the process that started it.)
    env = {k: v for k, v in os.environ.items() if k != "MALLOC_TRIM_THRESHOLD_"}
    code = "from skydome.batch.worker_memory import fit_allocator_to_frames as f; print(f())"
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    assert out.stdout.strip() == "False"
