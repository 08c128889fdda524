"""Float64 twin of the clouds' light model (shaders/clouds/cloud_lighting.glsl) and of the
radiance its ray march gives for a uniform slab: what the tests compare with the Monte Carlo
reference (reference/clouds_mc.py) and with the GLSL pass.

The march uses the droplets' optical depths with their diffraction peak taken out (delta-M:
the scaled tau = (1 - PEAK_FRACTION) tau, phase function RENDER_PHASE; skydome.clouds.phase).
At a point at scaled depth tau below the top of its local slab (towards the light; slab
thickness tau*), towards a direction of upward cosine mu:

- the exact single scattering of the unscattered beam: P(nu) exp(-tau_s), tau_s the slant
  optical depth towards the light;
- every order >= 2 of the beam from the Monte Carlo table of a slab over a black ground
  (skydome.clouds.ms_table.ms_source);
- the ground's reflected light and the sky's diffuse light from the Eddington two-stream
  field, I(mu) = I0 + mu I1, of a conservative slab (Meador & Weaver 1980, J. Atmos. Sci.
  37, 630, table 1: gamma1 = gamma2 at albedo 1, so the solution is closed-form without
  exponentials that overflow: the net flux is constant but for the beam, F_up + F_down is
  linear in tau plus the beam's term), delta-M scaled with the phase function's second
  moment (Joseph, Wiscombe & Weinman 1976, J. Atmos. Sci. 33, 2452): the ground's part is
  the field over the ground's albedo less the field over a black ground; each scattered as
  I0 + g mu I1.
"""

from __future__ import annotations

import math

import numpy as np

from skydome.clouds.ms_table import ms_source
from skydome.clouds.phase import PEAK_FRACTION, RENDER_PHASE


def two_stream_gammas(g_scaled: float, mu0: float) -> tuple[float, float, float]:
    """Meador & Weaver's Eddington gamma1 (= gamma2 at albedo 1), gamma3, gamma4."""
    gamma = 0.75 * (1.0 - g_scaled)
    gamma3 = (2.0 - 3.0 * g_scaled * mu0) / 4.0
    return gamma, gamma3, 1.0 - gamma3


def direct_field(tau, tau_total, mu0, g_scaled, albedo=0.0):
    """(I0, I1) (1/sr, per unit irradiance normal to the beam) of the diffuse field at scaled
    depth ``tau`` in a conservative slab of scaled thickness ``tau_total`` lit by a beam of
    cosine ``mu0`` at its top, over a Lambertian ground of ``albedo``."""
    tau = np.asarray(tau, dtype=np.float64)
    gamma, gamma3, gamma4 = two_stream_gammas(g_scaled, mu0)
    a = -mu0 * (2.0 * gamma * mu0 + gamma4 - gamma3)
    e_total = math.exp(-tau_total / mu0)
    c1 = (
        (1.0 - albedo)
        * (a * (1.0 - e_total) - mu0 * (1.0 + e_total))
        / (2.0 + 2.0 * gamma * tau_total * (1.0 - albedo))
    )
    c2 = mu0 + c1 - a
    e = np.exp(-tau / mu0)
    net = mu0 * e + c1  # F_up - F_down
    total = a * e + 2.0 * gamma * c1 * tau + c2  # F_up + F_down
    return total / (2.0 * math.pi), 3.0 * net / (4.0 * math.pi)


def diffuse_field(tau, tau_total, g_scaled, albedo=0.0):
    """(I0, I1) per unit diffuse irradiance (isotropic radiance) on the top of the slab."""
    tau = np.asarray(tau, dtype=np.float64)
    gamma = 0.75 * (1.0 - g_scaled)
    c1 = -2.0 * (1.0 - albedo) / (2.0 + 2.0 * gamma * tau_total * (1.0 - albedo))
    c2 = 2.0 + c1
    total = 2.0 * gamma * c1 * tau + c2
    return total / (2.0 * math.pi), np.broadcast_to(3.0 * c1 / (4.0 * math.pi), tau.shape)


def plane_albedo(tau_total, mu0, g, f, albedo=0.0) -> float:
    """The two-stream field's reflected flux / incident flux (mu0 E0) of a slab of optical
    thickness ``tau_total`` (delta-Eddington with the phase function's moments g, f)."""
    g_scaled = (g - f) / (1.0 - f)
    ts = (1.0 - f) * tau_total
    i0, i1 = direct_field(0.0, ts, mu0, g_scaled, albedo)
    up = math.pi * (i0 + 2.0 * i1 / 3.0)
    return float(up / mu0)


def source(tau, tau_total, mu0, mu_view_up, nu, cos_phi, albedo=0.0, sky=0.0):
    """The renderer's radiance source J (per unit E0, 1/sr) at the scaled depth ``tau`` of a
    uniform slab of scaled thickness ``tau_total`` (optical depths with the diffraction peak
    taken out, as the march has them: PEAK_FRACTION of the droplets'), towards a direction
    of upward cosine ``mu_view_up``, phase-angle cosine ``nu`` and azimuth cosine
    ``cos_phi`` from the light's: the exact single scattering (RENDER_PHASE), the Monte Carlo
    table's orders >= 2 (skydome.clouds.ms_table), the ground's light and the sky's (diffuse
    irradiance ``sky`` per unit E0) from the two-stream field of RENDER_PHASE's moments."""

    g, f = RENDER_PHASE.asymmetry, RENDER_PHASE.second_moment
    g_scaled = (g - f) / (1.0 - f)
    tau = np.asarray(tau, dtype=np.float64)
    ts, tts = (1.0 - f) * tau, (1.0 - f) * tau_total
    j = RENDER_PHASE.value(nu) * np.exp(-tau / mu0)
    j = j + ms_source(tau, tau_total, mu0, mu_view_up, cos_phi)
    if albedo > 0:
        i0, i1 = direct_field(ts, tts, mu0, g_scaled, albedo)
        z0, z1 = direct_field(ts, tts, mu0, g_scaled, 0.0)
        j = j + (i0 - z0) + g * mu_view_up * (i1 - z1)
    if sky:
        s0, s1 = diffuse_field(ts, tts, g_scaled, albedo)
        j = j + sky * (s0 + g * mu_view_up * s1)
    return j


def slab_radiance(tau_total, mu0, direction, *, albedo=0.0, steps=4000):
    """Radiance (per unit irradiance normal to the beam, 1/sr) the renderer's model gives
    leaving a uniform slab of the droplets' optical thickness ``tau_total`` along
    ``direction`` (unit, z up; the Sun at azimuth 0, its light travelling along
    (-sqrt(1 - mu0^2), 0, -mu0)): reflected for direction.z > 0, transmitted (diffuse) for
    direction.z < 0. The source is integrated along the ray in the scaled optical depth
    (1 - PEAK_FRACTION) tau_total (midpoint rule, exact attenuation per step)."""

    d = np.asarray(direction, dtype=np.float64)
    mu = float(d[2])
    sun_travel = np.array([-math.sqrt(1.0 - mu0 * mu0), 0.0, -mu0])
    nu = float(d @ sun_travel)
    horizontal = math.hypot(d[0], d[1])
    cos_phi = float(d[0] / horizontal) if horizontal > 1e-9 else 1.0
    ts = (1.0 - PEAK_FRACTION) * tau_total
    edges = np.linspace(0.0, ts, steps + 1)
    mid = 0.5 * (edges[1:] + edges[:-1])
    path = mid / mu if mu > 0 else (ts - mid) / -mu  # to the exit along the direction
    step = (ts / steps) / abs(mu)
    j = source(mid, ts, mu0, mu, nu, cos_phi, albedo)
    # the exact integral of exp(-path) over each step, times the midpoint source
    return float(np.sum(j * np.exp(-path) * 2.0 * np.sinh(0.5 * step)))
