"""Light pollution: Bortle classes, the glow's zenith-angle profile, Walker's law, the lamps'
spectra, and the volume layer's compositing over what lies behind it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from skydome import Sky
from skydome.core.cameras import DirectionsCamera, direction_from_angles
from skydome.errors import ParameterError
from skydome.night import City, LightPollution, LightPollutionLayer, bortle_zenith_mag
from skydome.night import light_pollution as lp
from skydome.night.airglow import luminance_to_mag, mag_to_luminance
from skydome.spectra import SRGB_LUMINANCE
from tests.test_scene import GlowLayer

PLACE, TIME = "Valletta", "2018-03-01T23:00Z"


def test_bortle_8_zenith_is_a_city_sky():
    # Bortle 8 skies measure 18.0-18.4 mag/arcsec^2 at the zenith (SQM tables; the brief):
    # the model's artificial part plus the natural 21.9 must fall there.
    model = LightPollution.from_bortle(8)
    total = luminance_to_mag(model.zenith_cd_m2 + mag_to_luminance(lp.NATURAL_ZENITH_MAG))
    assert 18.0 <= total <= 18.4
    assert total == pytest.approx(bortle_zenith_mag(8), abs=1e-9)
    # Classes get brighter with the number; class 1 is natural (no artificial light).
    mags = [bortle_zenith_mag(k) for k in range(1, 10)]
    assert all(a > b for a, b in zip(mags, mags[1:], strict=False))
    assert LightPollution.from_bortle(1).zenith_cd_m2 == 0.0
    with pytest.raises(ParameterError):
        LightPollution.from_bortle(10)


def test_zenith_parameters_agree():
    a = LightPollution(zenith_mag_arcsec2=18.2)
    b = LightPollution(zenith_cd_m2=10.8e4 * 10 ** (-0.4 * 18.2))
    assert a.zenith_cd_m2 == pytest.approx(b.zenith_cd_m2, rel=1e-12)
    assert a.zenith_mag() == pytest.approx(18.2, abs=1e-9)
    with pytest.raises(ParameterError):
        LightPollution(zenith_mag_arcsec2=18.2, zenith_cd_m2=1e-3)


def test_kasten_young_air_mass():
    # Kasten & Young 1989 tabulate X = 38.0868 at the horizon for their model atmosphere;
    # their fitted formula is within 0.5 % of it (37.92). Near the zenith X is the secant of
    # a plane-parallel atmosphere: sec 60 deg = 2 to 0.3 %.
    assert lp.kasten_young_airmass(math.pi / 2) == pytest.approx(38.0868, rel=5e-3)
    assert lp.kasten_young_airmass(math.radians(60.0)) == pytest.approx(2.0, rel=3e-3)
    assert lp.kasten_young_airmass(0.0) == pytest.approx(1.0, rel=3e-4)


def test_slab_profile_against_a_numerical_slab():
    # The horizon/zenith ratio of a homogeneous slab with a uniform source function is
    # (1 - exp(-tau X(90))) / (1 - exp(-tau X(0))): at 0.25 mag/airmass, 4.86. Independently,
    # integrate the emission-absorption along the ray, dI/ds = k (S - I), by midpoint steps
    # through a plane-parallel slab with path length X(z) (the same air mass).
    tau = 0.25 / (2.5 * math.log10(math.e))
    for z_deg in (0.0, 45.0, 75.0, 89.0):
        z = math.radians(z_deg)
        x = float(lp.kasten_young_airmass(z))
        n = 20000
        ds = x / n
        s = (np.arange(n) + 0.5) * ds  # depth in zenith-optical-depth units along the path
        numeric = np.sum(np.exp(-tau * s) * tau * ds)  # source 1, attenuated to the observer
        x0 = float(lp.kasten_young_airmass(0.0))
        zenith = np.sum(np.exp(-tau * (np.arange(n) + 0.5) * x0 / n) * tau * x0 / n)
        assert lp.slab_profile(z) == pytest.approx(numeric / zenith, rel=1e-6)
    ratio = float(lp.slab_profile(math.pi / 2))
    assert ratio == pytest.approx(4.86, abs=0.01)


def test_walker_law_scaling():
    near = City(90.0, 20.0, 100_000)
    # I = 0.01 P d^-2.5: 100 000 people at 20 km raise the sky at 45 deg by 56 %.
    assert near.walker_fraction() == pytest.approx(0.01 * 1e5 * 20.0**-2.5)
    assert City(90.0, 20.0, 200_000).walker_fraction() == pytest.approx(2 * near.walker_fraction())
    assert City(90.0, 40.0, 100_000).walker_fraction() == pytest.approx(
        2**-2.5 * near.walker_fraction()
    )
    # Towards the city at 45 deg the model adds exactly Walker's fraction of the natural sky.
    model = LightPollution(cities=[near])
    d = direction_from_angles(45.0, 90.0)
    assert model.luminance(d) == pytest.approx(
        near.walker_fraction() * mag_to_luminance(21.9), rel=1e-12
    )
    # The dome is brighter towards the city and low down than away from it.
    toward = model.luminance(direction_from_angles(10.0, 90.0))
    away = model.luminance(direction_from_angles(10.0, 270.0))
    assert toward > 5 * away
    with pytest.raises(ParameterError):
        City(90.0, 0.1, 1e5)


def test_lamp_spectra_have_their_published_colours():
    grid = np.arange(360.0, 831.0, 1.0)
    # High-pressure sodium: CCT ~2000-2100 K, S/P ~0.62 (lighting tables, IES TM-12-12).
    hps = lp.lamp_spectrum("hps", grid)
    assert 1900 < lp.correlated_colour_temperature(grid, hps) < 2150
    assert lp.scotopic_photopic_ratio(grid, hps) == pytest.approx(0.62, abs=0.05)
    # A 4000 K white LED: its CCT and an S/P of ~1.5 (1.4-1.6 for 4000 K phosphor LEDs).
    led = lp.lamp_spectrum("led4000", grid)
    assert lp.correlated_colour_temperature(grid, led) == pytest.approx(4000, abs=100)
    assert 1.4 < lp.scotopic_photopic_ratio(grid, led) < 1.65
    with pytest.raises(ParameterError):
        lp.lamp_spectrum("mercury", grid)


@pytest.fixture(scope="module")
def glow_behind():
    # A space-stage glow behind the light pollution (no atmosphere between: what the volume
    # layer receives is exactly this constant).
    return (1e-3, 2e-3, 3e-3, 4e-3)


def test_volume_layer_adds_to_what_lies_behind(glow_behind):
    city = City(120.0, 25.0, 300_000)
    layer = LightPollutionLayer.from_bortle(8, cities=[city])
    sky = Sky(PLACE, TIME, layers=[GlowLayer(glow_behind), layer])
    els = (90.0, 45.0, 20.0, 5.0, 1.0)
    up = np.array([direction_from_angles(e, a) for e in els for a in (120.0, 300.0)])
    down = np.array([direction_from_angles(e, a) for e in (-1.0, -30.0, -90.0) for a in (0, 120)])
    cam = DirectionsCamera(np.concatenate([up, down]))
    data = sky.render(cam, 0, 0, exposure=None).data[0].astype(np.float64)
    behind = np.asarray(glow_behind, dtype=np.float32)
    # Below the horizon (the ground): exactly what lay behind, bit for bit.
    assert np.array_equal(data[len(up) :], np.tile(behind, (len(down), 1)))
    # Above: behind + the glow's luminance in its lamp colour (float32: 1e-5 of the sum).
    added = data[: len(up)] - behind
    ref = layer.model.luminance(up, sky.altitude_m())
    np.testing.assert_allclose(added[:, :3] @ SRGB_LUMINANCE, ref, rtol=2e-3)
    # The horizon is brighter than the zenith as the slab profile says (away from the city).
    away = added[1::2, :3] @ SRGB_LUMINANCE
    assert away[0] < away[2] < away[4]


def test_light_pollution_passes_behind_through_in_the_abstract_mode(glow_behind):
    sky = Sky(
        sun_elevation_deg=-30.0, layers=[GlowLayer(glow_behind), LightPollutionLayer.from_bortle(9)]
    )
    cam = DirectionsCamera(np.array([direction_from_angles(e, 0.0) for e in (90.0, 10.0)]))
    data = sky.render(cam, 0, 0, exposure=None).data[0]
    assert np.array_equal(data, np.tile(np.asarray(glow_behind, np.float32), (2, 1)))


def test_sodium_glow_is_orange():
    sky = Sky(PLACE, TIME, layers=[LightPollutionLayer.from_bortle(8)])
    c = sky.layer("light_pollution").colour(sky.graph.basis)
    assert c[0] > c[1] > c[2]  # orange: R > G > B
    led = LightPollutionLayer(zenith_mag_arcsec2=19.0, lamp="led4000").colour(sky.graph.basis)
    assert led[2] / led[0] > c[2] / c[0]  # the LED is bluer
    assert led[3] > c[3]  # and scotopically richer
