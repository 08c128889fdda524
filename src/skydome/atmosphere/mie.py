"""Mie scattering by spheres, and the bulk optics of a size distribution of them (float64).

Used offline, to derive the optical properties of an aerosol from its size distribution and
refractive index (``tools/build_mars_dust.py``): extinction and scattering efficiencies, the
single-scattering albedo and the phase function, and a fit of that phase function by Henyey-Greenstein
lobes, the form the shaders evaluate (``skydome.atmosphere.phase.MiePhaseLobes``).

The series are those of Bohren & Huffman (1983), *Absorption and Scattering of Light by Small
Particles*, ch. 4 (coefficients a_n, b_n eqs. 4.56-4.57 with the logarithmic derivative D_n of
sec. 4.8, downward recurrence; angular functions pi_n, tau_n eq. 4.47), summed to
n_stop = x + 4 x^(1/3) + 2 terms (Wiscombe 1980). The refractive index is m = n + i k, with
k >= 0 absorbing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from skydome.errors import ParameterError
from skydome.physics.phase import henyey_greenstein


def mie_coefficients(m: complex, x) -> tuple[np.ndarray, np.ndarray]:
    """Coefficients a_n, b_n (n = 1..N, rows) for size parameters ``x`` (columns).

    Terms beyond a sphere's own n_stop are zero.
    """
    x = np.atleast_1d(np.asarray(x, float))
    if np.any(x <= 0.0):
        raise ParameterError("Mie size parameters must be > 0")
    nstop = np.floor(x + 4.0 * np.cbrt(x) + 2.0).astype(int)
    n_max = int(nstop.max())
    mx = m * x
    # D_n(mx) = psi_n'(mx) / psi_n(mx), stable downwards from well past both n_stop and |mx|:
    # the recurrence forgets its start within ~|mx|^(1/3) terms past |mx| (started at |mx| + 16
    # its D_1 erred by 4e-4 at x = 150 and 4 % at x = 1000; at |mx| + 8 |mx|^(1/3), < 1e-12)
    z = float(np.abs(mx).max())
    n_start = int(max(n_max, z + 8.0 * np.cbrt(z))) + 16
    d = np.zeros((n_start + 1, x.size), complex)
    for n in range(n_start, 0, -1):
        d[n - 1] = n / mx - 1.0 / (d[n] + n / mx)
    # Riccati-Bessel psi_n(x) = x j_n(x), chi_n(x) = -x y_n(x), xi_n = psi_n - i chi_n, upwards.
    psi_2, psi_1 = np.cos(x), np.sin(x)
    chi_2, chi_1 = -np.sin(x), np.cos(x)
    xi_1 = psi_1 - 1j * chi_1
    a = np.zeros((n_max, x.size), complex)
    b = np.zeros((n_max, x.size), complex)
    with np.errstate(all="ignore"):  # chi overflows past n_stop for small x: those terms are 0
        for n in range(1, n_max + 1):
            psi = (2 * n - 1) / x * psi_1 - psi_2
            chi = (2 * n - 1) / x * chi_1 - chi_2
            xi = psi - 1j * chi
            da = d[n] / m + n / x
            db = m * d[n] + n / x
            keep = n <= nstop
            a[n - 1] = np.where(keep, (da * psi - psi_1) / (da * xi - xi_1), 0.0)
            b[n - 1] = np.where(keep, (db * psi - psi_1) / (db * xi - xi_1), 0.0)
            psi_2, chi_2 = psi_1, chi_1
            psi_1, chi_1, xi_1 = psi, chi, xi
    return a, b


def _angular_functions(n_max: int, cos_theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """pi_n(cos theta), tau_n(cos theta) for n = 1..n_max (rows)."""
    pi = np.zeros((n_max, cos_theta.size))
    tau = np.zeros((n_max, cos_theta.size))
    p_prev, p = np.zeros_like(cos_theta), np.ones_like(cos_theta)
    for n in range(1, n_max + 1):
        if n > 1:
            p_prev, p = p, ((2 * n - 1) * cos_theta * p - n * p_prev) / (n - 1)
        pi[n - 1] = p
        tau[n - 1] = n * cos_theta * p - (n + 1) * p_prev
    return pi, tau


@dataclass(frozen=True)
class SphereScattering:
    """Mie results per size parameter: efficiencies (dimensionless) and the amplitude
    functions S1, S2 at the requested cosines (rows: size parameters)."""

    q_ext: np.ndarray
    q_sca: np.ndarray
    s1: np.ndarray
    s2: np.ndarray


def sphere_scattering(m: complex, x, cos_theta) -> SphereScattering:
    """Mie efficiencies and amplitude functions of spheres of size parameters ``x``
    (2 pi r / lambda) and relative refractive index ``m`` (n + i k), at scattering-angle
    cosines ``cos_theta``."""
    x = np.atleast_1d(np.asarray(x, float))
    mu = np.atleast_1d(np.asarray(cos_theta, float))
    a, b = mie_coefficients(m, x)
    n = np.arange(1, a.shape[0] + 1, dtype=float)[:, None]
    q_ext = 2.0 / x**2 * np.sum((2 * n + 1) * (a + b).real, axis=0)
    q_sca = 2.0 / x**2 * np.sum((2 * n + 1) * (np.abs(a) ** 2 + np.abs(b) ** 2), axis=0)
    pi, tau = _angular_functions(a.shape[0], mu)
    c = (2 * n + 1) / (n * (n + 1))
    s1 = (c * a).T @ pi + (c * b).T @ tau
    s2 = (c * a).T @ tau + (c * b).T @ pi
    return SphereScattering(q_ext, q_sca, s1, s2)


def sphere_phase_function(m: complex, x: float, cos_theta) -> np.ndarray:
    """Phase function (sr^-1, integrating to 1 over the sphere) of one sphere:
    (|S1|^2 + |S2|^2) / (2 pi x^2 Q_sca)."""
    s = sphere_scattering(m, [x], cos_theta)
    return (np.abs(s.s1[0]) ** 2 + np.abs(s.s2[0]) ** 2) / (2.0 * np.pi * x**2 * s.q_sca[0])


@dataclass(frozen=True)
class BulkOptics:
    """Optics of a size distribution at one wavelength: mean cross-sections per particle
    (um^2), single-scattering albedo, phase function (sr^-1) at ``cos_theta``, and its
    asymmetry parameter (mean cosine)."""

    c_ext_um2: float
    c_sca_um2: float
    cos_theta: np.ndarray
    phase: np.ndarray

    @property
    def ssa(self) -> float:
        return self.c_sca_um2 / self.c_ext_um2

    @property
    def asymmetry(self) -> float:
        return float(_sphere_integral(self.cos_theta, self.phase * self.cos_theta))


def gamma_size_distribution(r_eff_um: float, v_eff: float, radii_um) -> np.ndarray:
    """The modified gamma distribution of Hansen & Travis (1974, eq. 2.56), relative number
    per unit radius: n(r) ∝ r^((1 - 3 v) / v) exp(-r / (r_eff v)), effective radius r_eff (um)
    and effective variance v (0 < v < 1/2)."""
    if not 0.0 < v_eff < 0.5:
        raise ParameterError(f"effective variance must be within (0, 0.5), got {v_eff}")
    r = np.asarray(radii_um, float)
    log_n = (1.0 - 3.0 * v_eff) / v_eff * np.log(r) - r / (r_eff_um * v_eff)
    return np.exp(log_n - log_n.max())


def bulk_optics(
    m: complex,
    wavelength_um: float,
    r_eff_um: float,
    v_eff: float,
    cos_theta,
    *,
    radii: int = 240,
) -> BulkOptics:
    """Mie optics of a gamma size distribution (:func:`gamma_size_distribution`) at one
    wavelength, integrated over ``radii`` log-spaced radii from r_eff / 40 to 8 r_eff."""
    r = np.geomspace(r_eff_um / 40.0, 8.0 * r_eff_um, radii)
    weight = gamma_size_distribution(r_eff_um, v_eff, r) * np.gradient(r)
    x = 2.0 * np.pi * r / wavelength_um
    mu = np.asarray(cos_theta, float)
    s = sphere_scattering(m, x, mu)
    area = np.pi * r**2 * weight
    c_ext = float(np.sum(area * s.q_ext) / np.sum(weight))
    c_sca = float(np.sum(area * s.q_sca) / np.sum(weight))
    # dC_sca/dOmega = (|S1|^2 + |S2|^2) / (2 k^2), k = 2 pi / lambda; P = <dC/dOmega> / <C_sca>.
    k = 2.0 * np.pi / wavelength_um
    intensity = (np.abs(s.s1) ** 2 + np.abs(s.s2) ** 2) / (2.0 * k**2)
    phase = np.sum(weight[:, None] * intensity, axis=0) / np.sum(weight) / c_sca
    return BulkOptics(c_ext, c_sca, mu, phase)


def _sphere_integral(cos_theta: np.ndarray, values: np.ndarray) -> float:
    """∫ values dOmega over the sphere, trapezoidal in cos theta (any order of the cosines)."""
    order = np.argsort(cos_theta)
    return float(2.0 * np.pi * np.trapezoid(values[order], cos_theta[order]))


#: The fixed asymmetries of the Henyey-Greenstein lobes an aerosol's phase function is fitted
#: with (:func:`fit_hg_lobes`): narrow lobes for a diffraction peak a few degrees wide (1 - g is
#: about a lobe's width in radians), broad ones for the side, and two backward ones.
HG_LOBES_G = (0.98, 0.96, 0.93, 0.89, 0.83, 0.74, 0.6, 0.4, 0.0, -0.4)


def fit_hg_lobes(theta_rad, phase, lobe_g=HG_LOBES_G) -> np.ndarray:
    """Non-negative weights w_j of Henyey-Greenstein lobes HG(g_j) whose sum best fits
    ``phase`` (sr^-1) at the angles ``theta_rad``, in relative error: minimises
    sum_i (sum_j w_j HG(theta_i, g_j) / P_i - 1)^2 with w_j >= 0 (Lawson & Hanson 1974 NNLS).
    The weights are then scaled to sum to 1, so the fit integrates to 1 like a phase function.
    """
    theta = np.asarray(theta_rad, float)
    p = np.asarray(phase, float)
    a = henyey_greenstein(np.cos(theta)[:, None], np.asarray(lobe_g)[None, :]) / p[:, None]
    w = nnls(a, np.ones_like(p))
    total = w.sum()
    if total <= 0.0:
        raise ParameterError("no non-negative mixture of the lobes fits this phase function")
    return w / total


def nnls(a: np.ndarray, b: np.ndarray, max_iterations: int = 500) -> np.ndarray:
    """min |a x - b| subject to x >= 0: the active-set algorithm of Lawson & Hanson (1974,
    *Solving Least Squares Problems*, ch. 23)."""
    m, n = a.shape
    x = np.zeros(n)
    passive = np.zeros(n, bool)
    for _ in range(max_iterations):
        grad = a.T @ (b - a @ x)
        if passive.all() or np.max(np.where(passive, -np.inf, grad)) <= 1e-12 * np.abs(b).sum():
            break
        passive[int(np.argmax(np.where(passive, -np.inf, grad)))] = True
        while True:
            z = np.zeros(n)
            z[passive] = np.linalg.lstsq(a[:, passive], b, rcond=None)[0]
            if np.all(z[passive] > 0.0):
                x = z
                break
            neg = passive & (z <= 0.0)
            alpha = np.min(x[neg] / (x[neg] - z[neg]))
            x = x + alpha * (z - x)
            passive &= x > 1e-15
            x[~passive] = 0.0
    return x


def hg_lobes(cos_theta, weights, lobe_g=HG_LOBES_G) -> np.ndarray:
    """sum_j w_j HG(cos theta, g_j) (sr^-1); ``weights`` (..., lobes) broadcast against the
    cosines' shape plus a trailing lobe axis."""
    mu = np.asarray(cos_theta, float)[..., None]
    return np.sum(np.asarray(weights) * henyey_greenstein(mu, np.asarray(lobe_g)), axis=-1)
