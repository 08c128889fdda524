"""Real spherical harmonics of order 2 and the irradiance of a distant light field from them
(Ramamoorthi & Hanrahan 2001, "An efficient representation for irradiance environment
maps", eqs. 3-8, 12).

Order of the 9 functions: (l, m) = (0,0), (1,-1), (1,0), (1,1), (2,-2), (2,-1), (2,0), (2,1),
(2,2), with Y_1,-1 ~ y, Y_1,0 ~ z, Y_1,1 ~ x for unit directions (x, y, z) (skydome: x east,
y north, z up). A radiance L(w) projects to L_lm = sum L(w) Y_lm(w) dOmega; the irradiance of
a Lambertian surface of normal n is E(n) = sum_lm A_l L_lm Y_lm(n), with the clamped cosine's
coefficients A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4 (the terms l >= 3 are < 1 % of it for
smooth skies: R&H's bound).
"""

from __future__ import annotations

import math

import numpy as np

#: The normalisation constants of the 9 real harmonics (R&H eq. 3).
_C0 = 0.5 * math.sqrt(1.0 / math.pi)  # 0.282095
_C1 = math.sqrt(3.0 / (4.0 * math.pi))  # 0.488603
_C2 = 0.5 * math.sqrt(15.0 / math.pi)  # 1.092548
_C20 = 0.25 * math.sqrt(5.0 / math.pi)  # 0.315392
_C22 = 0.25 * math.sqrt(15.0 / math.pi)  # 0.546274

#: The clamped cosine's coefficient for each of the 9 functions (pi, 2pi/3 x 3, pi/4 x 5).
COSINE_LOBE = np.array([math.pi] + [2.0 * math.pi / 3.0] * 3 + [math.pi / 4.0] * 5)


def sh9(directions) -> np.ndarray:
    """The 9 real harmonics at unit ``directions`` (..., 3): (..., 9)."""
    d = np.asarray(directions, dtype=np.float64)
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    return np.stack(
        [
            np.full_like(x, _C0),
            _C1 * y,
            _C1 * z,
            _C1 * x,
            _C2 * x * y,
            _C2 * y * z,
            _C20 * (3.0 * z * z - 1.0),
            _C2 * x * z,
            _C22 * (x * x - y * y),
        ],
        axis=-1,
    )


def project(radiance, directions, solid_angle_sr) -> np.ndarray:
    """The 9 harmonic coefficients (9, C) of a radiance field sampled at ``directions`` (N, 3)
    as ``radiance`` (N, C) over pixels of ``solid_angle_sr`` (N,)."""
    basis = sh9(directions) * np.asarray(solid_angle_sr, dtype=np.float64)[..., None]
    return basis.T @ np.asarray(radiance, dtype=np.float64)


def irradiance_coefficients(radiance_coefficients) -> np.ndarray:
    """Irradiance coefficients (9, C) from radiance ones: each times its band's A_l, so that
    E(n) = sum_i coefficient_i Y_i(n) (``evaluate``)."""
    return COSINE_LOBE[:, None] * np.asarray(radiance_coefficients, dtype=np.float64)


def evaluate(coefficients, directions) -> np.ndarray:
    """sum_i coefficients_i Y_i(n) at unit ``directions`` (N, 3): (N, C)."""
    return sh9(directions) @ np.asarray(coefficients, dtype=np.float64)


def exact_irradiance(radiance, directions, solid_angle_sr, normals) -> np.ndarray:
    """The irradiance (N_normals, C) of Lambertian surfaces facing ``normals`` (unit) from a
    sampled radiance field: sum L max(n . w, 0) dOmega."""
    cos = np.maximum(np.asarray(normals, dtype=np.float64) @ np.asarray(directions).T, 0.0)
    return (cos * np.asarray(solid_angle_sr)[None, :]) @ np.asarray(radiance, dtype=np.float64)
