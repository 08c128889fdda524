"""The ice-crystal ray tracer (skydome.physics.crystal_optics) against prism optics.

The halos' places are geometric: a ray's minimum deviation through a prism of apex angle A
and index n is D = 2 asin(n sin(A / 2)) - A (60 deg: the 22 deg halo; 90 deg: the 46 deg
halo), and horizontal plates see the light at elevation e through an effective index
sqrt(n^2 - sin^2 e) / cos e (Bravais; Tape 1994, "Atmospheric Halos", ch. 2), which puts the
sun dogs' inner edge at that prism's minimum deviation in azimuth and the circumzenithal arc
at elevation asin(sqrt(n^2 - cos^2 e)), which exists only while n^2 - cos^2 e <= 1 (the Sun
below 32.2 deg). The tracer knows none of these formulas: it refracts and reflects rays.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from skydome.errors import ParameterError
from skydome.physics.crystal_optics import (
    HexagonalPrism,
    Orientation,
    Sphere,
    ice_index,
    orientations,
    scatter,
    trace,
)
from skydome.physics.interfaces import interface_reflectance
from skydome.physics.sphere_optics import (
    MAX_ORDER,
    descartes_angle_deg,
    geometric_phase,
    water_index,
)
from tests.optics_formulas import minimum_deviation_deg


def steepest_rise_deg(values, weights, lo, hi, step, per=None):
    """The edge where the binned light rises most steeply (the upper edge of the bin before
    the jump): a halo's sharp inner edge at the bin's resolution."""
    edges = np.arange(lo, hi + step / 2.0, step)
    light = np.histogram(values, edges, weights=weights)[0]
    if per is not None:
        light = light / per(edges)
    return edges[int(np.argmax(np.diff(light))) + 1]


def test_ice_index_is_warren_and_brandts():
    # their compilation at -7 C: 1.3194 at 400 nm, 1.3110 at 550 nm, 1.3069 at 700 nm; the
    # sodium line between 580 and 600 nm: the 21.8 deg halo at n = 1.31
    assert ice_index([400.0, 550.0, 700.0]) == pytest.approx([1.3194, 1.3110, 1.3069])
    assert minimum_deviation_deg(float(ice_index(589.0)), 60.0) == pytest.approx(21.8, abs=0.05)
    with pytest.raises(ParameterError):
        ice_index(900.0)


def test_fresnel_matches_normal_incidence_and_total_reflection():
    # ((n - 1) / (n + 1))^2 at normal incidence; beyond the critical angle everything reflects
    r_s, r_p, cos_t = interface_reflectance(1.0, 1.31)
    assert r_s == pytest.approx(((1.31 - 1) / 2.31) ** 2) and r_p == pytest.approx(r_s)
    critical = math.asin(1.0 / 1.31)
    r_s, r_p, cos_t = interface_reflectance(math.cos(critical + 0.01), 1.0 / 1.31)
    assert (r_s, r_p, cos_t) == (1.0, 1.0, 0.0)
    # Brewster's angle: no parallel reflection
    _, r_p, _ = interface_reflectance(math.cos(math.atan(1.31)), 1.31)
    assert r_p == pytest.approx(0.0, abs=1e-15)


@pytest.mark.parametrize("body", [HexagonalPrism(0.2), HexagonalPrism(3.0), Sphere()])
def test_tracer_conserves_energy(body):
    # scattered + absorbed + left inside = incident, ray by ray (absorbing ice: 1 %/radius)
    rng = np.random.default_rng(7)
    d = rng.normal(size=(20_000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    traced = trace(body, d, 1.31, rng.random((len(d), 4)), absorption=0.01)
    out = np.bincount(traced.ray, weights=traced.weights, minlength=len(d))
    total = out + traced.absorbed + traced.residual
    assert np.abs(total - 1.0).max() < 1e-6
    assert traced.absorbed.mean() > 1e-3  # the absorption is exercised
    # light trapped by total internal reflection past the 60 chords followed: little
    assert traced.residual.mean() < 1e-3
    # every direction leaving is a unit vector
    assert np.allclose(np.linalg.norm(traced.directions, axis=1), 1.0, atol=1e-9)


def test_orientations_are_rotations_and_float_as_told():
    rng = np.random.default_rng(3)
    for kind in ("random", "plates", "columns"):
        r = orientations(Orientation(kind, 1.0), 2000, rng)
        assert np.allclose(r @ np.swapaxes(r, 1, 2), np.eye(3), atol=1e-12)
        assert np.allclose(np.linalg.det(r), 1.0)
        axis_z = r[:, 2, 2]  # the c-axis's vertical component
        if kind == "plates":  # within a few tilts of vertical
            assert np.degrees(np.arccos(np.abs(axis_z))).max() < 6.0
        elif kind == "columns":
            assert np.degrees(np.arcsin(np.abs(axis_z))).max() < 6.0
        else:  # isotropic: the axis's vertical component uniform in [-1, 1]
            assert abs(np.mean(axis_z)) < 0.05 and abs(np.mean(axis_z**2) - 1 / 3) < 0.02
    with pytest.raises(ParameterError):
        Orientation("cubes")


@pytest.fixture(scope="module")
def random_columns():
    # the same 100 000 crystals at four wavelengths, the light at the zenith: the angle from
    # the light is 90 deg less the elevation seen
    wavelengths = (400.0, 500.0, 589.0, 700.0)
    s = scatter(HexagonalPrism(1.0), Orientation("random"), 90.0, wavelengths, 100_000, 3)
    return wavelengths, s


def _per_solid_angle(edges):
    return np.diff(-np.cos(np.radians(edges)))


@pytest.mark.parametrize("apex, tolerance", [(60.0, 0.2), (90.0, 0.3)])
def test_halos_inner_edges_are_the_prisms_minimum_deviation(random_columns, apex, tolerance):
    # the 22 deg halo (60 deg prisms) within 0.2 deg, the 46 deg (90 deg) within 0.3 deg, at
    # each wavelength: red inside, blue outside
    wavelengths, s = random_columns
    angle = 90.0 - s.elevation_deg
    edges = []
    for k, wl in enumerate(wavelengths):
        expected = minimum_deviation_deg(float(ice_index(wl)), apex)
        pick = s.wavelength == k
        step = 0.05 if apex == 60.0 else 0.1
        edge = steepest_rise_deg(angle[pick], s.weight[pick], expected - 3.0, expected + 3.0,
                                 step, _per_solid_angle)  # fmt: skip
        assert edge == pytest.approx(expected, abs=tolerance), wl
        edges.append(edge)
    assert edges == sorted(edges, reverse=True)  # dispersion: violet deviated most


@pytest.mark.parametrize("sun_deg", [0.0, 20.0, 40.0])
def test_sun_dogs_azimuth_follows_the_oblique_prism(sun_deg):
    n = float(ice_index(589.0))
    e = math.radians(sun_deg)
    effective = math.sqrt(n * n - math.sin(e) ** 2) / math.cos(e)
    expected = minimum_deviation_deg(effective, 60.0)
    s = scatter(HexagonalPrism(0.2), Orientation("plates", 0.0), sun_deg, [589.0], 60_000, 4)
    level = np.abs(s.elevation_deg - sun_deg) < 0.25  # the parhelic circle's height
    edge = steepest_rise_deg(np.abs(s.azimuth_deg[level]), s.weight[level], 15.0, 45.0, 0.05)
    assert edge == pytest.approx(expected, abs=0.3)


def test_circumzenithal_arc_only_below_32_degrees():
    n = float(ice_index(589.0))
    limit = math.degrees(math.acos(math.sqrt(n * n - 1.0)))
    assert limit == pytest.approx(32.2, abs=0.1)
    for sun_deg in (20.0, 30.0, 33.0, 40.0):
        s = scatter(HexagonalPrism(0.2), Orientation("plates", 0.0), sun_deg, [589.0], 60_000, 5)
        high = (np.abs(s.azimuth_deg) < 30.0) & (s.elevation_deg > sun_deg + 20.0)
        if sun_deg < limit:
            c = math.cos(math.radians(sun_deg))
            expected = math.degrees(math.asin(math.sqrt(n * n - c * c)))
            edges = np.arange(50.0, 90.0 + 0.05, 0.1)
            light = np.histogram(s.elevation_deg[high], edges, weights=s.weight[high])[0]
            light /= np.diff(np.sin(np.radians(edges)))
            peak = edges[int(np.argmax(light))] + 0.05
            assert peak == pytest.approx(expected, abs=0.2)
        else:
            # nothing at all comes from above the Sun near its azimuth
            assert s.weight[high].sum() == 0.0


def test_tracer_on_a_sphere_is_the_drops_geometric_optics():
    # the same tracer on a water sphere: the phase function of sphere_optics.geometric_phase
    # (orders summed analytically over the impact parameter, up to its MAX_ORDER = 7 chords,
    # renormalised: so the tracer too stops after 8 chords) within the Monte Carlo's 4 sigma
    # per 2 deg bin, and the bows at Descartes' angles
    n = float(water_index(550.0))
    rng = np.random.default_rng(11)
    rays = 300_000
    d = np.tile([[0.0, 0.0, -1.0]], (rays, 1))
    traced = trace(Sphere(), d, n, rng.random((rays, 4)), max_chords=MAX_ORDER + 1)
    angle = np.degrees(np.arccos(np.clip(-traced.directions[:, 2], -1.0, 1.0)))
    edges = np.arange(0.0, 180.0 + 1.0, 2.0)
    light = np.histogram(angle, edges, weights=traced.weights)[0]
    squares = np.histogram(angle, edges, weights=traced.weights**2)[0]
    solid = 2.0 * math.pi * _per_solid_angle(edges)
    total = traced.weights.sum()
    phase, sigma = light / total / solid, np.sqrt(squares) / total / solid
    expected = geometric_phase(n, edges)
    assert np.all(np.abs(phase - expected) <= 4.0 * sigma + 0.005 * expected)
    for order in (2, 3):
        bow = descartes_angle_deg(n, order)
        fine = np.arange(bow - 4.0, bow + 4.0, 0.05)
        light = np.histogram(angle, fine, weights=traced.weights)[0]
        assert fine[int(np.argmax(light))] + 0.025 == pytest.approx(bow, abs=0.1)
