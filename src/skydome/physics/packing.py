"""Spectral values packed for the shaders: wavelengths go 4 to a vec4 ("a group"), and a
matrix over wavelengths goes as one GLSL mat4 per group (column j = wavelength j of the
group; GLSL matrices are column-major)."""

from __future__ import annotations

import numpy as np

from skydome.errors import ParameterError


def mat4(m) -> list[float]:
    """A 4x4 matrix as a GLSL mat4 uniform (column-major)."""
    return np.asarray(m, dtype=np.float64).T.ravel().tolist()


def mat3(m) -> tuple[float, ...]:
    """A 3x3 matrix as a GLSL mat3 uniform (column-major)."""
    return tuple(float(v) for v in np.asarray(m, dtype=np.float64).T.ravel())


def mat4_groups(matrix) -> list[float]:
    """A (4, N) matrix over N wavelengths (N a multiple of 4) as N / 4 GLSL mat4s, flattened
    for a ``uniform mat4 name[NUM_GROUPS]``: mat4 g maps group g's vec4 to the 4 rows."""
    m = np.asarray(matrix, dtype=np.float64)
    if m.ndim != 2 or m.shape[0] != 4 or m.shape[1] % 4:
        raise ParameterError(f"a (4, 4k) matrix packs into mat4 groups, got shape {m.shape}")
    groups = m.shape[1] // 4
    return np.concatenate([m[:, 4 * g : 4 * g + 4].T.ravel() for g in range(groups)]).tolist()
