"""Column densities along straight rays through an atmosphere, float64 on the CPU.

For the few rays the CPU needs without a GL context (``skydome ephemeris``' direct-beam
ground illuminance, a scene's light transmittance reported in ``SkyState``), and the twin
the GPU's transmittance table is tested against (``skydome.reference.single`` re-exports it).
Gauss-Legendre quadrature on many sub-intervals, converged to ~1e-9 relative.

Units: metres; radii from the planet's centre; ``mu`` the cosine of the view zenith angle.
"""

from __future__ import annotations

import numpy as np

from skydome.atmosphere.params import AtmosphereParams
from skydome.physics import geometry

_GL_NODES, _GL_WEIGHTS = np.polynomial.legendre.leggauss(8)


def densities(params: AtmosphereParams, altitude_m) -> np.ndarray:
    """Relative densities (..., 3) of Rayleigh, Mie and absorbing constituents.
    GLSL twin: ``densities``."""
    h = np.asarray(altitude_m, float)
    return np.stack(
        [
            params.rayleigh_density.density(h),
            params.mie_density.density(h),
            params.absorption_density.density(h),
        ],
        axis=-1,
    )


def distance_to_top(params: AtmosphereParams, r, mu) -> np.ndarray:
    """Distance (m) from (r, mu) to the top of the atmosphere."""
    return geometry.distance_to_top(r, mu, params.top_radius_m)


def distance_to_bottom(params: AtmosphereParams, r, mu) -> np.ndarray:
    """Distance (m) from (r, mu) to the ground (where :func:`ray_hits_ground`)."""
    return geometry.distance_to_bottom(r, mu, params.bottom_radius_m)


def ray_hits_ground(params: AtmosphereParams, r, mu) -> np.ndarray:
    """Whether the ray (r, mu) meets the ground."""
    return geometry.ray_hits_ground(r, mu, params.bottom_radius_m)


def column(params: AtmosphereParams, r, mu, length_m, intervals: int = 400) -> np.ndarray:
    """Column densities (..., 3) in metres from radius r along cosine mu over length_m."""
    r, mu, length = np.broadcast_arrays(*(np.asarray(x, float) for x in (r, mu, length_m)))
    edges = np.linspace(0.0, 1.0, intervals + 1)
    a, b = edges[:-1], edges[1:]
    # Gauss-Legendre nodes on each sub-interval of [0, 1], scaled by the length.
    s = (0.5 * (b - a))[:, None] * _GL_NODES[None, :] + (0.5 * (a + b))[:, None]
    w = ((0.5 * (b - a))[:, None] * _GL_WEIGHTS[None, :]).ravel()
    t = length[..., None] * s.ravel()
    rt = np.sqrt(t * t + 2.0 * r[..., None] * mu[..., None] * t + r[..., None] ** 2)
    d = densities(params, rt - params.bottom_radius_m)
    return np.einsum("...kc,k->...c", d, w) * length[..., None]


def column_to_top(params: AtmosphereParams, r, mu) -> np.ndarray:
    """Column densities (..., 3), metres, from (r, mu) to the top of the atmosphere."""
    return column(params, r, mu, distance_to_top(params, r, mu))


def optical_depth(coefficients: dict, column) -> np.ndarray:
    """Optical depth (..., N) of column densities (..., 3) (Rayleigh, Mie, absorbing; m) at
    the N wavelengths of ``coefficients`` (:meth:`AtmosphereParams.coefficients`, per m):
    beta_R c_R + beta_M,ext c_M + beta_A c_A. The transmittance is exp(-optical depth).
    GLSL twin: ``optical_depth``."""
    col = np.asarray(column, float)
    return (
        col[..., 0:1] * coefficients["rayleigh_scattering"]
        + col[..., 1:2] * coefficients["mie_extinction"]
        + col[..., 2:3] * coefficients["absorption_extinction"]
    )
