"""Ice halos in the cirrus: the crystal mixture's table (skydome.clouds.halos) and what Sky
draws with it.

The places checked are the prisms' (see tests/test_crystal_optics.py): the 22 deg halo's
inner edge at the 60 deg prism's minimum deviation (21.6 deg in red to 22.6 deg in violet;
21.9 deg in green), the sun dogs' at the oblique prism's in azimuth (24.55 deg at 589 nm for a
Sun 20 deg up), the circumzenithal arc at asin(sqrt(n^2 - cos^2 e)) (65.8 deg).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from skydome.clouds.halos import (
    DEFAULT_HALOS,
    GRID_DEG,
    halo_table,
    parse_halos,
    table_angles_deg,
)
from skydome.core.basis import SpectralBasis
from skydome.errors import ParameterError
from skydome.physics.crystal_optics import ice_index
from skydome.spectra import ACCURATE_NM
from tests.optics_formulas import minimum_deviation_deg, sun_dog_deg

SUN_DEG = 20.0


def test_parse_halos():
    assert parse_halos("none") == ()
    assert parse_halos("columns,plates") == (("columns", 0.5), ("plates", 0.5))
    assert parse_halos(" Random:3, plates:1 ") == (("random", 0.75), ("plates", 0.25))
    assert sum(share for _, share in parse_halos(DEFAULT_HALOS)) == pytest.approx(1.0)
    for bad in ("", "cubes", "random:x", "random:-1", "plates:0", 3):
        with pytest.raises(ParameterError):
            parse_halos(bad)


@pytest.fixture(scope="module")
def basis():
    return SpectralBasis.for_wavelengths(ACCURATE_NM)


@pytest.fixture(scope="module")
def plates_table(basis):
    return halo_table("plates", SUN_DEG, basis.wavelengths_nm, basis.to_output)


def _solid_angles():
    el, _ = table_angles_deg()
    edges = np.radians(np.append(el - GRID_DEG / 2.0, 90.0))
    return 2.0 * math.radians(GRID_DEG) * np.diff(np.sin(edges))


def test_table_is_a_phase_function_per_channel(plates_table, basis):
    # each channel integrates to 1 over the sphere (1/sr), held >= 0; cached: the same table
    # for the same light (to the elevation step), and a new one for another mixture
    assert plates_table.shape == (4, 360, 360) and plates_table.dtype == np.float32
    total = (plates_table * _solid_angles()[None, :, None]).sum(axis=(1, 2))
    assert np.allclose(total, 1.0, rtol=1e-5)
    assert plates_table.min() >= 0.0
    again = halo_table("plates", SUN_DEG + 0.3, basis.wavelengths_nm, basis.to_output)
    assert again is plates_table


def test_table_draws_sun_dogs_and_circumzenithal_arc_in_place(plates_table):
    # green: along the parhelic circle (the Sun's elevation) the light rises most steeply at
    # the sun dog's inner edge (589 nm: 24.55 deg; the channel spans ~24.4-24.8) within 0.5
    # deg (the table's 0.5 deg cells and the Sun's disk); the circumzenithal arc peaks at its
    # elevation within 0.5 deg, near the Sun's azimuth
    el, az = table_angles_deg()
    green = plates_table[1]
    row = green[np.argmin(np.abs(el - SUN_DEG))]
    inside = (az > 18.0) & (az < 32.0)
    edge = az[inside][int(np.argmax(np.diff(row[inside])))] + GRID_DEG / 2.0
    assert edge == pytest.approx(sun_dog_deg(float(ice_index(550.0)), SUN_DEG), abs=0.5)
    column = green[:, 0]
    high = el > 50.0
    n = float(ice_index(550.0))
    cza = math.degrees(math.asin(math.sqrt(n * n - math.cos(math.radians(SUN_DEG)) ** 2)))
    assert el[high][int(np.argmax(column[high]))] == pytest.approx(cza, abs=0.5)
    # red inside: the sun dog's red channel rises no later than its blue
    level = np.argmin(np.abs(el - SUN_DEG))
    red, blue = (az[inside][int(np.argmax(np.diff(plates_table[c][level][inside])))]
                 for c in (0, 2))  # fmt: skip
    assert red <= blue


def test_no_circumzenithal_arc_with_the_sun_above_32_degrees(basis):
    # above 32.2 deg the arc cannot leave the plates: near the zenith and the Sun's azimuth
    # there is (all but) no light, where at 20 deg the arc is (under 1 % of its peak)
    el, az = table_angles_deg()
    region = (el[:, None] > 60.0) & (az[None, :] < 30.0)
    peaks = {}
    for sun in (20.0, 36.0):
        green = halo_table("plates", sun, basis.wavelengths_nm, basis.to_output)[1]
        peaks[sun] = green[region].max()
    assert peaks[36.0] < 0.01 * peaks[20.0], peaks


# ---------------------------------------------------------------------------- through Sky

W, H = 280, 200
FOV = 70.0


def _render(halos: str, cirrus: float = 1.0, clouds: str = "cirrus"):
    from skydome import Sky
    from skydome.clouds.params import Clouds

    with Sky(sun_elevation_deg=SUN_DEG, sun_azimuth_deg=180.0,
             clouds=Clouds(clouds, cirrus=cirrus, halos=halos)) as sky:  # fmt: skip
        camera = sky.camera("sun", fov_deg=FOV)
        frame = sky.render(camera, W, H, exposure=None)
        x, y = np.meshgrid(np.arange(W) + 0.5, np.arange(H) + 0.5)
        dirs, _ = camera.directions(x, y, W, H)
    return frame.data, np.asarray(dirs)[::-1]  # the frame's rows are top first


@pytest.fixture(scope="module")
def frames():
    plain, dirs = _render("none")
    return dirs, plain, {h: _render(h)[0] for h in ("random", "plates")}


def _sun_vector():
    e, a = math.radians(SUN_DEG), math.radians(180.0)
    return np.array([math.sin(a) * math.cos(e), math.cos(a) * math.cos(e), math.sin(e)])


def _steepest(x, ratio, lo, hi, step=0.25):
    edges = np.arange(lo, hi + step / 2.0, step)
    which = np.digitize(x, edges) - 1
    medians = np.array([np.median(ratio[which == k]) for k in range(edges.size - 1)])
    return edges[int(np.argmax(np.diff(medians))) + 1], medians


@pytest.mark.gl
def test_sky_draws_the_22_degree_halo(frames):
    # randomly oriented crystals over the sky: the frame over the frame without halos, by the
    # angle from the Sun (the cirrus's streaks divide out), rises most steeply at the 22 deg
    # halo's inner edge (green: 21.9 deg) within 0.5 deg, and is darker inside it than on it
    dirs, plain, drawn = frames
    angle = np.degrees(np.arccos(np.clip(dirs @ _sun_vector(), -1.0, 1.0)))
    ratio = drawn["random"][..., 1] / plain[..., 1]
    edge, medians = _steepest(angle.ravel(), ratio.ravel(), 17.0, 27.0)
    assert edge == pytest.approx(minimum_deviation_deg(float(ice_index(550.0)), 60.0), abs=0.5)
    assert medians.max() > 1.1 * medians[:8].mean()


@pytest.mark.gl
def test_sky_draws_sun_dogs_beside_the_sun(frames):
    # horizontal plates: along the Sun's elevation the ratio rises at the sun dog's inner edge
    # (24.55 deg of azimuth) within 0.5 deg, on both sides
    dirs, plain, drawn = frames
    d = dirs
    elevation = np.degrees(np.arcsin(d[..., 2]))
    azimuth = np.degrees(np.arctan2(d[..., 0], -d[..., 1]))  # from the Sun's (south)
    level = np.abs(elevation - SUN_DEG) < 0.75
    ratio = drawn["plates"][..., 1] / plain[..., 1]
    expected = sun_dog_deg(float(ice_index(550.0)), SUN_DEG)
    for side in (1.0, -1.0):
        pick = level & (side * azimuth > 0)
        edge, _ = _steepest(side * azimuth[pick], ratio[pick], 18.0, 30.0)
        assert edge == pytest.approx(expected, abs=0.5), side


@pytest.mark.gl
def test_frames_without_cirrus_do_not_depend_on_the_halos():
    # no cirrus, no crystals: the same frame to the bit whatever the halos asked for
    a, _ = _render("none", cirrus=0.0, clouds="fair")
    b, _ = _render(DEFAULT_HALOS, cirrus=0.0, clouds="fair")
    assert np.array_equal(a, b)


def test_diamond_dust_is_a_layer_of_crystals():
    from skydome.weather import Weather

    assert Weather("diamond-dust").fog_ice is True and Weather("fog").fog_ice is False
    with pytest.raises(ParameterError):
        Weather("sunny", fog_ice=True)  # crystals need a layer
    with pytest.raises(ParameterError):
        Weather("fog", fog_ice="yes")


@pytest.mark.gl
def test_diamond_dust_draws_the_22_degree_halo_near_the_ground():
    # the diamond-dust weather (crystals to 300 m, 12 km of visibility, no cloud): its frame
    # over the same without halos rises at the 22 deg halo's inner edge within 0.5 deg
    from skydome import Sky
    from skydome.clouds.params import Clouds
    from skydome.weather import Weather

    frames = {}
    for halos in ("random", "none"):
        with Sky(sun_elevation_deg=SUN_DEG, sun_azimuth_deg=180.0, weather=Weather("diamond-dust"),
                 clouds=Clouds("clear", halos=halos)) as sky:  # fmt: skip
            camera = sky.camera("sun", fov_deg=FOV)
            frames[halos] = sky.render(camera, W, H, exposure=None).data[..., 1]
            x, y = np.meshgrid(np.arange(W) + 0.5, np.arange(H) + 0.5)
            dirs = np.asarray(camera.directions(x, y, W, H)[0])[::-1]
    angle = np.degrees(np.arccos(np.clip(dirs @ _sun_vector(), -1.0, 1.0)))
    sky_pixels = dirs[..., 2] > 0.02
    ratio = frames["random"] / frames["none"]
    edge, medians = _steepest(angle[sky_pixels], ratio[sky_pixels], 17.0, 27.0)
    assert edge == pytest.approx(minimum_deviation_deg(float(ice_index(550.0)), 60.0), abs=0.5)
    assert medians.max() > 1.05 * medians[:8].mean()


def test_cli_halos_with_a_weather_and_bad_crystals(tmp_path):
    # --halos chooses diamond dust's crystals too; an unknown crystal: one line, status 2,
    # nothing written
    from tests.cli_helpers import run_cli

    out = tmp_path / "bad.png"
    r = run_cli("render", "--weather", "diamond-dust", "--halos", "cubes", "--size", "32x18",
                "-o", str(out))  # fmt: skip
    assert r.returncode == 2 and "halo crystals 'cubes'" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and not out.exists()
