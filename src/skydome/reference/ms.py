"""Float64 Monte Carlo reference for sky radiance with all scattering orders (DESIGN rule 2).

This module is a slow, independent check of the GLSL precomputation (Bruneton 2017), never a
production path. It solves the radiative transfer equation in a spherical atmosphere (no
plane-parallel approximation) by brute force:

* :func:`sky_radiance_mc` - a vectorized backward path tracer with next-event estimation (NEE)
  towards the Sun, every scattering order (Russian roulette, unbiased), Rayleigh and Mie
  scattering, ozone and aerosol absorption, a Lambertian spherical ground and the Earth's
  shadow.
* :func:`single_scattering_quadrature` - the single-scattering integral by deterministic
  composite Gauss-Legendre quadrature, to validate the tracer with ``orders=1``.
* :func:`ground_irradiance_mc` / :func:`direct_ground_irradiance` - diffuse and direct
  irradiance on the ground, for the indirect-irradiance table and the energy test.
* :func:`ground_radiance_mc` - the radiance of the lit Lambertian ground itself seen through
  the air (which :func:`sky_radiance_mc` excludes), for the renderer's ground.

Geometry and conventions
------------------------
* The planet is a sphere of radius ``bottom_radius_m`` centred at the origin; the atmosphere
  ends at ``top_radius_m``. Directions are unit vectors in the local East-North-Up frame of the
  camera (DESIGN rule 5: x = east, y = north, z = up); the camera is at ``(0, 0, R_b + h)``.
* The Sun is at azimuth 90 degrees (due east), zenith angle ``sun_zenith_rad``:
  ``s = (sin θs, 0, cos θs)``. It is a directional source (parallel rays, the solar disk is
  ignored for scattering) of irradiance E(λ) on a plane normal to ``s`` at the top of the
  atmosphere. All results are **per unit solar irradiance**: radiance in sr^-1 (multiply by
  E_sun(λ) in W m^-2 nm^-1 for W m^-2 sr^-1 nm^-1), irradiance dimensionless.
* A view direction ``v`` is the direction the camera looks in. The result is the radiance
  scattered towards the camera along the ray ``x + t v`` up to the top of the atmosphere or the
  ground, i.e. Bruneton's "scattering" quantity: the direct Sun is **excluded**, and for rays
  that hit the ground the radiance of the ground surface itself is **excluded** (only the
  in-scattered light in front of it, the aerial perspective, is returned). A camera at 0 m
  looking below the horizon therefore gets 0.
* Scattering order = number of interactions (atmospheric scattering or ground reflection) on
  the light path from the Sun to the camera. Order 1 is single scattering; light reflected once
  by the ground and scattered once in the air is order 2, as in Bruneton's precomputation where
  the ground irradiance of order n-1 feeds the scattering density of order n.

Physics (sources)
-----------------
* Phase functions: Rayleigh p_R(μ) = 3/(16π)(1+μ²); Mie: Cornette & Shanks (1992)
  p_M(μ) = 3/(8π)(1-g²)(1+μ²)/((2+g²)(1+g²-2gμ)^{3/2}) (both as in Bruneton 2017,
  ``functions.glsl``), μ the cosine of the angle between the propagation directions.
* Radiative transfer: L(x, v) = ∫ T(x, y) σ_s(y) ∫ p L_in dω dt (+ ground); estimated by path
  tracing with NEE (Pharr, Jakob & Humphreys, PBRT 3rd ed. §14.5, §15.2).
* Distance sampling inverts a tabulated optical depth: the optical depth at the quadrature
  nodes of each segment is integrated accurately (see below), the sampling density is
  piecewise σ̃·T̃ (interval-mean extinction, its transmittance) times an optional guide, and
  the estimator uses the exact transmittance at the sampled point (tabulated value at the node
  plus a Gauss-Legendre partial column), divided by that closed-form density: unbiased up to
  the quadrature error of the optical depth (< 1e-6). Every segment gets two independent
  distance samples ("decoupled" next-event estimation; see Novák et al. 2018, "Monte Carlo methods for
  volumetric light transport simulation", Computer Graphics Forum 37(2)): one on the *lit* part of the segment (outside the planet's
  shadow, the shadow being a half-cylinder, so its intersection with a ray is one interval),
  where the Sun is connected; one over the whole segment, the next vertex. The camera ray and
  segments that leave through the top use forced collisions (the vertex is drawn inside the
  segment, the weight carries 1 - T), so no path is wasted escaping; segments that end on the
  ground reflect there with probability T, and the sunlit ground at their end is connected to
  the Sun deterministically (weight T).
* Guiding (variance only, the estimates stay unbiased because every density is evaluated
  exactly and floored away from zero): the distance densities are multiplied by a crude
  transmittance to the Sun from a coarse (altitude, cosine) table, so NEE points avoid the
  dark air near the shadow boundary and, at twilight, vertices move up towards the lit air;
  where the Sun is below a vertex's horizon, half of the scattering directions are drawn from
  a band just above the sunward horizon (the twilight arch that lights the shadowed air),
  mixed with the phase function by the balance heuristic (defensive mixture, Hesterberg 1995).
* Spectral MIS: one path serves every wavelength. Each path samples with the coefficients of a
  "hero" wavelength (cycled over the paths) and every wavelength is weighted with the
  one-sample balance heuristic f_λ / mean_k p_k (Veach 1997 §9.2; Wilkie et al. 2014, "Hero
  wavelength spectral sampling").
* Mie directions are sampled from Henyey-Greenstein with the same g (PBRT 3rd ed. §15.2.3);
  the ratio Cornette-Shanks / HG = 3(1+μ²)/(2(2+g²)) is bounded, so the weights stay bounded.
  Rayleigh directions are sampled exactly by inverting its CDF (a cubic, solved in closed form).
* Ground: Lambertian, BRDF = albedo/π, cosine-weighted continuation (PBRT §13.6.3).
* Russian roulette with survival probability min(1, max_λ throughput) (PBRT §13.7).

Optical depth quadrature
------------------------
Along a ray from radius r with direction cosine μ, let r_p = r·sqrt(1-μ²) be the radius of the
perigee and s the signed distance from it. With the substitution
z = sign(s)·sqrt(sqrt(r_p² + s²) - r_p) (the square root of the height above the perigee,
signed), s = z·sqrt(2 r_p + z²), ds/dz = 2(r_p + z²)/sqrt(2 r_p + z²), the radius is
r_p + z² and the integrand ρ(r_p + z² - R_b)·ds/dz is smooth across the perigee (no square-root
singularity, unlike the altitude variable), Gaussian-like for an exponential profile. We split
[z_0, z_1] in equal sub-intervals plus the altitudes where a density profile has a kink (layer
boundaries, clamping points of the ozone tent) and integrate each with Gauss-Legendre. Tests
check it against brute-force trapezoids in t to better than 1e-6 relative.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np
from numpy.typing import ArrayLike

from skydome.atmosphere.params import AtmosphereParams, DensityLayer, DensityProfile
from skydome.errors import ParameterError
from skydome.physics.phase import cornette_shanks as cornette_shanks_phase
from skydome.physics.phase import henyey_greenstein as _hg_phase
from skydome.physics.phase import rayleigh_phase, sample_hg

__all__ = [
    "MCOrders",
    "cornette_shanks_phase",
    "direct_ground_irradiance",
    "ground_radiance_mc",
    "ground_irradiance_mc",
    "optical_depth",
    "rayleigh_phase",
    "sky_radiance_mc",
    "sky_radiance_mc_orders",
    "single_scattering_quadrature",
    "sun_direction",
]

# Quadrature settings. Segments for free-path sampling: N_SUB equal sub-intervals in z (plus
# kinks), each with an N_GL-point Gauss-Legendre rule; sun rays (total only) use NEE_SUB/NEE_GL.
SEG_SUB = 24
SEG_GL = 4
PARTIAL_GL = 6
NEE_SUB = 8
NEE_GL = 8
#: Paths processed together (memory is about 0.5 kB x SEG_SUB x SEG_GL per path).
CHUNK_PATHS = 8192
#: Order bins kept by the tracer: orders 1..N_ORDER_BINS-1 separately, the last bin >= that.
N_ORDER_BINS = 8
_HUGE_ORDER = 10_000
#: Guided distance sampling: floor of the guide (x its maximum) for NEE and for vertices.
NEE_GUIDE_FLOOR = 0.01
VERTEX_GUIDE_FLOOR = 0.05
SUN_TABLE_NU = 48
SUN_TABLE_NX = 96
#: Twilight direction guide (used where the Sun is below BAND_SUN_ELEVATION_MAX locally):
#: mixture weight, elevation range and scale, azimuthal concentration.
GUIDE_ALPHA = 0.5
BAND_SUN_ELEVATION_MAX = math.radians(2.0)
BAND_E_LO = math.radians(-6.0)
BAND_E_HI = math.radians(40.0)
BAND_E_SCALE = math.radians(8.0)
BAND_RHO = 0.6

# --------------------------------------------------------------------------------------------
# Sampling (the phase functions and HG's sampling: skydome.physics.phase)
# --------------------------------------------------------------------------------------------


def _horizon_frame(up: np.ndarray, sun: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sine of the Sun's elevation at vertices with zenith ``up`` and the horizontal unit
    vectors towards the Sun's azimuth (a) and 90° to its left (b)."""
    su = np.einsum("ij,ij->i", sun, up)
    a = sun - su[:, None] * up
    an = np.linalg.norm(a, axis=1)
    bad = an < 1e-9  # Sun at the zenith or nadir: any horizontal axis will do
    if np.any(bad):
        alt = np.where(np.abs(up[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        alt = alt - np.einsum("ij,ij->i", alt, up)[:, None] * up
        a = np.where(bad[:, None], alt, a)
        an = np.linalg.norm(a, axis=1)
    a = a / an[:, None]
    return su, a, np.cross(up, a)


def _band_sample(
    up: np.ndarray, a: np.ndarray, b: np.ndarray, xi_e: np.ndarray, xi_az: np.ndarray
) -> np.ndarray:
    """Directions from the twilight guide: elevation e in [BAND_E_LO, BAND_E_HI] with density
    ∝ exp(-(e - BAND_E_LO)/BAND_E_SCALE), azimuth from the Sun's wrapped-Cauchy(BAND_RHO)."""
    span = BAND_E_HI - BAND_E_LO
    e = BAND_E_LO - BAND_E_SCALE * np.log1p(-xi_e * -math.expm1(-span / BAND_E_SCALE))
    k = (1.0 - BAND_RHO) / (1.0 + BAND_RHO)
    phi = 2.0 * np.arctan(k * np.tan(math.pi * (xi_az - 0.5)))
    ce = np.cos(e)
    out = (ce * np.cos(phi))[:, None] * a + (ce * np.sin(phi))[:, None] * b
    return out + np.sin(e)[:, None] * up


def _band_pdf(up: np.ndarray, a: np.ndarray, b: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Solid-angle density (sr^-1) of :func:`_band_sample` for directions w."""
    e = np.arcsin(np.clip(np.einsum("ij,ij->i", w, up), -1.0, 1.0))
    span = BAND_E_HI - BAND_E_LO
    pe = np.exp(-(e - BAND_E_LO) / BAND_E_SCALE) / (
        BAND_E_SCALE * -math.expm1(-span / BAND_E_SCALE)
    )
    phi = np.arctan2(np.einsum("ij,ij->i", w, b), np.einsum("ij,ij->i", w, a))
    rho = BAND_RHO
    paz = (1.0 - rho * rho) / (2.0 * math.pi * (1.0 + rho * rho - 2.0 * rho * np.cos(phi)))
    inside = (e >= BAND_E_LO) & (e <= BAND_E_HI)
    return np.where(inside, pe * paz / np.maximum(np.cos(e), 1e-12), 0.0)


def _sample_rayleigh_mu(xi: np.ndarray) -> np.ndarray:
    """Exact inverse of the Rayleigh CDF F(μ) = 1/2 + 3/8(μ + μ³/3).

    μ³ + 3μ = 8ξ - 4 = 2q has the single real root μ = u - 1/u with u³ = q + sqrt(q² + 1).
    """
    q = 4.0 * xi - 2.0
    u = np.cbrt(q + np.sqrt(q * q + 1.0))
    return np.clip(u - 1.0 / u, -1.0, 1.0)


def _around(n: np.ndarray, mu: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Unit vectors at cosine ``mu`` and azimuth ``phi`` about unit vectors ``n`` (N, 3).

    Orthonormal basis: Duff et al. 2017, "Building an Orthonormal Basis, Revisited" (JCGT).
    """
    nx, ny, nz = n[:, 0], n[:, 1], n[:, 2]
    sign = np.where(nz >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + nz)
    b = nx * ny * a
    b1 = np.stack([1.0 + sign * nx * nx * a, sign * b, -sign * nx], axis=1)
    b2 = np.stack([b, sign + ny * ny * a, -ny], axis=1)
    st = np.sqrt(np.maximum(0.0, 1.0 - mu * mu))
    out = (st * np.cos(phi))[:, None] * b1 + (st * np.sin(phi))[:, None] * b2 + mu[:, None] * n
    return out / np.linalg.norm(out, axis=1, keepdims=True)


def sun_direction(sun_zenith_rad: float) -> np.ndarray:
    """Unit vector towards the Sun in the ENU frame: azimuth 90° (east), zenith ``θs``."""
    return np.array([math.sin(sun_zenith_rad), 0.0, math.cos(sun_zenith_rad)])


# --------------------------------------------------------------------------------------------
# The medium: densities, coefficients and optical depths
# --------------------------------------------------------------------------------------------


def _layer_terms(layer: DensityLayer) -> tuple[float, float, float, float]:
    return (layer.exp_term, layer.exp_scale_per_m, layer.linear_per_m, layer.constant)


def _eval_layer(terms: tuple[float, float, float, float], h: np.ndarray) -> np.ndarray:
    e, s, lin, c = terms
    d = np.full(h.shape, c) if lin == 0.0 else lin * h + c
    if e != 0.0:
        d = d + e * np.exp(s * h)
    return np.clip(d, 0.0, 1.0, out=d)


#: A tabulated profile's sample is a kink when its log-slope changes there by more than this
#: over the shorter adjoining gap (0.1 % of density), or when it or a neighbour is 0.
TABLE_KINK_LOG_SLOPE = 1e-3


def _table_kinks(profile: DensityProfile, top_m: float) -> list[float]:
    """Sample altitudes (m) in (0, top) where a tabulated profile bends: the quadrature nodes.

    Between samples the density is one exponential (or linear next to a 0), so the samples
    are its only kinks; those where the slope of ln(density) barely changes (a table sampled
    finely from a smooth profile) are left out, which keeps the ray quadrature's node count
    near that of a layered profile (the US Standard Atmosphere 1976 at 500 m steps keeps 9
    of its 199 inner samples: the tropopause changes the slope by 1.5e-2 per gap, its smooth
    layers by under 1e-3).
    """
    h = np.asarray(profile.altitudes_m)
    v = np.asarray(profile.values)
    zero = v == 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = np.diff(np.log(np.where(zero, 1.0, v))) / np.diff(h)
    gap = np.minimum(np.diff(h)[:-1], np.diff(h)[1:])
    bend = np.abs(np.diff(slope)) * gap > TABLE_KINK_LOG_SLOPE
    bend |= zero[1:-1] | zero[:-2] | zero[2:]
    return [float(x) for x in h[1:-1][bend] if 0.0 < x < top_m]


def _profile_kinks(profile: DensityProfile, top_m: float) -> list[float]:
    """Altitudes (m) in (0, top) where a profile is not smooth: layer boundary, clamping points."""
    if profile.is_tabulated:
        return _table_kinks(profile, top_m)
    lo, hi = profile.layers
    out: list[float] = []
    if lo.width_m > 0.0:
        out.append(lo.width_m)
    for layer, a, b in ((lo, 0.0, lo.width_m), (hi, lo.width_m, math.inf)):
        if layer is lo and lo.width_m <= 0.0:
            continue
        e, s, lin, c = _layer_terms(layer)
        for v in (0.0, 1.0):
            h = None
            if e == 0.0 and lin != 0.0:
                h = (v - c) / lin
            elif lin == 0.0 and e != 0.0 and s != 0.0 and (v - c) / e > 0.0:
                h = math.log((v - c) / e) / s
            if h is not None and a < h < b:
                out.append(h)
    return [h for h in out if 0.0 < h < top_m]


@dataclass
class _Medium:
    """Per-wavelength coefficients of an atmosphere and fast density evaluation (float64)."""

    R_b: float
    R_t: float
    k_ext: np.ndarray  # (3, L): extinction per unit relative density: Rayleigh, Mie, ozone
    k_sca: np.ndarray  # (2, L): scattering: Rayleigh, Mie
    albedo: np.ndarray  # (L,)
    g: float
    profiles: tuple  # per profile: (lo_width, lo_terms, hi_terms), or (nan, profile, None)
    kink_radii: np.ndarray
    sun_tau_mean: np.ndarray | None = None  # (SUN_TABLE_NU, SUN_TABLE_NX), sampling aid only

    @classmethod
    def build(cls, params: AtmosphereParams, wavelengths_nm: ArrayLike) -> _Medium:
        wl = np.atleast_1d(np.asarray(wavelengths_nm, dtype=np.float64))
        if wl.ndim != 1 or wl.size == 0 or not np.all(np.isfinite(wl)) or wl.min() <= 0:
            raise ParameterError(
                f"wavelengths_nm must be a 1-D array of positive numbers, got {wavelengths_nm}"
            )
        if params.mie_phase is not None:
            raise ParameterError(
                f"{params.name}: the Monte Carlo reference samples one Cornette-Shanks phase "
                "function; this atmosphere's varies with wavelength (mie_phase)"
            )
        c = params.coefficients(wl)
        top = params.atmosphere_height_m
        profs = []
        kinks: list[float] = []
        for prof in (params.rayleigh_density, params.mie_density, params.absorption_density):
            if prof.is_tabulated:
                profs.append((math.nan, prof, None))  # evaluated by DensityProfile.density
            else:
                lo, hi = prof.layers
                profs.append((lo.width_m, _layer_terms(lo), _layer_terms(hi)))
            kinks += _profile_kinks(prof, top)
        med = cls(
            R_b=params.bottom_radius_m,
            R_t=params.top_radius_m,
            k_ext=np.stack(
                [c["rayleigh_scattering"], c["mie_extinction"], c["absorption_extinction"]]
            ),
            k_sca=np.stack([c["rayleigh_scattering"], c["mie_scattering"]]),
            albedo=np.asarray(c["ground_albedo"], dtype=np.float64),
            g=float(params.mie_g),
            profiles=tuple(profs),
            kink_radii=params.bottom_radius_m
            + np.unique(np.round(np.array(kinks, dtype=np.float64), 6)),
        )
        med._build_sun_table()
        return med

    def _build_sun_table(self) -> None:
        """Optical depth towards the Sun on a coarse (altitude, zenith cosine) grid.

        Used only to shape the NEE sampling density (a crude T_sun), never in an estimate.
        Grid: altitude h = H u², cosine μ = μ_h + (1 - μ_h) x² with μ_h the horizon.
        """
        u = np.linspace(0.0, 1.0, SUN_TABLE_NU)
        x = np.linspace(0.0, 1.0, SUN_TABLE_NX)
        r = self.R_b + (self.R_t - self.R_b) * u * u
        mu_h = -np.sqrt(np.maximum(0.0, 1.0 - (self.R_b / r) ** 2))
        mu = mu_h[:, None] + (1.0 - mu_h[:, None]) * x[None, :] ** 2
        rr = np.broadcast_to(r[:, None], mu.shape).ravel()
        cols = _columns_to_top(self, rr, mu.ravel(), 4, 6)
        tau = cols.T @ self.k_ext.mean(axis=1)
        self.sun_tau_mean = tau.reshape(SUN_TABLE_NU, SUN_TABLE_NX)

    def approx_sun_transmittance(
        self, r: np.ndarray, mu_s: np.ndarray, extend: bool = False
    ) -> np.ndarray:
        """Crude transmittance to the Sun by bilinear lookup, 0 below the horizon (or, with
        ``extend``, the grazing value at the horizon).

        Geometric mean over the wavelengths (one guide serves every wavelength's technique).
        """
        H = self.R_t - self.R_b
        u = np.sqrt(np.clip((r - self.R_b) / H, 0.0, 1.0)) * (SUN_TABLE_NU - 1)
        mu_h = -np.sqrt(np.maximum(0.0, 1.0 - (self.R_b / r) ** 2))
        x = np.sqrt(np.clip((mu_s - mu_h) / (1.0 - mu_h), 0.0, 1.0)) * (SUN_TABLE_NX - 1)
        iu = np.minimum(u.astype(np.intp), SUN_TABLE_NU - 2)
        ix = np.minimum(x.astype(np.intp), SUN_TABLE_NX - 2)
        fu, fx = u - iu, x - ix
        t = self.sun_tau_mean.ravel()
        k = iu * SUN_TABLE_NX + ix
        tau = (1 - fu) * ((1 - fx) * t[k] + fx * t[k + 1]) + fu * (
            (1 - fx) * t[k + SUN_TABLE_NX] + fx * t[k + SUN_TABLE_NX + 1]
        )
        return np.where((mu_s >= mu_h) | extend, np.exp(-tau), 0.0)

    @property
    def n_wl(self) -> int:
        return self.k_ext.shape[1]

    def densities(self, h: np.ndarray, which: int = 3) -> np.ndarray:
        """Relative densities (Rayleigh, Mie, ozone)[:which] at altitudes ``h`` (m): (which, *h.shape)."""
        out = np.empty((which, *h.shape))
        for i in range(which):
            width, lo, hi = self.profiles[i]
            if hi is None:
                out[i] = lo.density(h)
            elif width <= 0.0:
                out[i] = _eval_layer(hi, h)
            else:
                out[i] = np.where(h < width, _eval_layer(lo, h), _eval_layer(hi, h))
        return out


def _z_of_s(s: np.ndarray, r_p: np.ndarray) -> np.ndarray:
    """Signed sqrt of the height above the perigee at signed distance s from it (stable form)."""
    den = np.sqrt(r_p * r_p + s * s) + r_p
    return np.copysign(np.sqrt(s * s / np.maximum(den, 1e-300)), s)


def _s_of_z(z: np.ndarray, r_p: np.ndarray) -> np.ndarray:
    """Signed distance from the perigee, inverse of :func:`_z_of_s`."""
    return z * np.sqrt(2.0 * r_p + z * z)


@cache
def _gl(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [-1, 1]."""
    return np.polynomial.legendre.leggauss(n)


def _interval_columns(
    med: _Medium, r_p: np.ndarray, za: np.ndarray, zb: np.ndarray, n_gl: int
) -> np.ndarray:
    """Column densities ∫ρ ds (m) of the 3 profiles between z = za and zb: (3, *za.shape).

    ``r_p`` must broadcast against ``za``.
    """
    x, w = _gl(n_gl)
    mid = 0.5 * (za + zb)
    half = 0.5 * (zb - za)
    zq = mid[..., None] + half[..., None] * x
    q = zq * zq
    rp = r_p[..., None]
    rq = rp + q
    jac = 2.0 * rq / np.sqrt(np.maximum(2.0 * rp + q, 1e-300))  # ds/dz
    rho = med.densities(rq - med.R_b)
    return np.einsum("c...g,...g->c...", rho, jac * (half[..., None] * w))


def _segment_nodes(
    med: _Medium, r: np.ndarray, mu: np.ndarray, t_end: np.ndarray, n_sub: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Quadrature nodes of [0, t_end] along rays from radius r with direction cosine mu.

    Returns (r_p, s0, z): the perigee radius and the signed distance of the start from it
    (N,), and the sorted nodes z (N, M+1): ``n_sub`` equal sub-intervals plus the kinks.
    """
    r_p = r * np.sqrt(np.maximum(0.0, 1.0 - mu * mu))
    s0 = r * mu
    z0 = _z_of_s(s0, r_p)
    z1 = _z_of_s(s0 + t_end, r_p)
    u = np.linspace(0.0, 1.0, n_sub + 1)
    nodes = z0[:, None] + (z1 - z0)[:, None] * u
    if med.kink_radii.size:
        zk = np.sqrt(np.maximum(med.kink_radii[None, :] - r_p[:, None], 0.0))
        zk = np.clip(np.concatenate([-zk, zk], axis=1), z0[:, None], z1[:, None])
        nodes = np.sort(np.concatenate([nodes, zk], axis=1), axis=1)
    return r_p, s0, nodes


def _columns_total(
    med: _Medium,
    r: np.ndarray,
    mu: np.ndarray,
    t_end: np.ndarray,
    n_sub: int = NEE_SUB,
    n_gl: int = NEE_GL,
) -> np.ndarray:
    """Column densities (3, N) from radius r along direction cosine mu over distance t_end."""
    r_p, _, nodes = _segment_nodes(med, r, mu, t_end, n_sub)
    return _interval_columns(med, r_p[:, None], nodes[:, :-1], nodes[:, 1:], n_gl).sum(axis=-1)


def _node_columns(
    med: _Medium, r_p: np.ndarray, za: np.ndarray, zb: np.ndarray, n_gl: int
) -> np.ndarray:
    """Column densities (m) from the first node of a ray to each of its nodes: (3, ..., M+1).

    The ray's M consecutive intervals [za, zb] (..., M) in the perigee variable z are
    integrated by :func:`_interval_columns` and summed cumulatively (0 at the first node).
    """
    cols = _interval_columns(med, r_p, za, zb, n_gl)
    return np.concatenate([np.zeros((*cols.shape[:-1], 1)), np.cumsum(cols, axis=-1)], axis=-1)


def _distance_to_top(med: _Medium, r: np.ndarray, mu: np.ndarray) -> np.ndarray:
    """Distance (m) to the top of the atmosphere from radius r along direction cosine mu."""
    return -r * mu + np.sqrt(np.maximum(med.R_t * med.R_t - r * r * (1.0 - mu * mu), 0.0))


def _columns_to_top(
    med: _Medium, r: np.ndarray, mu: np.ndarray, n_sub: int = NEE_SUB, n_gl: int = NEE_GL
) -> np.ndarray:
    """Column densities (3, N) (m) from radius r along direction cosine mu to the top of the
    atmosphere (the ray must not hit the ground): the optical depth towards the Sun."""
    return _columns_total(med, r, mu, _distance_to_top(med, r, mu), n_sub, n_gl)


def _ground_hit(med: _Medium, r: np.ndarray, mu: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(hits, distance) to the ground sphere along rays (distance clamped >= 0)."""
    disc = med.R_b * med.R_b - r * r * (1.0 - mu * mu)
    hits = (mu < 0.0) & (disc >= 0.0)
    # t = -rμ - sqrt(disc), written as (r² - R_b²)/(-rμ + sqrt(disc)) to be exact at r = R_b
    den = -r * mu + np.sqrt(np.maximum(disc, 0.0))
    t = np.where(hits, (r - med.R_b) * (r + med.R_b) / np.where(hits & (den > 0), den, 1.0), 0.0)
    return hits, np.maximum(t, 0.0)


def _sun_columns(med: _Medium, r: np.ndarray, mu_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(visible, columns (3, N)) from radius r towards a Sun at direction cosine mu_s."""
    vis = (mu_s >= 0.0) | (r * r * (1.0 - mu_s * mu_s) >= med.R_b * med.R_b)
    cols = np.zeros((3, r.size))
    if np.any(vis):
        cols[:, vis] = _columns_to_top(med, r[vis], mu_s[vis])
    return vis, cols


def optical_depth(
    params: AtmosphereParams,
    wavelengths_nm: ArrayLike,
    radius_m: ArrayLike,
    mu: ArrayLike,
    distance_m: ArrayLike | None = None,
) -> np.ndarray:
    """Optical depth (dimensionless) along rays from ``radius_m`` with zenith cosine ``mu``.

    Over ``distance_m`` (default: to the top of the atmosphere). Arrays broadcast together;
    result shape ``(*broadcast_shape, n_wavelengths)``. Rays must not cross the ground.
    """
    med = _Medium.build(params, wavelengths_nm)
    r, m = np.broadcast_arrays(np.asarray(radius_m, float), np.asarray(mu, float))
    shape = r.shape
    r, m = r.ravel(), m.ravel()
    t = (
        _distance_to_top(med, r, m)
        if distance_m is None
        else np.broadcast_to(distance_m, shape).ravel()
    )
    cols = _columns_total(med, r, m, np.asarray(t, float))
    return (cols.T @ med.k_ext).reshape(*shape, med.n_wl)


# --------------------------------------------------------------------------------------------
# Path tracer
# --------------------------------------------------------------------------------------------


def _normalize_mis(wt: np.ndarray, ratio: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rescale so that ratio (p_λ / mean_k p_k of the path prefix) averages 1; wt follows."""
    m = ratio.mean(axis=1, keepdims=True)
    return wt / m, ratio / m


def _shadow_interval(
    pos: np.ndarray, d: np.ndarray, sun: np.ndarray, R_b: float, t_end: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Distances [a, b] along rays pos + t d (rows) inside the planet's shadow, clipped to
    [0, t_end]; a >= b when the ray stays lit.

    The shadow of a sphere lit by parallel rays is the half-cylinder
    {|y - (y·s)s| < R_b, y·s < 0}, a convex set, so its intersection with a ray is one interval.
    """
    ds = np.einsum("ij,ij->i", d, sun)
    ps = np.einsum("ij,ij->i", pos, sun)
    av = d - ds[:, None] * sun
    bv = pos - ps[:, None] * sun
    A = np.einsum("ij,ij->i", av, av)
    B = np.einsum("ij,ij->i", av, bv)
    C = np.einsum("ij,ij->i", bv, bv) - R_b * R_b
    disc = B * B - A * C
    ok = (A > 1e-300) & (disc >= 0.0)
    sq = np.sqrt(np.maximum(disc, 0.0))
    Asafe = np.where(ok, A, 1.0)
    lo = np.where(ok, (-B - sq) / Asafe, np.where((A <= 1e-300) & (C < 0.0), -np.inf, np.inf))
    hi = np.where(ok, (-B + sq) / Asafe, np.where((A <= 1e-300) & (C < 0.0), np.inf, -np.inf))
    with np.errstate(divide="ignore", invalid="ignore"):
        t0 = -ps / ds
    # half-space y·s < 0
    lo = np.where(ds > 0.0, lo, np.where(ds < 0.0, np.maximum(lo, t0), lo))
    hi = np.where(ds > 0.0, np.minimum(hi, t0), hi)
    empty_half = (ds == 0.0) & (ps >= 0.0)
    lo = np.clip(np.where(empty_half, np.inf, lo), 0.0, t_end)
    hi = np.clip(np.where(empty_half, -np.inf, hi), 0.0, t_end)
    return lo, hi


def _interp_tau(tnodes: np.ndarray, tau: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Piecewise-linear optical depth (n, L) of the node table at distances t (n,)."""
    M = tnodes.shape[1] - 1
    n = np.arange(t.size)
    i = np.clip((tnodes[:, 1:] <= t[:, None]).sum(axis=1), 0, M - 1)
    ti, dt = tnodes[n, i], tnodes[n, i + 1] - tnodes[n, i]
    frac = np.clip((t - ti) / np.where(dt > 0, dt, 1.0), 0.0, 1.0)
    return tau[n, i, :] + frac[:, None] * (tau[n, i + 1, :] - tau[n, i, :])


def _sample_point(
    med: _Medium,
    pos: np.ndarray,
    d: np.ndarray,
    sun: np.ndarray,
    t_end: np.ndarray,
    tnodes: np.ndarray,
    tau: np.ndarray,
    hero: np.ndarray,
    rng: np.random.Generator,
    *,
    lit_only: bool,
    guided: bool,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Sample a distance along each segment, for NEE (``lit_only``) or for the next vertex.

    Density ∝ σ̃(t) T̃(t) g(t), with σ̃ T̃ the tabulated extinction and transmittance of the
    segment, restricted for NEE to the lit set (outside the planet's shadow). The guide g is
    a crude transmittance to the Sun from a coarse table (``guided``; else g = 1), constant on
    each node interval of the segment's optical-depth table and floored at a fraction of its
    maximum, so that the density is positive wherever the integrand can be. For NEE, g is
    taken at the middle of the lit part of the interval; for vertices it is extended into the
    shadow with the grazing value (the transmittance of the sunbeam that skims the ground
    below the point), which at twilight steers vertices up towards the lit air whose light
    fills the shadow. Sampling: an interval with probability ∝ its weight, then uniformly in
    the "mass coordinate" m(t) = ∫σ̃T̃ (constant across the shadow for NEE), inverted in
    closed form.

    Returns (rows, t, i, pdf): the rows with a nonzero mass, the distance, its node interval
    and the sampling density (rows, L) of every wavelength's technique (m^-1).
    """
    n = t_end.size
    ar = np.arange(n)
    ta, tb = tnodes[:, :-1], tnodes[:, 1:]
    if lit_only:
        sa, sb = _shadow_interval(pos, d, sun, med.R_b, t_end)
        shadowed = sb > sa
        sa = np.where(shadowed, sa, t_end)
        sb = np.where(shadowed, sb, t_end)
        tau_sa = _interp_tau(tnodes, tau, sa)
        tau_sb = _interp_tau(tnodes, tau, sb)
        m_sa = -np.expm1(-tau_sa)  # (n, L)
        tn = tnodes[..., None]
        m = np.where(
            tn <= sa[:, None, None],
            -np.expm1(-tau),
            np.where(
                tn < sb[:, None, None],
                m_sa[:, None, :],
                m_sa[:, None, :]
                + np.exp(-tau_sb)[:, None, :] * -np.expm1(-(tau - tau_sb[:, None, :])),
            ),
        )
        # middle of the (longer) lit piece of each interval
        p1 = np.clip(np.minimum(tb, sa[:, None]) - ta, 0.0, None)
        p2 = np.clip(tb - np.maximum(ta, sb[:, None]), 0.0, None)
        tm = np.where(p1 >= p2, ta + 0.5 * p1, np.maximum(ta, sb[:, None]) + 0.5 * p2)
    else:
        m_sa = np.full((n, tau.shape[2]), np.inf)
        tau_sb = np.zeros((n, tau.shape[2]))
        m = -np.expm1(-tau)
        tm = 0.5 * (ta + tb)
    dm = np.maximum(np.diff(m, axis=1), 0.0)  # (n, M, L)
    if guided:
        y = pos[:, None, :] + tm[..., None] * d[:, None, :]
        ry = np.linalg.norm(y, axis=2)
        mu_s = np.einsum("nkj,nj->nk", y, sun) / ry
        gcell = med.approx_sun_transmittance(ry, mu_s, extend=not lit_only)  # (n, M)
        floor = NEE_GUIDE_FLOOR if lit_only else VERTEX_GUIDE_FLOOR
        gcell = gcell + floor * gcell.max(axis=1, keepdims=True) + 1e-300
    else:
        gcell = np.ones(ta.shape)
    W = dm * gcell[..., None]
    S = W.sum(axis=1)  # (n, L)
    e = np.nonzero(S[ar, hero] > 0.0)[0]
    he = hero[e]
    re = np.arange(e.size)
    cdf = np.cumsum(W[e, :, he], axis=1)
    v = rng.random(e.size) * cdf[:, -1]
    M = ta.shape[1]
    j = np.minimum((cdf < v[:, None]).sum(axis=1), M - 1)
    m_lo, m_hi = m[e, j, he], m[e, j + 1, he]
    mm = m_lo + rng.random(e.size) * (m_hi - m_lo)
    msa_h, tsb_h = m_sa[e, he], tau_sb[e, he]
    tstar = np.where(
        mm <= msa_h,
        -np.log1p(-np.minimum(mm, 1.0)),
        tsb_h - np.log1p(-np.maximum(mm - msa_h, 0.0) * np.exp(tsb_h)),
    )
    # position inside interval j (τ linear in t there)
    tau_i = tau[e, j, :]
    dtau = tau[e, j + 1, :] - tau_i
    dth = dtau[re, he]
    frac = np.clip((tstar - tau_i[re, he]) / np.where(dth > 0, dth, 1.0), 0.0, 1.0)
    ti, dt = tnodes[e, j], tnodes[e, j + 1] - tnodes[e, j]
    t = ti + frac * dt
    sig = dtau / np.where(dt > 0, dt, 1.0)[:, None]
    pdf = sig * np.exp(-(tau_i + frac[:, None] * dtau)) * gcell[e, j][:, None]
    pdf /= np.maximum(S[e], 1e-300)  # S can round to 0 for a wavelength (then pdf is 0 too)
    return e, t, j, pdf


def _exact_transmittance(
    med: _Medium,
    sel: np.ndarray,
    i: np.ndarray,
    t: np.ndarray,
    s0: np.ndarray,
    r_p: np.ndarray,
    znodes: np.ndarray,
    tau: np.ndarray,
) -> np.ndarray:
    """Transmittance (n, L) from the segment start to distance t inside node interval i:
    the tabulated optical depth at node i plus a Gauss-Legendre partial column."""
    z_t = _z_of_s(s0[sel] + t, r_p[sel])
    part = _interval_columns(med, r_p[sel], znodes[sel, i], z_t, PARTIAL_GL)
    return np.exp(-(tau[sel, i, :] + part.T @ med.k_ext))


def _trace(
    med: _Medium,
    r0: np.ndarray,
    dirs: np.ndarray,
    suns: np.ndarray,
    rng: np.random.Generator,
    *,
    max_order: int,
    hero: np.ndarray,
    rr_scale: float = 1.0,
    guide_alpha: float = GUIDE_ALPHA,
    guided: bool = True,
) -> np.ndarray:
    """Trace backward paths; returns per-path contributions (N, L, N_ORDER_BINS).

    Paths start at (0, 0, r0) in directions ``dirs`` (N, 3); ``suns`` (N, 3) are the Sun
    directions per path. Each segment gets two independent samples ("decoupled" NEE):

    1. NEE: a point on the *lit* part of the segment (outside the planet's shadow), drawn with
       density ∝ σ̃ T̃ g restricted to it (:func:`_sample_point`), where the Sun is connected.
       This keeps twilight skies, lit only high up, from wasting samples in the shadow. If
       the segment ends on the ground (and it is not the camera ray), the sunlit ground there
       is connected too, weighted by the segment's transmittance.
    2. Continuation: the ground with probability T (segments that end there, except the
       camera ray), else a vertex over the whole segment with density ∝ σ̃ T̃ g (a forced
       collision), from which the path scatters (phase function, mixed with the twilight
       guide) or reflects (Lambertian) on.

    The camera ray (first segment) never reflects on the ground: the ground surface seen
    directly is excluded (module docstring).
    """
    n_all, L = r0.size, med.n_wl
    acc = np.zeros((n_all, L, N_ORDER_BINS))
    ids = np.arange(n_all)
    pos = np.zeros((n_all, 3))
    pos[:, 2] = r0
    d = np.array(dirs, dtype=np.float64)
    sun = np.array(suns, dtype=np.float64)
    hero = np.array(hero)
    wt = np.ones((n_all, L))
    ratio = np.ones((n_all, L))
    g = med.g

    for order in range(1, max_order + 1):
        n = ids.size
        if n == 0:
            break
        ar = np.arange(n)
        obin = min(order, N_ORDER_BINS) - 1
        r = np.linalg.norm(pos, axis=1)
        mu = np.einsum("ij,ij->i", pos, d) / r
        hits, t_g = _ground_hit(med, r, mu)
        t_end = np.where(hits, t_g, _distance_to_top(med, r, mu))
        ground_seg = hits & (order > 1)

        # --- tabulated optical depth along the segment -------------------------------------
        r_p, s0, znodes = _segment_nodes(med, r, mu, t_end, SEG_SUB)
        cum = _node_columns(med, r_p[:, None], znodes[:, :-1], znodes[:, 1:], SEG_GL)
        tau = np.einsum("cnm,cl->nml", cum, med.k_ext)  # (n, M+1, L)
        tnodes = _s_of_z(znodes, r_p[:, None]) - s0[:, None]
        tnodes[:, 0] = 0.0
        tnodes[:, -1] = t_end
        tnodes = np.clip(np.maximum.accumulate(tnodes, axis=1), 0.0, t_end[:, None])
        tau_max = tau[:, -1, :]

        # --- 1. NEE on the lit part of the segment ------------------------------------------
        e, t, i, pdf = _sample_point(
            med, pos, d, sun, t_end, tnodes, tau, hero, rng, lit_only=True, guided=guided
        )
        if e.size:
            T = _exact_transmittance(med, e, i, t, s0, r_p, znodes, tau)
            y = pos[e] + t[:, None] * d[e]
            ry = np.linalg.norm(y, axis=1)
            mu_s = np.einsum("ij,ij->i", y, sun[e]) / ry
            vis, scol = _sun_columns(med, ry, mu_s)
            rho = med.densities(ry - med.R_b, which=2)
            cos_sv = np.einsum("ij,ij->i", d[e], sun[e])
            f_sun = (
                med.k_sca[0][None, :] * (rho[0] * rayleigh_phase(cos_sv))[:, None]
                + med.k_sca[1][None, :] * (rho[1] * cornette_shanks_phase(cos_sv, g))[:, None]
            ) * (np.exp(-(scol.T @ med.k_ext)) * vis[:, None])
            den = (ratio[e] * pdf).mean(axis=1, keepdims=True)
            acc[ids[e], :, obin] += wt[e] * T * f_sun / den

        # sunlit ground at the end of the segment (deterministic given the segment)
        gsel = np.nonzero(ground_seg)[0]
        if gsel.size:
            gp = pos[gsel] + t_end[gsel, None] * d[gsel]
            gp *= (med.R_b / np.linalg.norm(gp, axis=1))[:, None]
            mu_s = np.einsum("ij,ij->i", gp, sun[gsel]) / med.R_b
            lit = mu_s > 0.0
            if np.any(lit):
                gl_ = gsel[lit]
                scol = _columns_to_top(med, np.full(gl_.size, med.R_b), mu_s[lit])
                contrib = (
                    wt[gl_]
                    * np.exp(-tau_max[gl_])
                    * med.albedo[None, :]
                    / math.pi
                    * mu_s[lit, None]
                    * np.exp(-(scol.T @ med.k_ext))
                )
                acc[ids[gl_], :, obin] += contrib
        if order == max_order:
            break

        # --- 2. continuation vertex ---------------------------------------------------------
        # ground (only for segments that end there, not the camera ray) with probability
        # T(t_end), else a collision from the guided density
        t_gnd = np.exp(-tau_max)  # (n, L)
        to_ground = ground_seg & (rng.random(n) < t_gnd[ar, hero])
        cand = np.nonzero(~to_ground)[0]
        e, t, i, pdf = _sample_point(
            med, pos[cand], d[cand], sun[cand], t_end[cand], tnodes[cand], tau[cand],
            hero[cand], rng, lit_only=False, guided=guided,
        )  # fmt: skip
        c = cand[e]
        pdf *= np.where(ground_seg[c, None], -np.expm1(-tau_max[c]), 1.0)
        coll = np.zeros(n, dtype=bool)
        coll[c] = True
        live = coll | to_ground
        ratio[c] *= pdf
        wt[c] *= _exact_transmittance(med, c, i, t, s0, r_p, znodes, tau)
        new_pos = pos.copy()
        new_pos[c] = pos[c] + t[:, None] * d[c]
        gidx = np.nonzero(to_ground)[0]
        tg = np.exp(-tau_max[gidx])
        ratio[gidx] *= tg
        wt[gidx] *= tg
        new_pos[gidx] = pos[gidx] + t_end[gidx, None] * d[gidx]
        wt = np.where(live[:, None], wt, 0.0)
        ratio = np.where(live[:, None], ratio, 1.0)
        # keep vertices inside the shell despite rounding
        rn = np.linalg.norm(new_pos, axis=1)
        new_pos *= (np.clip(rn, med.R_b, med.R_t) / rn)[:, None]
        new_pos[gidx] *= (med.R_b / np.linalg.norm(new_pos[gidx], axis=1))[:, None]
        pos = new_pos

        ry = np.linalg.norm(pos, axis=1)
        rho = med.densities(ry - med.R_b, which=2)
        xi1, xi2, xi3 = rng.random(n), rng.random(n), rng.random(n)
        phi = 2.0 * math.pi * xi2
        sr = med.k_sca[0][None, :] * rho[0][:, None]
        sm = med.k_sca[1][None, :] * rho[1][:, None]
        p_ray = sr / np.maximum(sr + sm, 1e-300)  # (n, L)
        use_ray = rng.random(n) < p_ray[ar, hero]
        mu_ph = np.where(use_ray, _sample_rayleigh_mu(xi1), sample_hg(g, xi1))
        new_d = _around(d, mu_ph, phi)
        if guide_alpha > 0.0:
            # defensive mixture with the twilight guide where the Sun is below the local
            # horizon (module docstring)
            up = pos / ry[:, None]
            su, ha, hb = _horizon_frame(up, sun)
            alpha = np.where(su < math.sin(BAND_SUN_ELEVATION_MAX), guide_alpha, 0.0)
            use_guide = rng.random(n) < alpha
            new_d = np.where(use_guide[:, None], _band_sample(up, ha, hb, xi1, xi2), new_d)
            new_d /= np.linalg.norm(new_d, axis=1, keepdims=True)
        mu_new = np.clip(np.einsum("ij,ij->i", d, new_d), -1.0, 1.0)
        ph_r = rayleigh_phase(mu_new)[:, None]
        f_dir = sr * ph_r + sm * cornette_shanks_phase(mu_new, g)[:, None]
        pdf_dir = p_ray * ph_r + (1.0 - p_ray) * _hg_phase(mu_new, g)[:, None]
        if guide_alpha > 0.0:
            pb = _band_pdf(up, ha, hb, new_d)
            pdf_dir = (1.0 - alpha)[:, None] * pdf_dir + (alpha * pb)[:, None]
        gdir = _around(pos / ry[:, None], np.sqrt(xi1), phi)  # cosine-weighted (PBRT §13.6.3)
        tg_ = to_ground[:, None]
        d = np.where(tg_, gdir, new_d)
        wt = np.where(tg_, wt * med.albedo[None, :], wt * f_dir)
        ratio = np.where(tg_, ratio, ratio * pdf_dir)
        wt, ratio = _normalize_mis(wt, ratio)

        # --- Russian roulette (PBRT §13.7) ---------------------------------------------------
        q = np.minimum(1.0, rr_scale * wt.max(axis=1))
        keep = live & (xi3 < q)
        wt[keep] /= q[keep, None]
        ids, pos, d, sun, hero = ids[keep], pos[keep], d[keep], sun[keep], hero[keep]
        wt, ratio = wt[keep], ratio[keep]
    return acc


def _check_common(
    params: AtmosphereParams, camera_altitude_m: float, sun_zenith_rad: float
) -> float:
    if not isinstance(params, AtmosphereParams):
        raise ParameterError(f"params must be an AtmosphereParams, got {type(params).__name__}")
    h = float(camera_altitude_m)
    if not (0.0 <= h < params.atmosphere_height_m):
        raise ParameterError(
            f"camera_altitude_m = {camera_altitude_m} m is outside [0, {params.atmosphere_height_m}) m"
        )
    if not (0.0 <= float(sun_zenith_rad) <= math.pi):
        raise ParameterError(f"sun_zenith_rad = {sun_zenith_rad} is outside [0, π]")
    return h


def _check_dirs(view_dirs: ArrayLike) -> np.ndarray:
    v = np.atleast_2d(np.asarray(view_dirs, dtype=np.float64))
    if v.ndim != 2 or v.shape[1] != 3 or not np.all(np.isfinite(v)):
        raise ParameterError(f"view_dirs must have shape (n, 3) and be finite, got shape {v.shape}")
    n = np.linalg.norm(v, axis=1)
    if np.any(n < 1e-12):
        raise ParameterError("view_dirs contains a zero vector")
    return v / n[:, None]


@dataclass(frozen=True)
class MCOrders:
    """Monte Carlo sky radiance per unit solar irradiance (sr^-1), cumulative over orders.

    ``radiance[..., k]`` and ``stderr[..., k]`` include orders 1..k+1 for k < N_ORDER_BINS-1;
    the last entry includes every order. Shapes (n_views, n_wavelengths, N_ORDER_BINS).
    """

    radiance: np.ndarray
    stderr: np.ndarray
    n_paths: int

    @property
    def total(self) -> np.ndarray:
        return self.radiance[..., -1]

    @property
    def total_stderr(self) -> np.ndarray:
        return self.stderr[..., -1]


def sky_radiance_mc_orders(
    params: AtmosphereParams,
    wavelengths_nm: ArrayLike,
    camera_altitude_m: float,
    sun_zenith_rad: float,
    view_dirs: ArrayLike,
    *,
    orders: int | None = None,
    n_paths: int = 4096,
    seed: int = 0,
    rr_scale: float = 1.0,
) -> MCOrders:
    """Like :func:`sky_radiance_mc` but returns the cumulative radiance per order (MCOrders)."""
    h = _check_common(params, camera_altitude_m, sun_zenith_rad)
    v = _check_dirs(view_dirs)
    max_order = _HUGE_ORDER if orders is None else int(orders)
    if max_order < 1:
        raise ParameterError(f"orders = {orders} must be >= 1 (or None for all orders)")
    n_paths = int(n_paths)
    if n_paths < 2:
        raise ParameterError(f"n_paths = {n_paths} must be >= 2")
    med = _Medium.build(params, wavelengths_nm)
    L = med.n_wl
    sun = sun_direction(float(sun_zenith_rad))
    r0 = params.bottom_radius_m + h
    rng = np.random.default_rng(seed)
    n_views = v.shape[0]
    total = n_views * n_paths
    s1 = np.zeros((n_views, L, N_ORDER_BINS))
    s2 = np.zeros_like(s1)
    for start in range(0, total, CHUNK_PATHS):
        k = np.arange(start, min(start + CHUNK_PATHS, total))
        view, j = np.divmod(k, n_paths)
        acc = _trace(
            med,
            np.full(k.size, r0),
            v[view],
            np.broadcast_to(sun, (k.size, 3)),
            rng,
            max_order=max_order,
            hero=j % L,
            rr_scale=rr_scale,
        )
        cacc = np.cumsum(acc, axis=2)
        np.add.at(s1, view, cacc)
        np.add.at(s2, view, cacc * cacc)
    mean = s1 / n_paths
    var = np.maximum(s2 / n_paths - mean * mean, 0.0) * n_paths / (n_paths - 1)
    stderr = np.sqrt(var / n_paths)
    if orders is not None and max_order < N_ORDER_BINS:
        # bins above max_order repeat the last computed order
        mean[..., max_order:] = mean[..., max_order - 1 : max_order]
        stderr[..., max_order:] = stderr[..., max_order - 1 : max_order]
    return MCOrders(radiance=mean, stderr=stderr, n_paths=n_paths)


def sky_radiance_mc(
    params: AtmosphereParams,
    wavelengths_nm: ArrayLike,
    camera_altitude_m: float,
    sun_zenith_rad: float,
    view_dirs: ArrayLike,
    *,
    orders: int | None = None,
    n_paths: int = 4096,
    seed: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """Sky radiance per unit solar irradiance by backward Monte Carlo path tracing.

    Parameters
    ----------
    params:
        The atmosphere.
    wavelengths_nm:
        Wavelengths (nm), shape (n_wavelengths,). One set of paths serves all of them
        (hero-wavelength spectral MIS).
    camera_altitude_m:
        Camera altitude above the ground sphere (m), in [0, top).
    sun_zenith_rad:
        Solar zenith angle (rad) in [0, π]; the Sun is due east (azimuth 90°).
    view_dirs:
        Unit view directions (n_views, 3) in the camera's ENU frame (x east, y north, z up).
    orders:
        ``None`` for every scattering order, else the highest order included (1 = single).
    n_paths:
        Paths per view direction (a multiple of n_wavelengths balances the hero wavelengths).
    seed:
        Seed of the random generator (results are deterministic).

    Returns
    -------
    (radiance, stderr):
        Arrays (n_views, n_wavelengths) in sr^-1 per unit solar irradiance (W m^-2 nm^-1 at
        the top of the atmosphere); stderr is the standard error of the mean. The direct Sun
        and the radiance of the ground surface are excluded (module docstring).
    """
    res = sky_radiance_mc_orders(
        params, wavelengths_nm, camera_altitude_m, sun_zenith_rad, view_dirs,
        orders=orders, n_paths=n_paths, seed=seed,
    )  # fmt: skip
    return res.total, res.total_stderr


def ground_irradiance_mc(
    params: AtmosphereParams,
    wavelengths_nm: ArrayLike,
    sun_zenith_rad: ArrayLike,
    *,
    orders: int | None = None,
    n_paths: int = 16384,
    seed: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """Diffuse (sky) irradiance on a horizontal ground plane per unit solar irradiance.

    E_d = ∫_{upper hemisphere} L(ω) cos θ dω, estimated as π·mean(L) over cosine-weighted
    view directions. ``sun_zenith_rad`` may be a scalar (result (n_wavelengths,)) or an array
    of zenith angles, one per path (for integrals over the planet; result is then the average
    over those paths). Every order is included (ground-atmosphere interreflections too); the
    direct beam is :func:`direct_ground_irradiance`. Returns (irradiance, stderr),
    dimensionless (W m^-2 per W m^-2 of solar irradiance at the top of the atmosphere).
    """
    _check_common(params, 0.0, 0.0)
    med = _Medium.build(params, wavelengths_nm)
    L = med.n_wl
    max_order = _HUGE_ORDER if orders is None else int(orders)
    rng = np.random.default_rng(seed)
    th = np.asarray(sun_zenith_rad, dtype=np.float64)
    per_path = th.ndim > 0
    n_paths = th.size if per_path else int(n_paths)
    if np.any((th < 0) | (th > math.pi)):
        raise ParameterError("sun_zenith_rad must lie in [0, π]")
    s1 = np.zeros(L)
    s2 = np.zeros(L)
    for start in range(0, n_paths, CHUNK_PATHS):
        k = np.arange(start, min(start + CHUNK_PATHS, n_paths))
        xi1, xi2 = rng.random(k.size), rng.random(k.size)
        dirs = _around(np.tile([0.0, 0.0, 1.0], (k.size, 1)), np.sqrt(xi1), 2 * math.pi * xi2)
        tz = th.ravel()[k] if per_path else np.full(k.size, float(th))
        suns = np.stack([np.sin(tz), np.zeros(k.size), np.cos(tz)], axis=1)
        acc = _trace(med, np.full(k.size, params.bottom_radius_m), dirs, suns, rng,
                     max_order=max_order, hero=k % L)  # fmt: skip
        x = math.pi * acc.sum(axis=2)
        s1 += x.sum(axis=0)
        s2 += (x * x).sum(axis=0)
    mean = s1 / n_paths
    var = np.maximum(s2 / n_paths - mean * mean, 0.0) * n_paths / (n_paths - 1)
    return mean, np.sqrt(var / n_paths)


def direct_ground_irradiance(
    params: AtmosphereParams, wavelengths_nm: ArrayLike, sun_zenith_rad: ArrayLike
) -> np.ndarray:
    """Direct solar irradiance on horizontal ground per unit solar irradiance: cos θs·T(θs).

    Zero when the Sun is below the horizon (the solar disk is treated as a point).
    Shape ``(*np.shape(sun_zenith_rad), n_wavelengths)``.
    """
    th = np.asarray(sun_zenith_rad, dtype=np.float64)
    mu = np.cos(th)
    tau = optical_depth(params, wavelengths_nm, params.bottom_radius_m, np.maximum(mu, 0.0))
    return np.where((mu > 0.0)[..., None], mu[..., None] * np.exp(-tau), 0.0)


def ground_radiance_mc(
    params: AtmosphereParams,
    wavelengths_nm: ArrayLike,
    camera_altitude_m: float,
    sun_zenith_rad: float,
    view_dirs: ArrayLike,
    *,
    n_paths: int = 16384,
    seed: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """Radiance of the Lambertian ground itself as the camera sees it, per unit solar irradiance.

    For a view ray that hits the ground at q: T(x, q)·albedo(λ)/π·(E_dir + E_sky)(θ_q), with
    θ_q the Sun's zenith angle at q (the planet is a sphere, so q's irradiance is that of a
    camera at 0 m under a Sun at θ_q), E_dir from :func:`direct_ground_irradiance` (a point
    Sun), E_sky from :func:`ground_irradiance_mc` (every order, ground-air interreflections
    included; an independent seed per view, from ``SeedSequence([seed, view])``) and T the
    transmittance from :func:`optical_depth`. Rays that miss the ground get 0. Added to
    :func:`sky_radiance_mc` (the air in front of the ground) it gives all the light a camera
    receives along a ground ray. Same conventions as :func:`sky_radiance_mc`; returns
    (radiance, stderr), each (n_views, n_wavelengths) in sr^-1; the standard error is that of
    E_sky (the other factors are deterministic).
    """
    h = _check_common(params, camera_altitude_m, sun_zenith_rad)
    v = _check_dirs(view_dirs)
    med = _Medium.build(params, wavelengths_nm)
    sun = sun_direction(float(sun_zenith_rad))
    r = params.bottom_radius_m + h
    hits, t_ground = _ground_hit(med, np.full(v.shape[0], r), v[:, 2])
    out = np.zeros((v.shape[0], med.n_wl))
    err = np.zeros_like(out)
    for i in np.nonzero(hits)[0]:
        q = np.array([0.0, 0.0, r]) + t_ground[i] * v[i]
        zenith_q = math.acos(float(np.clip(q @ sun / np.linalg.norm(q), -1.0, 1.0)))
        view_seed = int(np.random.SeedSequence([seed, int(i)]).generate_state(1)[0])
        e_sky, e_sky_err = ground_irradiance_mc(
            params, wavelengths_nm, zenith_q, n_paths=n_paths, seed=view_seed
        )
        e_dir = direct_ground_irradiance(params, wavelengths_nm, zenith_q)
        tau = (
            optical_depth(params, wavelengths_nm, r, v[i, 2], t_ground[i]) if t_ground[i] > 0 else 0
        )
        k = np.exp(-tau) * med.albedo / math.pi
        out[i] = k * (e_dir + e_sky)
        err[i] = k * e_sky_err
    return out, err


# --------------------------------------------------------------------------------------------
# Deterministic single scattering
# --------------------------------------------------------------------------------------------


def _shadow_breaks(x: np.ndarray, v: np.ndarray, s: np.ndarray, R_b: float) -> list[float]:
    """Distances along x + t v where the ray crosses the boundary of the planet's shadow.

    The shadow is the half-cylinder {|y - (y·s)s| < R_b, y·s < 0}; returns up to 3 candidates
    (cylinder entry/exit and the plane y·s = 0), NaN where absent.
    """
    a = v - np.dot(v, s) * s
    b = x - np.dot(x, s) * s
    A, B, C = np.dot(a, a), np.dot(a, b), np.dot(b, b) - R_b * R_b
    out = [np.nan, np.nan, np.nan]
    disc = B * B - A * C
    if A > 0 and disc >= 0:
        out[0] = (-B - math.sqrt(disc)) / A
        out[1] = (-B + math.sqrt(disc)) / A
    vs = np.dot(v, s)
    if vs != 0:
        out[2] = -np.dot(x, s) / vs
    return out


def single_scattering_quadrature(
    params: AtmosphereParams,
    wavelengths_nm: ArrayLike,
    camera_altitude_m: float,
    sun_zenith_rad: float,
    view_dirs: ArrayLike,
    *,
    n_sub: int = 96,
    n_gl: int = 8,
) -> np.ndarray:
    """Single-scattering sky radiance per unit solar irradiance (sr^-1), deterministic.

    L1(x, v) = ∫_0^{t_end} T(x, y) [β_R ρ_R(y) p_R(v·s) + β_M ρ_M(y) p_M(v·s)] T_sun(y) V(y) dt
    with y = x + t v, t_end the distance to the ground or the top, T the transmittance along the
    view ray, T_sun to the top of the atmosphere towards the Sun and V = 0 inside the planet's
    shadow (Bruneton 2017 ComputeSingleScatteringIntegrand). Composite Gauss-Legendre in the
    perigee variable z (module docstring) with ``n_sub`` sub-intervals of ``n_gl`` points, split
    at the profile kinks and the shadow boundaries; T(x, y) by cumulative sub-interval columns
    plus a Gauss-Legendre partial column to each node. Same conventions as
    :func:`sky_radiance_mc`; returns (n_views, n_wavelengths).
    """
    h = _check_common(params, camera_altitude_m, sun_zenith_rad)
    vdirs = _check_dirs(view_dirs)
    med = _Medium.build(params, wavelengths_nm)
    s = sun_direction(float(sun_zenith_rad))
    r = params.bottom_radius_m + h
    x = np.array([0.0, 0.0, r])
    out = np.zeros((vdirs.shape[0], med.n_wl))
    for iv, v in enumerate(vdirs):
        mu = v[2]
        ra, ma = np.array([r]), np.array([mu])
        hits, t_g = _ground_hit(med, ra, ma)
        t_end = float(t_g[0] if hits[0] else _distance_to_top(med, ra, ma)[0])
        if t_end <= 0.0:
            continue
        r_p, s0, nodes = _segment_nodes(med, ra, ma, np.array([t_end]), n_sub)
        r_p, s0 = float(r_p[0]), float(s0[0])
        brk = [t for t in _shadow_breaks(x, v, s, med.R_b) if np.isfinite(t) and 0.0 < t < t_end]
        zb = _z_of_s(s0 + np.array(brk, dtype=float), r_p)
        zn = np.unique(np.concatenate([nodes[0], zb]))
        za_, zb_ = zn[:-1], zn[1:]
        cumc = _node_columns(med, np.array(r_p), za_, zb_, SEG_GL + 2)  # (3, M+1)
        xg, wg = _gl(n_gl)
        half = 0.5 * (zb_ - za_)
        zq = (0.5 * (za_ + zb_))[:, None] + half[:, None] * xg  # (M, G)
        part = _interval_columns(
            med, np.array(r_p), np.broadcast_to(za_[:, None], zq.shape), zq, n_gl
        )
        col_to = cumc[:, :-1, None] + part  # (3, M, G)
        T_view = np.exp(-np.einsum("cmg,cl->mgl", col_to, med.k_ext))
        q = zq * zq
        ry = r_p + q
        jac = 2.0 * ry / np.sqrt(np.maximum(2.0 * r_p + q, 1e-300))
        tq = _s_of_z(zq, r_p) - s0
        y = x[None, None, :] + tq[..., None] * v
        ryn = np.linalg.norm(y, axis=-1)
        mu_s = (y @ s) / ryn
        vis, scol = _sun_columns(med, ryn.ravel(), mu_s.ravel())
        T_sun = (np.exp(-(scol.T @ med.k_ext)) * vis[:, None]).reshape(*zq.shape, med.n_wl)
        rho = med.densities(ryn - med.R_b, which=2)
        cos_sv = float(v @ s)
        beta = rho[0][..., None] * med.k_sca[0] * rayleigh_phase(cos_sv) + rho[1][
            ..., None
        ] * med.k_sca[1] * cornette_shanks_phase(cos_sv, med.g)
        w = (half[:, None] * wg)[..., None] * jac[..., None]
        out[iv] = (w * T_view * beta * T_sun).sum(axis=(0, 1))
    return out
