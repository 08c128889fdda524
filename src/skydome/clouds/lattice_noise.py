"""Float64 twin of ``shaders/clouds/noise_common.glsl``: the same hash, gradient (Perlin)
noise, cellular (Worley) noise and fBm, evaluated with NumPy at given points.

The hash is integer arithmetic modulo 2^32, so it is bit-identical to the GLSL; the
noise values then differ from the float32 shaders only by float32 rounding. Points are
arrays of shape (..., 3) in lattice units (texture coordinates times the period) and must
be >= 0, as in the shaders. The weather maps (:mod:`skydome.clouds.weather`, host data made
once per seed) are drawn with it; the noise textures themselves are drawn by the shaders.
"""

from __future__ import annotations

import numpy as np

_U32 = np.uint32


def pcg4d(v: np.ndarray) -> np.ndarray:
    """PCG4D hash (Jarzynski & Olano, JCGT 9(3), 2020) of uint32 arrays of shape (..., 4)."""
    v = np.array(v, dtype=_U32, copy=True)
    with np.errstate(over="ignore"):
        v = v * _U32(1664525) + _U32(1013904223)
        x, y, z, w = (v[..., i].copy() for i in range(4))
        x += y * w
        y += z * x
        z += x * y
        w += y * z
        x ^= x >> _U32(16)
        y ^= y >> _U32(16)
        z ^= z >> _U32(16)
        w ^= w >> _U32(16)
        x += y * w
        y += z * x
        z += x * y
        w += y * z
    return np.stack([x, y, z, w], axis=-1)


def noise_salt(seed: int, stream: int) -> int:
    """The hash salt of one random stream (a seed and a stream id), as in the shaders."""
    v = np.array([seed % 2**32, stream % 2**32, 0x68E31DA4, 0xB5297A4D], dtype=_U32)
    return int(pcg4d(v)[0])


def _hash_cells(cells: np.ndarray, salt: int) -> np.ndarray:
    """pcg4d(cell.xyz, salt) for integer cells of shape (..., 3), already wrapped."""
    c = cells.astype(_U32)
    return pcg4d(np.concatenate([c, np.full(c.shape[:-1] + (1,), salt, dtype=_U32)], axis=-1))


def _wrap(cells: np.ndarray, period) -> np.ndarray:
    return np.mod(cells, np.asarray(period, dtype=np.int64))


def fade(t: np.ndarray) -> np.ndarray:
    """Perlin's quintic fade 6t^5 - 15t^4 + 10t^3 (Perlin 2002)."""
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)


def _gradients() -> np.ndarray:
    """The 12 gradients of Perlin 2002, (+-1, +-1) on the axis pairs xy, xz, yz, in the
    order the shaders pick them by ``hash % 12`` (bit 0: sign of the first, bit 1: second)."""
    rows = []
    for first, second in ((0, 1), (0, 2), (1, 2)):
        for i in range(4):
            g = [0.0, 0.0, 0.0]
            g[first] = -1.0 if i & 1 else 1.0
            g[second] = -1.0 if i & 2 else 1.0
            rows.append(g)
    return np.array(rows)


GRADIENTS = _gradients()


def perlin_noise(p: np.ndarray, period, salt: int) -> np.ndarray:
    """Gradient noise of integer ``period`` (per axis, scalar or 3 values) at points (..., 3)."""
    p = np.asarray(p, dtype=np.float64)
    c = np.floor(p).astype(np.int64)
    f = p - c
    w = fade(f)
    out = np.zeros(p.shape[:-1])
    for corner in np.ndindex(2, 2, 2):
        o = np.array(corner[::-1])  # (x, y, z) offsets
        weight = np.prod(np.where(o == 1, w, 1.0 - w), axis=-1)
        if not weight.any():  # e.g. the far corners of a slice on a lattice plane
            continue
        h = _hash_cells(_wrap(c + o, period), salt)[..., 0]
        g = GRADIENTS[(h >> _U32(16)) % _U32(12)]
        value = np.sum(g * (f - o), axis=-1)
        out += weight * value
    return out


def worley_f1(p: np.ndarray, period, salt: int) -> np.ndarray:
    """Distance (cells) to the nearest point of a jittered grid, over the 27 cells around p."""
    p = np.asarray(p, dtype=np.float64)
    c = np.floor(p).astype(np.int64)
    f = p - c
    best = np.full(p.shape[:-1], np.inf)
    for offset in np.ndindex(3, 3, 3):
        o = np.array(offset) - 1
        h = _hash_cells(_wrap(c + o, period), salt)
        jitter = (h[..., :3] >> _U32(8)).astype(np.float64) / 16777216.0
        d = o + jitter - f
        best = np.minimum(best, np.sum(d * d, axis=-1))
    return np.sqrt(best)


def perlin_fbm(u: np.ndarray, period: int, octaves: int, seed: int, stream: int) -> np.ndarray:
    """Gradient-noise fBm at tile coordinates ``u`` (..., 3): periods P, 2P, ...; amplitudes
    1, 1/2, ...; divided by the sum of the amplitudes.
    GLSL twin: ``perlin_fbm``."""
    u = np.asarray(u, dtype=np.float64)
    total, norm = np.zeros(u.shape[:-1]), 0.0
    for o in range(octaves):
        p = period * 2**o
        amp = 0.5**o
        total += amp * perlin_noise(u * p, p, noise_salt(seed, stream + o))
        norm += amp
    return total / norm


def worley_inverted(u: np.ndarray, period: int, seed: int, stream: int) -> np.ndarray:
    """1 - F1, clamped to [0, 1], at tile coordinates ``u``."""
    u = np.asarray(u, dtype=np.float64)
    f1 = worley_f1(u * period, period, noise_salt(seed, stream))
    return 1.0 - np.clip(f1, 0.0, 1.0)


def worley_fbm(u: np.ndarray, period: int, seed: int, stream: int) -> np.ndarray:
    """Schneider's Worley fBm: 0.625 W(P) + 0.25 W(2P) + 0.125 W(4P).
    GLSL twin: ``worley_fbm``."""
    return (
        0.625 * worley_inverted(u, period, seed, stream)
        + 0.25 * worley_inverted(u, 2 * period, seed, stream + 1)
        + 0.125 * worley_inverted(u, 4 * period, seed, stream + 2)
    )
