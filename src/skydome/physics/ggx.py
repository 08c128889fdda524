"""The GGX (Trowbridge-Reitz) microfacet lobe in float64: the twins of
``shaders/lighting/ggx.glsl`` (the split-sum image lighting of :mod:`skydome.lighting_ibl`;
Karis 2013, "Real Shading in Unreal Engine 4"). ``alpha`` = roughness^2 throughout."""

from __future__ import annotations

import math

import numpy as np


def d_ggx(noh, alpha):
    """The GGX normal distribution D (sr^-1) at cos(n, h) = ``noh``:
    alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2) (Walter et al. 2007, eq. 33)."""
    noh = np.asarray(noh, dtype=np.float64)
    a2 = np.asarray(alpha, dtype=np.float64) ** 2
    d = noh * noh * (a2 - 1.0) + 1.0
    return a2 / (math.pi * d * d)


def g_smith_schlick(nov, nol, alpha):
    """Smith's masking-shadowing with Schlick's G1 = x / (x (1 - k) + k), k = alpha / 2
    (Karis 2013's choice for image lighting), at cosines ``nov`` and ``nol``."""
    k = 0.5 * np.asarray(alpha, dtype=np.float64)
    nov = np.asarray(nov, dtype=np.float64)
    nol = np.asarray(nol, dtype=np.float64)
    return nov / (nov * (1.0 - k) + k) * (nol / (nol * (1.0 - k) + k))


def hammersley(n: int) -> np.ndarray:
    """The n Hammersley points (n, 2): (i / n, the base-2 radical inverse of i)."""
    i = np.arange(n, dtype=np.uint64)
    b = np.zeros(n, dtype=np.float64)
    scale = 0.5
    bits = i.copy()
    for _ in range(32):
        b += (bits & np.uint64(1)).astype(np.float64) * scale
        bits >>= np.uint64(1)
        scale *= 0.5
    return np.stack([i.astype(np.float64) / n, b], axis=-1)


def importance_sample_ggx(xi: np.ndarray, alpha: float, n: np.ndarray) -> np.ndarray:
    """Half vectors (..., 3) drawn from D(n.h)(n.h) around unit normals ``n`` (..., 3) for
    points ``xi`` (..., 2) in [0, 1)^2 (Karis' ImportanceSampleGGX and tangent frame)."""
    xi = np.asarray(xi, dtype=np.float64)
    n = np.asarray(n, dtype=np.float64)
    phi = 2.0 * math.pi * xi[..., 0]
    cos_t = np.sqrt((1.0 - xi[..., 1]) / (1.0 + (alpha * alpha - 1.0) * xi[..., 1]))
    sin_t = np.sqrt(np.maximum(1.0 - cos_t * cos_t, 0.0))
    up = np.where(
        (np.abs(n[..., 2]) < 0.999)[..., None], np.array([0.0, 0.0, 1.0]), np.array([1.0, 0, 0])
    )
    tx = np.cross(up, n)
    tx /= np.linalg.norm(tx, axis=-1, keepdims=True)
    ty = np.cross(n, tx)
    return (
        tx * (sin_t * np.cos(phi))[..., None]
        + ty * (sin_t * np.sin(phi))[..., None]
        + n * cos_t[..., None]
    )
