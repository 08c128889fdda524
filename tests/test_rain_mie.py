"""The rain's bows by Lorenz-Mie theory (tools/build_rain_mie_phase.py ->
rain_drop_mie_phase.npz -> skydome.clouds.phase.RainBows): against miepython, Airy's theory
of the supernumeraries, Descartes' angles, and what the drops' sizes do to the bows.

Airy (1838; van de Hulst 1957 sec. 13.22): near a bow the rays' deviation is a parabola in the
impact parameter b (theta = theta_R + D'' (b - b_R)^2 / 2), so the outgoing wavefront is a
cubic and the light goes as Ai^2(-z), z = (theta - theta_R) x^(2/3) / (D'' / 2)^(1/3) (x the
size parameter): maxima at z = 1.0188, 3.2482, ... (the primary, the supernumeraries), and
the geometric bow (z = 0, Descartes' angle) where the light is Ai(0)^2 / Ai(-1.0188)^2 = 0.4407
of the first maximum, on the dark side.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from skydome.clouds.phase import (
    RAIN_PHASES,
    load_rain_bows,
    rain_channel_phases,
    render_grid_deg,
)
from skydome.physics.sphere_optics import descartes_angle_deg, water_index
from tests.optics_formulas import AIRY_EDGE, AIRY_MAXIMA, airy_unit_deg
from tests.tools_module import load_tool

ROOT = Path(__file__).resolve().parents[1]


def _tool():
    return load_tool("build_rain_mie_phase")


def test_drop_light_equals_miepython():
    # the tool's Mie series (skydome.atmosphere.mie's coefficients, amplitudes summed in
    # chunks) against miepython's, drop by drop, over the primary bow: within 0.5 % (they
    # agree to ~1e-7); the efficiencies too
    from skydome.atmosphere.mie import sphere_scattering

    ref = json.loads((ROOT / "tests/data/rain_mie_miepython.json").read_text())
    tool = _tool()
    angles = tool.sample_angles_deg(np.asarray(ref["edges_deg"]))
    light = tool.drop_light(ref["radii_um"], ref["wavelength_nm"], angles.ravel())
    light = light.reshape(len(ref["radii_um"]), *angles.shape).mean(-1)
    expected = np.asarray(ref["light_um2_sr"])
    assert np.abs(light / expected - 1.0).max() < 0.005
    k = 2.0 * math.pi / (ref["wavelength_nm"] / 1e3)
    s = sphere_scattering(complex(ref["index"], 0.0), k * np.asarray(ref["radii_um"]), [1.0])
    assert s.q_ext == pytest.approx(ref["q_ext"], rel=0.005)
    assert s.q_sca == pytest.approx(ref["q_sca"], rel=0.005)


def _bow_profile(radius_um, wavelength_nm, lo, hi, step=0.002, smooth_deg=0.1):
    """One drop's light over [lo, hi] deg, its fine ripple (the reflected light's
    interference, ~0.03 deg) averaged over ``smooth_deg``."""
    theta = np.arange(lo, hi, step)
    light = _tool().drop_light([radius_um], wavelength_nm, theta)[0]
    k = max(int(round(smooth_deg / step)), 1)
    return theta, np.convolve(light, np.ones(k) / k, mode="same"), k


def test_supernumerary_spacing_of_quarter_millimetre_drops_is_airys():
    # 0.25 mm drops at 550 nm: the primary's first maximum and its first supernumerary inside
    # it, 1.08 deg apart by Airy, within 10 %
    n = float(water_index(550.0))
    bow = descartes_angle_deg(n, 2)
    theta, light, k = _bow_profile(250.0, 550.0, bow - 0.5, bow + 2.5)
    inner = np.arange(k, theta.size - k)
    peaks = [theta[j] for j in inner if light[j] == light[j - k // 2 : j + k // 2 + 1].max()
             and theta[j] > bow]  # fmt: skip
    x = 2.0 * math.pi * 250.0 / 0.55
    unit = airy_unit_deg(n, x)
    airy = (AIRY_MAXIMA[1] - AIRY_MAXIMA[0]) * unit
    assert airy == pytest.approx(1.08, abs=0.01)
    assert peaks[1] - peaks[0] == pytest.approx(airy, rel=0.10)
    assert peaks[0] - bow == pytest.approx(AIRY_MAXIMA[0] * unit, abs=0.05)


@pytest.mark.parametrize("radius_um, wavelength_nm", [(500.0, 450.0), (500.0, 650.0),
                                                       (1000.0, 550.0)])  # fmt: skip
def test_bows_geometric_edges_are_descartes(radius_um, wavelength_nm):
    # drops of 0.5 mm and more: where each bow's light falls to Airy's 0.4407 of its first
    # maximum on the dark side (Alexander's band) is Descartes' angle within 0.1 deg, for the
    # primary (dark at smaller angles) and the secondary (dark at larger)
    n = float(water_index(wavelength_nm))
    for order, dark in ((2, -1), (3, +1)):
        bow = descartes_angle_deg(n, order)
        theta, light, _ = _bow_profile(radius_um, wavelength_nm, bow - 1.2, bow + 1.2)
        bright = (theta - bow) * -dark > 0
        first = np.where(bright & (np.abs(theta - bow) < 0.6))[0]
        j = first[np.argmax(light[first])]
        while light[j] > AIRY_EDGE * light[first].max():
            j += dark
        assert theta[j] == pytest.approx(bow, abs=0.1), (order, theta[j], bow)


def test_packaged_bows_are_what_the_tool_builds():
    # one wavelength rebuilt: every rain rate and drop size equal to the packaged (float32)
    tool = _tool()
    bows = load_rain_bows()
    w = 8
    table = tool.build(wavelengths_nm=[bows.wavelength_nm[w]])
    assert np.allclose(table["phase"][:, 0], bows.by_rate[:, w], rtol=2e-6, atol=0)
    assert np.allclose(table["narrow"][:, 0], bows.by_radius[:, w], rtol=2e-6, atol=0)


def test_mie_bows_join_the_rays_outside_the_bows():
    # away from the bows' caustics (143-145 deg inside the primary; 125-127 deg outside the
    # secondary, from 500 nm: at shorter wavelengths the secondary, at 128.1-128.8 deg,
    # spreads there for small drops) the waves' light is the rays' within 8 % for every rain
    # rate: the two tables meet where the renderer blends them
    bows = load_rain_bows()
    rays = RAIN_PHASES.at(bows.wavelength_nm)
    for lo, hi, shortest in ((143.0, 145.0, 400.0), (125.0, 127.0, 500.0)):
        pick = (bows.theta_deg > lo) & (bows.theta_deg < hi)
        wl = bows.wavelength_nm >= shortest
        geo = np.stack([np.interp(bows.theta_deg[pick], RAIN_PHASES.theta_deg, r) for r in rays])
        for rate_table in bows.by_rate:
            ratio = rate_table[:, pick].mean(1) / geo.mean(1)
            assert np.abs(ratio[wl] - 1.0).max() < 0.08


def _green(rain_mm_h=4.0, drop_radius_um=None):
    from skydome.core.basis import SpectralBasis
    from skydome.spectra import ACCURATE_NM

    basis = SpectralBasis.for_wavelengths(ACCURATE_NM)
    return rain_channel_phases(basis.wavelengths_nm, basis.to_output, rain_mm_h, drop_radius_um)[1]


def test_drizzle_bows_are_broad_and_pale_showers_narrow():
    # seen in the Sun's disk, green: the primary's peak over the light just inside it (140-
    # 142 deg) grows with the rain rate (larger drops: a sharper caustic) and its width at
    # half the peak above the band shrinks
    theta = render_grid_deg()
    peaks, widths = [], []
    for rate in (0.1, 1.0, 10.0):
        p = _green(rate)
        bow = (theta > 136.0) & (theta < 140.0)
        peak = p[bow].max()
        band = p[(theta > 131.0) & (theta < 135.0)].mean()
        peaks.append(peak / p[(theta > 140.0) & (theta < 142.0)].mean())
        half = bow & (p > band + 0.5 * (peak - band))
        widths.append(theta[half].max() - theta[half].min())
    assert peaks == sorted(peaks) and peaks[-1] > 1.1 * peaks[0], peaks
    assert widths == sorted(widths, reverse=True) and widths[0] > 1.3 * widths[-1], widths


def test_drops_of_one_size_draw_supernumeraries():
    # 0.2 mm drops, 10 % spread, in the Sun's disk: a second maximum inside the primary (a
    # supernumerary, ~1.3 deg in), which Marshall-Palmer's spread of sizes at the same
    # drops' scale (0.3 mm/h) washes out
    theta = render_grid_deg()
    inside = (theta > 138.0) & (theta < 142.5)

    def maxima(p):
        j = np.where(inside)[0]
        return [theta[i] for i in j if p[i] > p[i - 1] and p[i] >= p[i + 1]]

    assert len(maxima(_green(drop_radius_um=200.0))) >= 2
    assert len(maxima(_green(0.3))) == 1
