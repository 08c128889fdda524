"""Float64 NumPy reference of the transmittance and single-scattering integrals.

Slow and obvious, for tests only (never the production path). Column densities come from
``skydome.atmosphere.columns`` (Gauss-Legendre quadrature on many sub-intervals, converged
to ~1e-9 relative), so they check the GPU's transmittance table; the single-scattering sum uses the same sample
positions as ``atmosphere/single_scattering.glsl`` (quadratic spacing, offset 0.5), so the two agree
up to the table's interpolation and float32 rounding.

Units: metres, per-metre coefficients; radiance per unit solar irradiance (sr^-1).
"""

from __future__ import annotations

import numpy as np

from skydome.atmosphere.columns import (  # noqa: F401  (re-exported for the tests)
    column,
    column_to_top,
    densities,
    distance_to_bottom,
    distance_to_top,
    optical_depth,
    ray_hits_ground,
)
from skydome.atmosphere.params import AtmosphereParams
from skydome.physics.phase import cornette_shanks, rayleigh_phase


def single_scattering(
    params: AtmosphereParams,
    wavelengths_nm,
    position_m,
    directions,
    sun,
    samples: int = 16,
    offset: float = 0.5,
    sun_disk: bool = True,
) -> np.ndarray:
    """Radiance per unit solar irradiance (n_rays, n_wavelengths), sr^-1.

    position_m: (3,) planet-centred camera position; directions: (n, 3) unit view rays;
    sun: (3,) unit direction to the Sun. Same model as atmosphere/single_scattering.glsl: in-scattering
    by Rayleigh and Mie, Earth's shadow, absorption, the Lambertian ground lit by the
    attenuated Sun, and the Sun's uniform disk.
    """
    coef = params.coefficients(wavelengths_nm)
    dirs = np.atleast_2d(np.asarray(directions, float))
    dirs = dirs / np.linalg.norm(dirs, axis=-1, keepdims=True)
    sun = np.asarray(sun, float) / np.linalg.norm(sun)
    n_rays, n_wl = len(dirs), len(coef["rayleigh_scattering"])
    out = np.zeros((n_rays, n_wl))
    Rb, Rt = params.bottom_radius_m, params.top_radius_m
    nu = dirs @ sun
    alpha = params.sun_angular_radius_rad
    disk = (nu > np.cos(alpha)) & sun_disk
    disk_radiance = 1.0 / (np.pi * np.sin(alpha) ** 2)

    # Move cameras outside the atmosphere to the entry point.
    pos = np.broadcast_to(np.asarray(position_m, float), dirs.shape).copy()
    r = np.linalg.norm(pos, axis=-1)
    b = np.einsum("ij,ij->i", pos, dirs)
    disc = b * b - (r * r - Rt * Rt)
    outside = r > Rt
    miss = outside & ((disc < 0) | (-b + np.sqrt(np.maximum(disc, 0)) < 0))
    t_entry = np.where(outside & ~miss, np.maximum(-b - np.sqrt(np.maximum(disc, 0)), 0), 0.0)
    pos = pos + dirs * t_entry[:, None]
    r = np.where(outside, Rt, r)
    out[miss & disk] = disk_radiance
    live = ~miss
    mu = np.clip(np.einsum("ij,ij->i", pos, dirs) / r, -1, 1)
    ground = ray_hits_ground(params, r, mu)
    length = np.where(ground, distance_to_bottom(params, r, mu), distance_to_top(params, r, mu))
    phase_r = rayleigh_phase(nu)
    if params.mie_phase is None:
        phase_m = cornette_shanks(nu, params.mie_g)[:, None]
    else:  # a phase function per wavelength (n_rays, n_wl)
        phase_m = params.mie_phase.phase(nu, wavelengths_nm)
    du = 1.0 / samples
    for i in range(samples):
        u = (i + offset) * du
        t = length * u * u
        dt = 2.0 * length * u * du
        p = pos + dirs * t[:, None]
        rt = np.linalg.norm(p, axis=-1)
        mu_s = np.einsum("ij,j->i", p, sun) / rt
        lit = live & ~ray_hits_ground(params, rt, mu_s)
        col = column(params, r, mu, t) + column_to_top(params, rt, mu_s)
        d = densities(params, rt - Rb) * dt[:, None]
        scat = (
            d[:, 0:1] * coef["rayleigh_scattering"] * phase_r[:, None]
            + d[:, 1:2] * coef["mie_scattering"] * phase_m
        )
        out += np.where(lit[:, None], scat * np.exp(-optical_depth(coef, col)), 0.0)

    col_view = column(params, r, mu, length)
    # Ground: albedo / pi * cos(sun zenith) * T(ground -> sun) * T(camera -> ground).
    pg = pos + dirs * length[:, None]
    mu_sg = np.einsum("ij,j->i", pg / np.linalg.norm(pg, axis=-1, keepdims=True), sun)
    sunlit = live & ground & (mu_sg > 0)
    col_g = column_to_top(params, np.full(n_rays, Rb), np.clip(mu_sg, 0, 1)) + col_view
    out += np.where(
        sunlit[:, None],
        coef["ground_albedo"] / np.pi * mu_sg[:, None] * np.exp(-optical_depth(coef, col_g)),
        0.0,
    )
    seen = live & ~ground & disk
    out += np.where(seen[:, None], disk_radiance * np.exp(-optical_depth(coef, col_view)), 0.0)
    return out
