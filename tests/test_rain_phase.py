"""Rain drops' phase function by geometric optics (skydome.physics.sphere_optics), against
Mie theory (miepython, tests/data/rain_phase_miepython.json made by
tools/make_rain_phase_reference.py) and Descartes' bows; the packaged table the renderer
scatters rain with; and the rain's rainbow in the cloud layer's march."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from skydome.clouds.phase import RAIN_PEAK_FRACTION, RAIN_PHASES, RAIN_RENDER_PHASE
from skydome.io.packaged import read_packaged_csv
from skydome.physics.sphere_optics import (
    descartes_angle_deg,
    geometric_phase,
    ray_orders,
    water_index,
)

REFERENCE = Path(__file__).parent / "data" / "rain_phase_miepython.json"
EDGES_DEG = np.linspace(0.0, 180.0, 361)
CENTRES_DEG = 0.5 * (EDGES_DEG[1:] + EDGES_DEG[:-1])


@pytest.fixture(scope="module")
def phase_1333():
    return geometric_phase(1.333, EDGES_DEG, rays=1_000_000)


def test_rays_against_mie(phase_1333):
    """Geometric optics is Mie theory's limit for drops of 100-400 um (size parameters
    1100-4600) away from the diffraction peak and the bows: within 1.5 % of miepython over
    10-60 deg (where the straight-through light dominates: measured within 0.7 %) and 15 %
    beyond (measured 12 % at 80 deg, the edge of the transmitted light at 82.8 deg, and 7-10 %
    towards the back, where Mie's surface waves add to the rays)."""
    ref = json.loads(REFERENCE.read_text())
    assert ref["q_sca"] == pytest.approx(2.0, abs=0.02)  # the extinction paradox
    for theta, mie in zip(ref["theta_deg"], ref["per_area"], strict=True):
        rays = float(np.interp(theta, CENTRES_DEG, phase_1333))
        bound = 0.015 if theta <= 60.0 else 0.15
        assert abs(rays / mie - 1.0) < bound, (theta, rays, mie)


def test_the_bows_sit_at_descartes_angles(phase_1333):
    """The rays pile up at the bows' minimum deviation (Descartes: 137.92 deg primary and
    129.11 deg secondary at n = 1.333): the brightest half-degree bins there; Alexander's
    band between them darker than inside the primary and outside the secondary."""
    assert descartes_angle_deg(1.333, 2) == pytest.approx(137.92, abs=0.01)
    assert descartes_angle_deg(1.333, 3) == pytest.approx(129.11, abs=0.01)
    primary = CENTRES_DEG[
        np.argmax(np.where((CENTRES_DEG > 132) & (CENTRES_DEG < 145), phase_1333, 0))
    ]
    secondary = CENTRES_DEG[
        np.argmax(np.where((CENTRES_DEG > 120) & (CENTRES_DEG < 132), phase_1333, 0))
    ]
    assert primary - 0.5 <= descartes_angle_deg(1.333, 2) <= primary + 0.25
    assert secondary - 0.25 <= descartes_angle_deg(1.333, 3) <= secondary + 0.5
    band = phase_1333[(CENTRES_DEG > 131) & (CENTRES_DEG < 137)].mean()
    assert band < 0.3 * phase_1333[(CENTRES_DEG > 140) & (CENTRES_DEG < 150)].mean()
    assert band < 0.5 * phase_1333[(CENTRES_DEG > 122) & (CENTRES_DEG < 128)].mean()


def test_the_orders_carry_all_the_light():
    """Fresnel's shares of all orders add up to 1 (no absorption), to 1e-9 over 200 orders
    (grazing rays excluded: their internal reflectance tends to 1)."""
    b = np.linspace(0.0, 0.99, 100)
    _, shares = ray_orders(b, 1.333, max_order=200)
    assert np.allclose(shares.sum(axis=0), 1.0, atol=1e-9)


def test_the_packaged_tables():
    """The renderer's tables (350-800 nm every 10 nm): at each wavelength the primary and the
    secondary bows peak in the 0.05 deg bin holding Descartes' angles for water's index there
    (red's primary at a smaller scattering angle than violet's, the secondary's order
    reversed); each normalised; in white light (V(lambda)) half of the drops' extinction
    (diffraction) plus the rays within 5 deg counted as unscattered."""
    t = RAIN_PHASES.theta_deg
    half_bin = 0.025 + 1e-6
    for wl, row in zip(RAIN_PHASES.wavelength_nm, RAIN_PHASES.phase, strict=True):
        n = float(water_index(wl))
        primary = t[np.argmax(np.where((t > 133) & (t < 145), row, 0))]
        secondary = t[np.argmax(np.where((t > 120) & (t < 133), row, 0))]
        # the caustic's bin: the one holding the angle, or its neighbour on the bright side
        assert -half_bin <= primary - descartes_angle_deg(n, 2) <= 3 * half_bin, (wl, primary)
        assert -3 * half_bin <= secondary - descartes_angle_deg(n, 3) <= half_bin, wl
        rad = np.radians(t)
        assert np.trapezoid(row * 2 * np.pi * np.sin(rad), rad) == pytest.approx(1.0, abs=0.01)
    assert descartes_angle_deg(float(water_index(700.0)), 2) < descartes_angle_deg(
        float(water_index(400.0)), 2
    )
    assert 0.5 < RAIN_PEAK_FRACTION < 0.51
    # the rendered white phase: normalised, the table's beyond the truncation angle
    kept = 2.0 * (1.0 - RAIN_PEAK_FRACTION)
    v = read_packaged_csv("cie_luminous_efficiency_5nm.csv")
    white = RAIN_PHASES.white(v["wavelength_nm"], v["V_photopic"])
    cos_t = np.cos(np.radians([30.0, 90.0, 150.0, 170.0]))  # (the bows: its grid is coarser)
    np.testing.assert_allclose(RAIN_RENDER_PHASE.value(cos_t) * kept, white.value(cos_t), rtol=2e-3)


def test_the_suns_disk_smooths_the_bows():
    """Seen in the Sun's disk (0.533 deg across), the phase function keeps its integral (to
    0.1 %) and the primary bow's caustic, a spike one 0.05 deg bin wide in a parallel beam,
    spreads over the disk: its half-maximum width is 0.3-0.6 deg; a smooth part (30 deg)
    is unchanged to 0.1 %."""
    from skydome.clouds.phase import SUN_RADIUS_DEG, disk_smoothed

    row = RAIN_PHASES.phase[20]  # 550 nm
    fine, smooth = disk_smoothed(RAIN_PHASES.theta_deg, row)
    rad = np.radians(fine)
    assert np.trapezoid(smooth * 2 * np.pi * np.sin(rad), rad) == pytest.approx(1.0, abs=1e-3)
    bow = (fine > 135.0) & (fine < 142.0)
    peak = smooth[bow].max()
    above = fine[bow][smooth[bow] > 0.5 * (peak + smooth[(fine > 141) & (fine < 142)].mean())]
    assert 0.3 < above.max() - above.min() < 0.6, (above.min(), above.max())
    assert 2 * SUN_RADIUS_DEG == pytest.approx(0.533, abs=0.001)
    k = np.argmin(np.abs(fine - 30.0))
    assert smooth[k] == pytest.approx(np.interp(30.0, RAIN_PHASES.theta_deg, row), rel=1e-3)


@pytest.mark.gl
@pytest.mark.parametrize("rain_fraction", [1.0, 0.0])
def test_sunlit_rain_shows_its_rainbow(rain_fraction):
    """A uniform rain under a transparent deck, lit by a Sun 10 deg up, seen from the ground
    along the antisolar vertical: the cloud layer's march draws the primary bow within 1 deg
    of Descartes' angle (137.9 deg at 550 nm; white light spreads it over 137.6-138.8), the
    secondary within 1 deg of 129.1 deg, and Alexander's dark band between them darker than
    inside the primary; red outside blue in the primary, inside it in the secondary; snow (rain_fraction 0) scatters as the droplets: no secondary bow (the
    light rises steadily through 124-133 deg; the droplets' broad cloudbow remains)."""
    from skydome import Sky
    from skydome.atmosphere.layer import AtmosphereLayer
    from skydome.clouds.layer import CloudLayer
    from skydome.clouds.params import Clouds
    from tests.antisolar_strip import antisolar_strip
    from tests.conftest import TINY_TABLES

    rain = CloudLayer(Clouds("overcast", uniform=True, optical_depth=0.001,
                             precipitation_extinction_per_m=1e-3, rain_fraction=rain_fraction))  # fmt: skip
    sky = Sky(sun_elevation_deg=10.0, sun_azimuth_deg=270.0,
              layers=[AtmosphereLayer("earth", config=TINY_TABLES), rain])  # fmt: skip
    camera, w, h, theta = antisolar_strip()  # the probe's rows are top first too
    try:
        sky.graph.update(sky.state)
        radiance, _ = rain.probe(camera, w, h, 2.0, test_irradiance=1.0)
    finally:
        sky.release()
    light = radiance[:, 2, 1]
    red, blue = radiance[:, 2, 0], radiance[:, 2, 2]
    primary = theta[np.argmax(np.where((theta > 133) & (theta < 145), light, 0))]
    secondary = theta[np.argmax(np.where((theta > 124) & (theta < 132), light, 0))]
    band = light[(theta > 131) & (theta < 136)].mean()
    second = light[(theta > 127) & (theta < 131)].max()
    inside = light[(theta > 140) & (theta < 146)].mean()
    if rain_fraction == 1.0:
        assert abs(primary - 137.9) < 1.0 and abs(secondary - 129.1) < 1.0, (primary, secondary)
        assert light.max() > 4.0 * band and band < 0.5 * inside
        assert second > 1.3 * light[(theta > 131) & (theta < 133)].mean()

        # the colours: red outside the primary (a smaller scattering angle) than blue, and
        # inside the secondary (the order reversed)
        def peak(channel, lo, hi):
            return theta[np.argmax(np.where((theta > lo) & (theta < hi), channel, 0))]

        assert peak(red, 133, 145) < peak(blue, 133, 145)
        assert peak(red, 124, 132) > peak(blue, 124, 132)
    else:
        assert second <= light[(theta > 131) & (theta < 133)].mean()


@pytest.mark.gl
def test_look_antisun_aims_opposite_the_sun(tmp_path):
    """`Sky.camera("antisun")` and `--look antisun` aim at the antisolar point: the view's
    centre is opposite the Sun to 1e-9; the command line knows the same looks as the API."""
    from skydome import Sky
    from skydome.cli.describe import LOOKS as CLI_LOOKS
    from skydome.sky import LOOKS
    from tests.cli_helpers import run_cli

    assert CLI_LOOKS == LOOKS
    with Sky(sun_elevation_deg=23.0, sun_azimuth_deg=250.0) as sky:
        camera = sky.camera("antisun", fov_deg=60)
        centre, _ = camera.directions(16.0, 9.0, 32, 18)
        sun = sky.state.sun
        e, a = math.radians(sun.elevation_deg), math.radians(sun.azimuth_deg)
        towards_sun = np.array([math.sin(a) * math.cos(e), math.cos(a) * math.cos(e), math.sin(e)])
    assert float(np.dot(np.ravel(centre), towards_sun)) == pytest.approx(-1.0, abs=1e-9)
    out = tmp_path / "antisun.png"
    r = run_cli("render", "--sun-elevation", "20", "--look", "antisun", "--size", "32x18",
                "-o", str(out))  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert out.exists()


@pytest.mark.gl
def test_moonlit_rain_shows_a_moonbow():
    """Valletta, 2018-03-01 19:00 UTC: the Sun 25.7 deg down (night), the full Moon 28.5 deg up
    in the east, the key light of the clouds. A uniform rain seen through Sky along the anti-lunar
    vertical draws the primary bow within 1 deg of Descartes' angle from the Moon (137.9 deg),
    brighter than Alexander's band outside it."""
    import datetime as dt

    from skydome import Sky
    from skydome.atmosphere.layer import AtmosphereLayer
    from skydome.clouds.layer import CloudLayer
    from skydome.clouds.params import Clouds
    from skydome.core.cameras import PerspectiveCamera
    from tests.conftest import TINY_TABLES

    rain = CloudLayer(Clouds("overcast", uniform=True, optical_depth=0.001,
                             precipitation_extinction_per_m=1e-3))  # fmt: skip
    time = dt.datetime(2018, 3, 1, 19, 0, tzinfo=dt.timezone.utc)
    w, h = 4, 240
    with Sky(place="valletta", time=time,
             layers=[AtmosphereLayer("earth", config=TINY_TABLES), rain]) as sky:  # fmt: skip
        moon = sky.state.moon
        assert sky.state.sun.elevation_deg < -8.0 and moon.elevation_deg > 10.0
        camera = PerspectiveCamera(
            fov_deg=2 * math.degrees(math.atan(math.tan(math.radians(22.0)) * w / h)),
            yaw_deg=(moon.azimuth_deg + 180.0) % 360.0, pitch_deg=42.0 - moon.elevation_deg,
        )  # fmt: skip
        frame = sky.render(camera, w, h, exposure=None)
        dirs, _ = camera.directions(np.full(h, 2.0), np.arange(h) + 0.5, w, h)
    e, a = math.radians(moon.elevation_deg), math.radians(moon.azimuth_deg)
    towards = np.array([math.sin(a) * math.cos(e), math.cos(a) * math.cos(e), math.sin(e)])
    theta = np.degrees(np.arccos(np.asarray(dirs) @ towards))[::-1]  # rows top first
    light = frame.data[:, 2, 1]
    primary = theta[np.argmax(np.where((theta > 133) & (theta < 145), light, 0))]
    assert abs(primary - 137.9) < 1.0, primary
    assert light.max() > 2.0 * light[(theta > 131) & (theta < 136)].mean()


@pytest.mark.gl
def test_no_rain_no_bow_the_frame_is_bit_identical():
    """Clouds without rain: the frame is the same to the bit whether their precipitation
    would be rain (scattering by the drops' optics, the bows) or snow: the rain's optics
    touch nothing where no rain falls."""
    from skydome import Sky
    from skydome.clouds.params import Clouds

    frames = []
    for rain_fraction in (1.0, 0.0):
        clouds = Clouds("fair", rain_fraction=rain_fraction)
        with Sky(sun_elevation_deg=15.0, sun_azimuth_deg=270.0, clouds=clouds) as sky:
            frames.append(sky.render(sky.camera("antisun", fov_deg=90), 64, 36, exposure=None))
    assert np.array_equal(frames[0].data, frames[1].data)


@pytest.mark.gl
def test_sky_draws_supernumeraries_for_drops_of_one_size():
    """Through Sky, sunlit uniform rain along the antisolar vertical (the Sun 10 deg up):
    drops of one size (0.2 mm, a 10 % spread) draw a supernumerary arc inside the primary
    (a second maximum 138-142.5 deg from the Sun); Marshall-Palmer rain (4 mm/h) one maximum
    there."""
    from skydome import Sky
    from skydome.atmosphere.layer import AtmosphereLayer
    from skydome.clouds.layer import CloudLayer
    from skydome.clouds.params import Clouds
    from tests.antisolar_strip import antisolar_strip
    from tests.conftest import TINY_TABLES

    camera, w, h, theta = antisolar_strip(h=480)
    inside = np.where((theta > 138.0) & (theta < 142.5))[0]
    counts = []
    for radius in (0.2, None):
        rain = CloudLayer(Clouds("overcast", uniform=True, optical_depth=0.001,
                                 precipitation_extinction_per_m=1e-3,
                                 rain_drop_radius_mm=radius))  # fmt: skip
        with Sky(sun_elevation_deg=10.0, sun_azimuth_deg=270.0,
                 layers=[AtmosphereLayer("earth", config=TINY_TABLES), rain]) as sky:  # fmt: skip
            light = sky.render(camera, w, h, exposure=None).data[:, 2, 1]
        # maxima standing 2 % over the lowest light within 0.5 deg (6 rows) on each side
        # (the march's sampling leaves bumps of < 0.5 %)
        counts.append(sum(
            1 for i in inside
            if light[i] > light[i - 1] and light[i] >= light[i + 1]
            and light[i] - max(light[i - 6 : i].min(), light[i + 1 : i + 7].min()) > 0.02 * light[i]
        ))  # fmt: skip
    assert counts[0] >= 2 and counts[1] == 1, counts
