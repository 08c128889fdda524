"""glibc's allocator in a Dask worker, set for frames.

Dask's nanny starts every worker process with ``MALLOC_TRIM_THRESHOLD_=65536`` (its
``distributed.nanny.pre-spawn-environ``, to hand freed memory back to the system). Setting
any of glibc's thresholds turns off glibc's dynamic mmap threshold (mallopt(3)), which leaves
it at 128 KiB: every array of a frame (a 512 x 256 RGB float64 map is 3 MiB) is then mapped
from the kernel when made and unmapped when freed, its pages faulted in and zeroed again
each time. Measured on this project's batch (2 cores, llvmpipe): the same job took 117 ms
with that variable against 93 ms without. :func:`fit_allocator_to_frames` puts the two
thresholds where glibc's own dynamic rule takes them for large arrays (mmap at 32 MiB, its
ceiling on 64-bit systems; trim at twice that), so a worker allocates as a plain process
does; memory that a worker frees stays reusable by the next frame, and its resident size
stays flat (the batch benchmark measures it).
"""

from __future__ import annotations

import ctypes
import os
import platform

__all__ = ["MMAP_THRESHOLD_BYTES", "TRIM_THRESHOLD_BYTES", "fit_allocator_to_frames"]

#: glibc's ceiling for its dynamic mmap threshold on 64-bit systems (DEFAULT_MMAP_THRESHOLD_MAX).
MMAP_THRESHOLD_BYTES = 32 * 2**20
#: Twice the mmap threshold: where glibc's dynamic rule puts the trim threshold.
TRIM_THRESHOLD_BYTES = 2 * MMAP_THRESHOLD_BYTES
# mallopt(3) parameter numbers (malloc.h).
_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3


def fit_allocator_to_frames() -> bool:
    """When this process runs on glibc with ``MALLOC_TRIM_THRESHOLD_`` set (a Dask nanny's
    worker), set glibc's mmap and trim thresholds to :data:`MMAP_THRESHOLD_BYTES` and
    :data:`TRIM_THRESHOLD_BYTES`; True if it did. Elsewhere (another C library, or no such
    variable: glibc's dynamic thresholds are on) nothing changes and it returns False."""
    if "MALLOC_TRIM_THRESHOLD_" not in os.environ or platform.libc_ver()[0] != "glibc":
        return False
    try:
        mallopt = ctypes.CDLL("libc.so.6").mallopt
    except (OSError, AttributeError):
        return False
    mallopt.argtypes = [ctypes.c_int, ctypes.c_int]
    mallopt.restype = ctypes.c_int
    # mallopt returns 1 on success, 0 on error.
    mmap_ok = mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES) == 1
    trim_ok = mallopt(_M_TRIM_THRESHOLD, TRIM_THRESHOLD_BYTES) == 1
    return mmap_ok and trim_ok
