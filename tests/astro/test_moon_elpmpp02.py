"""The Moon's theory (ELP/MPP02, DE405 fit, as packaged and truncated) against its
published test positions and against DE421, geocentric and geometric.

External numbers: the test positions of the DE405/DE406 fit in Y. T. Liu's documentation
of ELP/MPP02 (github.com/ytliu0/ElpMpp02, docs/ElpMpp02.tex, "Test cases": X, Y, Z in km,
mean ecliptic and equinox of J2000, TDB), computed there with the complete series; and
JPL's DE421 through skyfield. The J2000 ecliptic is reached from our mean equator of date
by ERFA's IAU 2006 precession (pmat06) and ecliptic (ecm06), independently of how
skydome.astro.moon turns ELP's frame into that of date.
"""

import numpy as np
import pytest
from _astro_oracles import ARCSEC, skyfield

from skydome.astro import frames, moon

erfa = pytest.importorskip("erfa")

# TDB JD: X, Y, Z (km), ecliptic and equinox of J2000 (the tex's table for DE405/DE406)
DE405_TESTS = {
    2521835.67: (-184108.21468, 345893.25529, 30395.06868),  # 2192-06-13
    2265621.33: (-298024.37832, -213909.67132, -23263.21426),  # 1490-12-07
    2009406.99: (350041.24745, -201093.28987, 1643.33539),  # 0789-06-16
    1753192.65: (90272.39894, 351997.39617, 13417.01712),  # 0087-12-25
    1496978.31: (-403018.01560, -2639.93889, -28463.89733),  # -0614-07-03
}


def _j2000_ecliptic(jd: np.ndarray, mean_of_date: np.ndarray) -> np.ndarray:
    gcrs = np.einsum("nji,nj->ni", erfa.pmat06(jd, 0.0), mean_of_date)
    return np.einsum("ij,nj->ni", erfa.ecm06(2451545.0, 0.0), gcrs)


def test_published_de405_positions():
    """Within 0.2" (0.4 km at the Moon), 2192 back to -614: the truncation to 0.003" costs
    up to 0.16" over 1900-2100 and 0.25" at -500..500 in the worst case of thousands of
    instants (tools/build_moon_elpmpp02.py), the IAU 2006 ecliptic differs from Laskar's
    (ELP's) by milliarcseconds. Measured 0.02-0.11" (0.03-0.20 km)."""
    jd = np.array(list(DE405_TESTS))
    ref = np.array(list(DE405_TESTS.values()))
    ours = _j2000_ecliptic(jd, moon.moon_geocentric_mean_of_date(jd))
    err = np.linalg.norm(ours - ref, axis=1)
    assert np.all(err / np.linalg.norm(ref, axis=1) < 0.2 / ARCSEC), err


def test_geocentric_vs_de421_1950_2050():
    """Geometric geocentric places of 4000 random instants of 1950-2050 against DE421
    (the issue asks well under 1"): within 0.35" (measured 0.23" max, 0.052" RMS over
    20000 instants: the truncation's 0.16" / 0.035" plus ELP/MPP02's own distance from
    DE421, and a 0.03" mean offset in longitude, ELP's J2000 origin against the ICRS),
    RMS 0.08"; distance within 0.5 km (truncated at 0.01 km: 0.33 km)."""
    ts, eph = skyfield()
    rng = np.random.default_rng(7)
    jd = 2433282.5 + rng.random(4000) * 36524.0
    ref = (eph["moon"] - eph["earth"]).at(ts.tdb_jd(jd)).position.km.T  # ICRS
    ref = np.einsum("nij,nj->ni", erfa.pmat06(jd, 0.0), ref)  # mean equator of date
    ours = moon.moon_geocentric_mean_of_date(jd)
    sep = np.arccos(
        np.clip(
            np.sum(ours * ref, 1) / np.linalg.norm(ours, axis=1) / np.linalg.norm(ref, axis=1),
            -1,
            1,
        )
    )
    sep = sep * ARCSEC
    assert sep.max() < 0.35 and np.sqrt(np.mean(sep**2)) < 0.08, (sep.max(), sep.std())
    dr = np.linalg.norm(ours, axis=1) - np.linalg.norm(ref, axis=1)
    assert np.abs(dr).max() < 0.5
    # the longitude of date is that of the mean equinox of date: no drift in 100 years
    eps = frames.mean_obliquity(jd)
    lam_o = frames.cartesian_to_spherical(np.einsum("nij,nj->ni", frames.rot_x(eps), ours))[0]
    lam_r = frames.cartesian_to_spherical(np.einsum("nij,nj->ni", frames.rot_x(eps), ref))[0]
    dl = ((lam_o - lam_r + np.pi) % (2 * np.pi) - np.pi) * ARCSEC
    slope = np.polyfit((jd - 2451545.0) / 36525.0, dl, 1)[0]
    assert abs(slope) < 0.05  # "/century (measured 0.001"; p_A's rate is 5029")
