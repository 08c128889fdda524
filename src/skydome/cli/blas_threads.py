"""One BLAS thread for the commands that draw many frames on a CPU rasterizer.

NumPy's OpenBLAS hands a large enough matrix product (the stars' (N, 3) directions times a
3 x 3 rotation, a camera's projection of them) to worker threads, which then spin, waiting
for more work, on the cores that Mesa's llvmpipe draws with: 2.7 % of a time-lapse's CPU
samples on a 2-core machine (``perf``), and the whole run 2 % faster with one thread. The
time-lapse and the viewer set OpenBLAS to one thread through its own entry point, found
among the process's loaded libraries; elsewhere (another BLAS, no /proc) nothing changes.
"""

from __future__ import annotations

import ctypes
import os
from pathlib import Path

#: OpenBLAS's thread-count setters: NumPy's wheels' (scipy-openblas, 64-bit integers), then
#: a system OpenBLAS's.
_SETTERS = (
    "scipy_openblas_set_num_threads64_",
    "scipy_openblas_set_num_threads",
    "openblas_set_num_threads64_",
    "openblas_set_num_threads",
)


def _openblas_libraries() -> list[str]:
    """Paths of the loaded shared libraries whose name holds 'openblas' (Linux: the
    process's memory map; elsewhere none)."""
    maps = Path("/proc/self/maps")
    if not maps.exists():
        return []
    found: list[str] = []
    for line in maps.read_text().splitlines():
        path = line.split(maxsplit=5)[-1] if line.count(" ") >= 5 else ""
        if "openblas" in os.path.basename(path).lower() and path not in found:
            found.append(path)
    return found


def single_blas_thread() -> bool:
    """Set the loaded OpenBLAS to one thread; True if one was found and set."""
    for path in _openblas_libraries():
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for name in _SETTERS:
            setter = getattr(lib, name, None)
            if setter is not None:
                setter(ctypes.c_int(1))
                return True
    return False
