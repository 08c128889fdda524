"""Float64 twin of the clouds' light model (shaders/clouds/cloud_lighting.glsl): the
delta-Eddington two-stream solution of a conservative slab, and the radiance a ray march with
that source function gives for a uniform slab (what the tests compare with the Monte Carlo
reference of reference/clouds_mc.py and with the GLSL pass).

The model, per point of a cloud at scaled depth tau' below the top of a local slab of scaled
thickness tau*' (delta-M scaling with the phase function's second moment f: tau' = (1 - f)
tau, g' = (g - f) / (1 - f); Joseph, Wiscombe & Weinman 1976, J. Atmos. Sci. 33, 2452):

- orders >= 2 of the beam from a table of the source function computed by Monte Carlo for a
  black ground (skydome.clouds.ms_table); the two-stream field below adds the ground's light
  (the difference between its value over the ground's albedo and over a black one) and the
  sky's;
- the diffuse field of the Eddington approximation, I(mu) = I0 + mu I1 (mu the upward
  cosine), from the two-stream equations with Meador & Weaver's (1980, J. Atmos. Sci. 37,
  630, table 1) Eddington coefficients at single-scattering albedo 1, where gamma1 = gamma2
  and the solution is closed-form without exponentials that overflow: the net flux is
  constant (F_up - F_down = mu0 E0 exp(-tau/mu0) + c1) and F_up + F_down is linear in tau
  plus the direct beam's term;
- the radiance source towards a direction of upward cosine mu and phase angle cosine nu:
  J = E0 [P(nu) exp(-tau_s) + (1 - f) P'(nu) (exp(-(1 - f) tau_s) - exp(-tau_s))]
      + E0 (I0 + g mu I1) + E_sky (I0_sky + g mu I1_sky),
  the exact single scattering of the unscattered beam (tau_s the slant optical depth towards
  the light), the light once scattered into the phase function's forward peak (which the
  delta scaling keeps in the beam) scattered again by the rest of the phase function
  (P' = HG(g')), and the diffuse field scattered by the whole phase function (the forward
  peak re-emits the field it scatters, so the first moment is the full g);
- E_sky: a diffuse (isotropic) irradiance on the top of the slab, E0: the collimated
  irradiance normal to the beam; ground albedo ``albedo`` below.
"""

from __future__ import annotations

import math

import numpy as np


def hg_phase(cos_theta, g: float):
    """Henyey-Greenstein phase function (1/sr), normalised to 1 over the sphere."""
    c = np.asarray(cos_theta, dtype=np.float64)
    return (1.0 - g * g) / (4.0 * math.pi * (1.0 + g * g - 2.0 * g * c) ** 1.5)


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
    """The model's reflected flux / incident flux (mu0 E0) of a slab of real optical
    thickness ``tau_total`` (delta-Eddington)."""
    g_scaled = (g - f) / (1.0 - f)
    ts = (1.0 - f) * tau_total
    gamma, gamma3, gamma4 = two_stream_gammas(g_scaled, mu0)
    i0, i1 = direct_field(0.0, ts, mu0, g_scaled, albedo)
    up = math.pi * (i0 + 2.0 * i1 / 3.0)
    return float(up / mu0)


def source(tau, tau_total, mu0, mu_view_up, nu, cos_phi, phase, g, f, albedo=0.0, sky=0.0):
    """The model's radiance source J (per unit E0, 1/sr) at real depth ``tau`` of a uniform
    slab of real thickness ``tau_total``, towards a direction of upward cosine
    ``mu_view_up``, phase-angle cosine ``nu`` and azimuth cosine ``cos_phi`` from the
    light's; ``phase(nu)`` the full phase function: the exact single scattering, the Monte
    Carlo table's orders >= 2 (skydome.clouds.ms_table), the ground's light and the sky's
    (diffuse irradiance ``sky`` per unit E0) from the two-stream field."""
    from skydome.clouds.ms_table import ms_source

    g_scaled = (g - f) / (1.0 - f)
    tau = np.asarray(tau, dtype=np.float64)
    ts, tts = (1.0 - f) * tau, (1.0 - f) * tau_total
    j = phase(nu) * np.exp(-tau / mu0) + ms_source(tau, tau_total, mu0, mu_view_up, cos_phi)
    if albedo > 0:
        i0, i1 = direct_field(ts, tts, mu0, g_scaled, albedo)
        z0, z1 = direct_field(ts, tts, mu0, g_scaled, 0.0)
        j = j + (i0 - z0) + g * mu_view_up * (i1 - z1)
    if sky:
        s0, s1 = diffuse_field(ts, tts, g_scaled, albedo)
        j = j + sky * (s0 + g * mu_view_up * s1)
    return j


def slab_radiance(tau_total, mu0, direction, phase, g, f, *, albedo=0.0, steps=4000):
    """Radiance (per unit irradiance normal to the beam, 1/sr) leaving a uniform slab along
    ``direction`` (unit, z up; the Sun at azimuth 0, light travelling along
    (-sqrt(1 - mu0^2), 0, -mu0)): reflected for direction.z > 0, transmitted (diffuse) for
    direction.z < 0, by integrating the model's source along the ray (midpoint rule in
    optical depth, exact attenuation per step)."""
    d = np.asarray(direction, dtype=np.float64)
    mu = float(d[2])
    sun_travel = np.array([-math.sqrt(1.0 - mu0 * mu0), 0.0, -mu0])
    nu = float(d @ sun_travel)
    # azimuth of the direction from the Sun's (+x)
    horizontal = math.hypot(d[0], d[1])
    cos_phi = float(d[0] / horizontal) if horizontal > 1e-9 else 1.0
    edges = np.linspace(0.0, tau_total, steps + 1)
    mid = 0.5 * (edges[1:] + edges[:-1])
    # optical path from each depth to the exit along the direction
    if mu > 0:  # up, exit at the top
        path = mid / mu
    else:
        path = (tau_total - mid) / -mu
    dtau_path = (tau_total / steps) / abs(mu)
    j = source(mid, tau_total, mu0, mu, nu, cos_phi, phase, g, f, albedo)
    # exact integral of exp(-path) over each step, times the midpoint source
    weight = np.exp(-path) * 2.0 * np.sinh(0.5 * dtau_path)
    return float(np.sum(j * weight))
