"""skydome.cli.blas_threads: the time-lapse and the viewer set NumPy's OpenBLAS to one
thread (its idle threads spin on the cores a CPU rasterizer draws with)."""

from __future__ import annotations

import ctypes

import numpy as np

from skydome.cli.blas_threads import _openblas_libraries, single_blas_thread

_GETTERS = ("scipy_openblas_get_num_threads64_", "openblas_get_num_threads")


def _get_set(lib):
    get = next((getattr(lib, n) for n in _GETTERS if hasattr(lib, n)), None)
    set_ = next(
        (
            getattr(lib, n)
            for n in ("scipy_openblas_set_num_threads64_", "openblas_set_num_threads")
            if hasattr(lib, n)
        ),
        None,
    )
    return get, set_


def test_one_blas_thread_and_the_same_products():
    np.ones((2, 2)) @ np.ones((2, 2))  # BLAS loaded
    libs = _openblas_libraries()
    if not libs:  # another BLAS, or no /proc: nothing to set, and nothing is
        assert single_blas_thread() is False
        return
    lib = ctypes.CDLL(libs[0])
    get, set_ = _get_set(lib)
    before = get() if get else None
    a = np.random.default_rng(1).normal(size=(40000, 3))
    m = np.random.default_rng(2).normal(size=(3, 3))
    want = a @ m
    try:
        assert single_blas_thread() is True
        if get is not None:
            assert get() == 1
        np.testing.assert_array_equal(a @ m, want)  # the same sums, in one thread
    finally:
        if before is not None and set_ is not None:
            set_(ctypes.c_int(before))
