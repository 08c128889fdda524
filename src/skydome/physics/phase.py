"""Phase functions (sr^-1, normalised over the sphere) as functions of the cosine of the
scattering angle ``mu``. GLSL twins: ``shaders/common/phase_functions.glsl``."""

from __future__ import annotations

import numpy as np

#: Most Henyey-Greenstein lobes a lobe mixture may hold (the shaders' array size, MIE_LOBES
#: and CLOUD_LOBES at most this).
MAX_LOBES = 12


def rayleigh_phase(mu) -> np.ndarray:
    """Rayleigh scattering: 3 (1 + mu^2) / (16 pi) (GLSL: ``rayleigh_phase``)."""
    mu = np.asarray(mu, dtype=np.float64)
    return 3.0 / (16.0 * np.pi) * (1.0 + mu * mu)


def henyey_greenstein(mu, g) -> np.ndarray:
    """Henyey-Greenstein: (1 - g^2) / (4 pi (1 + g^2 - 2 g mu)^1.5) (GLSL:
    ``henyey_greenstein_phase``)."""
    mu = np.asarray(mu, dtype=np.float64)
    g = np.asarray(g, dtype=np.float64)
    return (1.0 - g * g) / (4.0 * np.pi * (1.0 + g * g - 2.0 * g * mu) ** 1.5)


def cornette_shanks(mu, g) -> np.ndarray:
    """Cornette & Shanks (1992, Appl. Opt. 31, 3152, eq. 4), Bruneton's Mie phase function:
    3 (1 - g^2)(1 + mu^2) / (8 pi (2 + g^2)(1 + g^2 - 2 g mu)^1.5) (GLSL: ``cornette_shanks_phase``)."""
    mu = np.asarray(mu, dtype=np.float64)
    g = np.asarray(g, dtype=np.float64)
    k = 3.0 / (8.0 * np.pi) * (1.0 - g * g) / (2.0 + g * g)
    return k * (1.0 + mu * mu) / (1.0 + g * g - 2.0 * g * mu) ** 1.5


def cornette_shanks_mean_cosine(g: float) -> float:
    """Mean scattering cosine <mu> of the Cornette-Shanks function of parameter g:
    3 g (4 + g^2) / (5 (2 + g^2))."""
    g = float(g)
    return 3.0 * g * (4.0 + g * g) / (5.0 * (2.0 + g * g))


def sample_hg(g, u) -> np.ndarray:
    """Cosines of scattering angles drawn from HG(g) by inverting its CDF at uniform deviates
    ``u`` in [0, 1) (``g`` and ``u`` broadcast):
    cos = (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u))^2) / (2 g), and 2 u - 1 where |g| < 1e-6."""
    g = np.asarray(g, float)
    u = np.asarray(u, float)
    small = np.abs(g) < 1e-6
    gs = np.where(small, 0.5, g)  # placeholder where isotropic, result replaced below
    s = (1.0 - gs * gs) / (1.0 - gs + 2.0 * gs * u)
    mu = (1.0 + gs * gs - s * s) / (2.0 * gs)
    return np.clip(np.where(small, 2.0 * u - 1.0, mu), -1.0, 1.0)
