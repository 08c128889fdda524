"""Mie theory (skydome.atmosphere.mie) against published values and exact limits, and the
Henyey-Greenstein lobe fit."""

from __future__ import annotations

import numpy as np
import pytest

from skydome.atmosphere import mie
from skydome.atmosphere.phase import MiePhaseLobes
from skydome.errors import ParameterError
from skydome.physics.phase import henyey_greenstein


def test_bohren_huffman_worked_example():
    # Bohren & Huffman (1983) Appendix A, BHMIE's sample run: a sphere of radius 0.525 um,
    # index 1.55 (non-absorbing) at 0.6328 um prints QSCA = QEXT = 3.10543, QBACK = 2.92534
    # (miepython 3.3.0 gives the same to 1e-12).
    x = 2.0 * np.pi * 0.525 / 0.6328
    s = mie.sphere_scattering(1.55, [x], [1.0, -1.0])
    assert s.q_ext[0] == pytest.approx(3.10543, abs=1e-5)
    assert s.q_sca[0] == pytest.approx(3.10543, abs=1e-5)
    q_back = 4.0 * abs(s.s1[0, 1]) ** 2 / x**2  # BH eq. 4.82
    assert q_back == pytest.approx(2.92534, abs=1e-5)


@pytest.mark.parametrize("x", [150.0, 1000.0, 5000.0, 20000.0])
def test_first_coefficients_of_large_spheres_match_their_closed_form(x):
    # a_1 and b_1 from the closed-form Riccati-Bessel functions of order 1 (Bohren & Huffman
    # eqs. 4.53, 4.88): the downward recurrence of D_n must have forgotten its start by n = 1
    # (started at |mx| + 16 it erred by 4 % at x = 1000: rain drops' size parameters are
    # 1000-30000)
    m = 1.333

    def psi(z):
        return np.sin(z) / z - np.cos(z)

    def dpsi(z):
        return np.cos(z) / z - np.sin(z) / z**2 + np.sin(z)

    def xi(z):
        return psi(z) - 1j * (np.cos(z) / z + np.sin(z))

    def dxi(z):
        return dpsi(z) - 1j * (-np.sin(z) / z - np.cos(z) / z**2 + np.cos(z))

    mx = m * x
    a1 = (m * psi(mx) * dpsi(x) - psi(x) * dpsi(mx)) / (m * psi(mx) * dxi(x) - xi(x) * dpsi(mx))
    b1 = (psi(mx) * dpsi(x) - m * psi(x) * dpsi(mx)) / (psi(mx) * dxi(x) - m * xi(x) * dpsi(mx))
    a, b = mie.mie_coefficients(complex(m, 0.0), [x])
    assert abs(a[0, 0] - a1) < 1e-9 and abs(b[0, 0] - b1) < 1e-9


def test_rayleigh_limit():
    # x << 1: Q_sca = 8/3 x^4 |K|^2 and Q_abs = 4 x Im K, K = (m^2 - 1) / (m^2 + 2) (BH eqs.
    # 5.8, 5.11); the next terms are O(x^2) relative: 1e-4 at x = 0.01.
    m, x = 1.5 + 0.01j, 0.01
    k = (m * m - 1) / (m * m + 2)
    s = mie.sphere_scattering(m, [x], [1.0])
    assert s.q_sca[0] == pytest.approx(8.0 / 3.0 * x**4 * abs(k) ** 2, rel=1e-3)
    assert s.q_ext[0] - s.q_sca[0] == pytest.approx(4.0 * x * k.imag, rel=1e-3)


def test_large_sphere_extinction_paradox():
    # Q_ext -> 2 for large spheres (diffraction + geometric shadow); at x = 400 the
    # correction is of order x^(-2/3) ~ 2 %.
    s = mie.sphere_scattering(1.5 + 1e-3j, [400.0], [1.0])
    assert s.q_ext[0] == pytest.approx(2.0, abs=0.05)


def test_phase_function_integrates_to_one():
    th = np.radians(np.linspace(0.0, 180.0, 3601))
    p = mie.sphere_phase_function(1.5 + 0.001j, 20.0, np.cos(th))
    integral = 2.0 * np.pi * np.trapezoid(p * np.sin(th), th)
    assert integral == pytest.approx(1.0, rel=2e-3)  # trapezoid over the 0.05 deg grid


def test_gamma_distribution_has_its_effective_radius():
    # Hansen & Travis (1974): r_eff = <r^3> / <r^2>, v_eff = <(r - r_eff)^2 r^2> / (r_eff^2 <r^2>).
    r = np.geomspace(1e-3, 40.0, 20000)
    n = mie.gamma_size_distribution(1.71, 0.25, r)
    m2, m3 = np.trapezoid(n * r**2, r), np.trapezoid(n * r**3, r)
    r_eff = m3 / m2
    v_eff = np.trapezoid(n * r**2 * (r - r_eff) ** 2, r) / (r_eff**2 * m2)
    assert r_eff == pytest.approx(1.71, rel=1e-3)
    assert v_eff == pytest.approx(0.25, rel=1e-3)
    with pytest.raises(ParameterError):
        mie.gamma_size_distribution(1.0, 0.6, r)


def test_bulk_optics_of_small_absorbing_particles():
    # A distribution far below the wavelength scatters like Rayleigh: asymmetry ~ 0.
    mu = np.cos(np.radians(np.linspace(0.0, 180.0, 721)))
    b = mie.bulk_optics(1.5 + 0.01j, 10.0, 0.05, 0.1, mu)
    assert abs(b.asymmetry) < 0.01
    assert 0.0 < b.ssa < 1.0


def test_nnls_matches_least_squares_when_unconstrained_is_positive():
    rng = np.random.default_rng(3)
    a = rng.random((40, 5))
    x_true = np.array([0.5, 1.0, 2.0, 0.3, 1.5])
    b = a @ x_true
    np.testing.assert_allclose(mie.nnls(a, b), x_true, rtol=1e-9)
    # and clips what would be negative: the answer satisfies the KKT conditions
    b2 = a @ np.array([1.0, -2.0, 0.5, 0.0, 1.0])
    x = mie.nnls(a, b2)
    grad = a.T @ (b2 - a @ x)
    assert np.all(x >= 0.0)
    assert np.all(grad[x == 0.0] <= 1e-9) and np.allclose(grad[x > 0.0], 0.0, atol=1e-9)


def test_lobe_fit_recovers_a_mixture():
    th = np.radians(np.linspace(0.5, 170.0, 300))
    w_true = np.zeros(len(mie.HG_LOBES_G))
    w_true[[1, 5, 9]] = [0.5, 0.4, 0.1]
    phase = mie.hg_lobes(np.cos(th), w_true)
    np.testing.assert_allclose(mie.fit_hg_lobes(th, phase), w_true, atol=1e-8)


def test_mie_phase_lobes_validate_and_evaluate():
    lobes = MiePhaseLobes((0.9, 0.0), (400.0, 700.0), ((1.0, 0.0), (0.5, 0.5)))
    nu = np.array([1.0, 0.0, -1.0])
    p = lobes.phase(nu, [400.0, 550.0, 700.0])
    np.testing.assert_allclose(p[:, 0], henyey_greenstein(nu, 0.9))
    np.testing.assert_allclose(p[:, 1], 0.75 * henyey_greenstein(nu, 0.9) + 0.25 / (4 * np.pi))
    np.testing.assert_allclose(lobes.asymmetry([400.0, 700.0]), [0.9, 0.45])
    for bad in (
        dict(lobe_g=(1.0, 0.0)),
        dict(weights=((1.0, 0.0), (0.6, 0.6))),
        dict(weights=((1.2, -0.2), (0.5, 0.5))),
        dict(wavelengths_nm=(700.0, 400.0)),
    ):
        args = dict(lobe_g=(0.9, 0.0), wavelengths_nm=(400.0, 700.0),
                    weights=((1.0, 0.0), (0.5, 0.5)), **{})  # fmt: skip
        args.update(bad)
        with pytest.raises(ParameterError):
            MiePhaseLobes(**args)
