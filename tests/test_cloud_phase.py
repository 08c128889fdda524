"""The cloud droplet phase function (skydome.clouds.phase): the Mie table the renderer
scatters with (its published features, its truncation), the tabulated form (normalisation,
moments, sampling), the HG-lobe fit (normalisation, sampling, its published asymmetry), and
the tool that builds both packaged tables."""

from __future__ import annotations

from functools import cache
from importlib import resources

import numpy as np
import pytest

from skydome.clouds.phase import (
    CLOUD_PHASE,
    MIE_PHASE,
    MIE_PHASE_CSV,
    PEAK_FRACTION,
    PHASE_CSV,
    RENDER_PHASE,
    RENDER_PHASE_TEXELS,
    TRUNCATION_DEG,
    LobePhase,
    TabulatedPhase,
)
from skydome.errors import ParameterError
from tests.tools_module import load_tool


@cache
def _tool():
    return load_tool("build_cloud_phase")


@cache
def _mie():
    return _tool().mie_phase()  # (theta_deg, phase 1/sr, asymmetry), ~2 s


def _hg_cdf(mu, g):
    """P(cos theta < mu) of HG(g), from integrating (1 - g^2) / (2 (1 + g^2 - 2 g mu)^1.5)."""
    if abs(g) < 1e-9:
        return (mu + 1.0) / 2.0
    return (1.0 - g * g) / (2.0 * g) * (1.0 / np.sqrt(1.0 + g * g - 2.0 * g * mu) - 1.0 / (1.0 + g))


def test_normalised_over_the_sphere():
    # 2 pi int P sin(theta) dtheta by trapezoids on a theta grid that resolves the 0.3 deg
    # wide peak (1e-5 rad steps near 0): the quadrature error is < 1e-5.
    th = np.concatenate([np.linspace(0.0, 0.1, 20001), np.linspace(0.1, np.pi, 40001)[1:]])
    for phase in (CLOUD_PHASE, LobePhase((0.3, 0.7), (-0.5, 0.9))):
        integral = 2.0 * np.pi * np.trapezoid(phase.value(np.cos(th)) * np.sin(th), th)
        assert integral == pytest.approx(1.0, abs=1e-4)
        # first moment = sum w g (HG's Legendre moments are g^l)
        m1 = 2.0 * np.pi * np.trapezoid(phase.value(np.cos(th)) * np.cos(th) * np.sin(th), th)
        assert m1 == pytest.approx(phase.asymmetry, abs=1e-4)


def test_sampling_matches_the_density():
    # Chi-square of 200 000 samples in 40 bins (equal width in log(1 - mu) to resolve the
    # peak) against the exact bin probabilities from each lobe's CDF: 39 degrees of freedom,
    # the 0.1 % upper quantile is 72.1.
    rng = np.random.default_rng(7)
    n = 200_000
    mu = CLOUD_PHASE.sample(rng, n)
    edges = np.concatenate([[-1.0], 1.0 - np.geomspace(1.999, 1e-6, 39), [1.0]])
    counts, _ = np.histogram(mu, edges)
    cdf = sum(
        w * _hg_cdf(edges, g) for w, g in zip(CLOUD_PHASE.weights, CLOUD_PHASE.g, strict=True)
    )
    expected = n * np.diff(cdf)
    chi2 = np.sum((counts - expected) ** 2 / expected)
    assert chi2 < 72.1
    assert np.mean(mu) == pytest.approx(CLOUD_PHASE.asymmetry, abs=4.0 * np.std(mu) / n**0.5)


def test_asymmetry_of_water_clouds():
    # Hansen & Travis (1974, Space Sci. Rev. 16, 527), sec. 2: for gamma distributions of
    # water drops (m = 1.33, v_eff ~ 0.1) the asymmetry parameter at effective size parameter
    # 2 pi r_eff / lambda ~ 100 is 0.85-0.87 (their figure of <cos> against x_eff); the fit
    # keeps the Mie value of the first moment.
    assert 0.84 <= CLOUD_PHASE.asymmetry <= 0.88
    assert CLOUD_PHASE.asymmetry == pytest.approx(_mie()[2], abs=1e-4)
    # delta-M truncation fraction: below g (the lobes' g_j <= 1) and above g^2 (Jensen)
    assert CLOUD_PHASE.asymmetry**2 < CLOUD_PHASE.second_moment < CLOUD_PHASE.asymmetry


def test_fit_against_its_mie_phase_function():
    # HG lobes are monotone, so the cloudbow (140 deg), the glory (180 deg) and the minimum
    # near 100 deg are out of reach: no non-negative mixture of the candidate lobes does
    # better than an RMS ln error of 0.66 over 5-175 deg (tools/build_cloud_phase.py). We
    # require RMS < 0.75 and max < 1.45 (a factor 4.3, at the cloudbow), and within 0.2 (22 %)
    # over the forward lobe 5-40 deg, which dominates the scattered light.
    theta, p_mie, _ = _mie()
    p_fit = CLOUD_PHASE.value(np.cos(np.radians(theta)))
    err = np.log(p_fit / p_mie)
    wide = (theta >= 5.0) & (theta <= 175.0)
    assert np.sqrt(np.mean(err[wide] ** 2)) < 0.75
    assert np.abs(err[wide]).max() < 1.45
    fwd = (theta >= 5.0) & (theta <= 40.0)
    assert np.sqrt(np.mean(err[fwd] ** 2)) < 0.6
    # the diffraction peak holds its share: the fraction of light within 5 deg agrees to 10 %
    inner = theta <= 5.0
    th = np.radians(theta[inner])
    f_mie = 2 * np.pi * np.trapezoid(p_mie[inner] * np.sin(th), th)
    f_fit = 2 * np.pi * np.trapezoid(p_fit[inner] * np.sin(th), th)
    assert f_fit == pytest.approx(f_mie, rel=0.1)


def test_tool_rebuilds_the_packaged_tables():
    packaged = resources.files("skydome.data").joinpath(PHASE_CSV).read_text()
    assert _tool().build_text() == packaged
    packaged = resources.files("skydome.data").joinpath(MIE_PHASE_CSV).read_text()
    assert _tool().build_mie_text() == packaged


def test_mie_table_has_the_published_features():
    # Hansen & Travis (1974, Space Sci. Rev. 16, 527), Figs. 8-9, water clouds of
    # r_eff ~ 10 um at visible wavelengths: asymmetry 0.85-0.87, the deep side-scattering
    # minimum near 100 deg, the cloudbow at 138-142 deg (the geometric primary bow of m = 1.333
    # is at 137.9 deg; small drops move it outwards) and the glory rising steeply to 180 deg.
    t, p = MIE_PHASE.theta_deg, MIE_PHASE.values
    assert 0.85 <= MIE_PHASE.asymmetry <= 0.87
    assert MIE_PHASE.asymmetry == pytest.approx(_mie()[2], abs=2e-4)
    side = (t >= 60.0) & (t <= 130.0)
    assert 95.0 <= t[side][np.argmin(p[side])] <= 110.0
    bow = (t >= 120.0) & (t <= 160.0)
    assert 138.0 <= t[bow][np.argmax(p[bow])] <= 143.0
    assert p[-1] > 3.0 * np.interp(170.0, t, p)  # the glory
    # the diffraction peak: half of the light within a few degrees (extinction efficiency 2)
    inner = t <= 5.0
    th = np.radians(t[inner])
    assert 2 * np.pi * np.trapezoid(p[inner] * np.sin(th), th) == pytest.approx(0.5, abs=0.05)


def test_render_phase_is_mie_beyond_the_cut():
    # The flat cut keeps the Mie function beyond TRUNCATION_DEG (what single scattering sees),
    # scaled by 1 / (1 - f); within 0.2 % (the 0.088 deg grid's linear interpolation of the
    # 0.05 deg table). f is the peak's excess over its flat top: the direct integral of
    # P - P(theta_c) over theta < theta_c agrees within 1e-3.
    assert RENDER_PHASE.values.size == RENDER_PHASE_TEXELS
    x = np.linspace(TRUNCATION_DEG + 1.0, 180.0, 2000)
    mu = np.cos(np.radians(x))
    assert np.allclose(RENDER_PHASE.value(mu) * (1.0 - PEAK_FRACTION), MIE_PHASE.value(mu),
                       rtol=2e-3)  # fmt: skip
    t, p = MIE_PHASE.theta_deg, MIE_PHASE.values
    inner = t <= TRUNCATION_DEG
    th = np.radians(t[inner])
    excess = p[inner] - np.interp(TRUNCATION_DEG, t, p)
    assert PEAK_FRACTION == pytest.approx(2 * np.pi * np.trapezoid(excess * np.sin(th), th),
                                          abs=1e-3)  # fmt: skip
    assert RENDER_PHASE.value(np.array([1.0]))[0] == pytest.approx(
        RENDER_PHASE.value(np.array([np.cos(np.radians(TRUNCATION_DEG))]))[0], rel=5e-3
    )


def test_tabulated_hg_has_the_hg_moments_and_samples():
    # An HG lobe (g = 0.6) tabulated on the renderer's grid: its moments are g and g^2 within
    # 2e-4 (the grid resolves the lobe, 0.4 rad wide); its samples follow its CDF (the
    # closed form of _hg_cdf) within 4 standard errors per bin.
    hg = LobePhase.henyey_greenstein(0.6)
    tab = TabulatedPhase.of(hg)
    assert tab.asymmetry == pytest.approx(0.6, abs=2e-4)
    assert tab.second_moment == pytest.approx(0.36, abs=2e-4)
    mu = np.linspace(-1, 1, 9)
    assert np.allclose(tab.value(mu), hg.value(mu), rtol=1e-3)
    n = 200_000
    sample = tab.sample(np.random.default_rng(4), n)
    edges = np.linspace(-1.0, 1.0, 21)
    counts = np.histogram(sample, edges)[0] / n
    expect = np.diff(_hg_cdf(edges, 0.6))
    assert np.all(np.abs(counts - expect) < 4.0 * np.sqrt(expect / n) + 1e-4)


def test_render_phase_samples_follow_it():
    # The renderer's phase function sampled (the Monte Carlo's table of the clouds' multiple
    # scattering uses these): the mean cosine and the share beyond 90 deg match its
    # quadrature within 4 standard errors.
    n = 400_000
    mu = RENDER_PHASE.sample(np.random.default_rng(5), n)
    assert np.mean(mu) == pytest.approx(RENDER_PHASE.asymmetry, abs=4 * np.std(mu) / n**0.5)
    x = np.linspace(-1.0, 0.0, 20001)
    back = 2 * np.pi * np.trapezoid(RENDER_PHASE.value(x), x)
    assert np.mean(mu < 0) == pytest.approx(back, abs=4 * np.sqrt(back / n))


def test_tabulated_validation():
    with pytest.raises(ParameterError, match="rise from 0 to 180"):
        TabulatedPhase([0.0, 90.0], [1.0, 1.0])
    with pytest.raises(ParameterError, match=">= 0"):
        TabulatedPhase([0.0, 180.0], [1.0, -1.0])
    with pytest.raises(ParameterError, match="as many"):
        TabulatedPhase([0.0, 180.0], [1.0])
    with pytest.raises(ParameterError, match="truncation"):
        MIE_PHASE.delta_truncated(95.0)
    # normalised on construction (the trapezoid rule on 181 x 16 intervals: 1e-5)
    iso = TabulatedPhase(np.linspace(0.0, 180.0, 181), np.full(181, 7.0))
    assert iso.value(np.array([0.2]))[0] == pytest.approx(1.0 / (4.0 * np.pi), rel=1e-5)


def test_validation():
    with pytest.raises(ParameterError):
        LobePhase((0.5, 0.6), (0.1, 0.2))  # sum 1.1
    with pytest.raises(ParameterError):
        LobePhase((1.2, -0.2), (0.1, 0.2))  # negative weight
    with pytest.raises(ParameterError):
        LobePhase((1.0,), (1.0,))  # |g| = 1
    with pytest.raises(ParameterError):
        LobePhase((0.5, 0.5), (0.1,))  # lengths
    p = LobePhase((0.25, 0.75), (0.0, 0.5))
    assert p.asymmetry == pytest.approx(0.375)
    assert p.second_moment == pytest.approx(0.1875)
    assert p.value(np.array([0.3]))[0] == pytest.approx(
        0.25 / (4 * np.pi) + 0.75 * 0.75 / (4 * np.pi * (1.25 - 0.3) ** 1.5)
    )
