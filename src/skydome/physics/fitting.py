"""Fits shared by the host code: non-negative least squares."""

from __future__ import annotations

import numpy as np


def nonnegative_lstsq(a: np.ndarray, b: np.ndarray, iterations: int = 4000) -> np.ndarray:
    """min |a x - b|^2 with x >= 0, for a, b >= 0: Lee & Seung's multiplicative updates
    (x <- x a^T b / a^T a x), which keep x non-negative and do not increase the residual."""
    ata = a.T @ a
    atb = a.T @ b
    x = np.full(a.shape[1], 1e-3)
    for _ in range(iterations):
        x *= atb / np.maximum(ata @ x, 1e-300)
    return x
