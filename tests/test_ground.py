"""What lies below the horizon (`Sky(ground=...)`, `--ground none|black|ALBEDO`), and the air
in front of the ground at dusk (the sky-view tables' ground rays: no dark band)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from skydome.atmosphere.ground import ground_albedo, parse_ground
from skydome.errors import ParameterError
from skydome.physics.refraction import horizon_dip_sin
from skydome.spectra import SRGB_LUMINANCE
from tests.cli_helpers import run_cli

PARIS_DUSK = {"place": "paris", "time": "2024-07-05T20:30Z"}  # the Sun 4.5 deg down
CAMERA_M = 36.7  # Paris's 35 m and the standing eye (Sky.altitude_m)


def column_dirs(azimuth_deg: float, elevations_deg) -> np.ndarray:
    a = math.radians(azimuth_deg)
    e = np.radians(np.asarray(elevations_deg, dtype=np.float64))
    return np.stack([np.sin(a) * np.cos(e), np.cos(a) * np.cos(e), np.sin(e)], axis=1)


def luminance_along(sky, dirs: np.ndarray) -> np.ndarray:
    """The luminance Y (cd/m^2) of the rays ``dirs`` (ENU unit vectors)."""
    from skydome.core.cameras import DirectionsCamera

    frame = sky.render(DirectionsCamera(dirs), 0, 0, exposure=None)
    return np.asarray(frame.data[..., :3], dtype=np.float64).reshape(-1, 3) @ SRGB_LUMINANCE


def test_ground_settings_are_parsed():
    assert parse_ground(None) is None
    assert parse_ground(" Black ") == "black" and parse_ground("none") == "none"
    assert parse_ground("0.2") == 0.2 and parse_ground(0) == 0.0
    assert ground_albedo("none") == 0.0 and ground_albedo(0.25) == 0.25
    assert ground_albedo("black") is None and ground_albedo(None) is None
    for bad in ("grass", 1.5, -0.1, float("nan"), True, "0.2.1"):
        with pytest.raises(ParameterError, match="ground"):
            parse_ground(bad)


def test_dip_is_the_horizon_of_the_sphere():
    # from 36.7 m above a 6371 km sphere the horizon lies 0.1945 deg down (sqrt(2h/R) rad,
    # the textbook geometric dip), and a ray at that elevation grazes the sphere
    s = horizon_dip_sin(CAMERA_M, 6_371_000.0)
    assert math.degrees(math.asin(s)) == pytest.approx(
        math.degrees(math.sqrt(2 * CAMERA_M / 6_371_000.0)), rel=1e-4
    )


@pytest.mark.gl
def test_black_ground_zeroes_below_the_horizon_and_keeps_the_sky():
    # every ray below the camera's horizon is exactly 0; every ray above it is the default
    # sky's to the bit (the layer passes what lies behind through)
    from skydome import Sky

    elevations = np.concatenate([np.linspace(-89.0, -0.25, 40), np.linspace(-0.14, 89.0, 40)])
    dirs = column_dirs(300.0, elevations)
    with Sky(**PARIS_DUSK) as sky:
        plain = luminance_along(sky, dirs)
    with Sky(ground="black", **PARIS_DUSK) as sky:
        black = luminance_along(sky, dirs)
    below = elevations < -0.2
    assert np.all(black[below] == 0.0) and np.all(plain[below] > 0.0)
    assert np.array_equal(black[~below], plain[~below])


@pytest.mark.gl
def test_albedo_ground_is_the_atmosphere_with_that_albedo():
    from skydome import Sky
    from skydome.atmosphere import preset

    dirs = column_dirs(120.0, [-30.0, -5.0, -1.0, 5.0, 45.0])
    where = {"sun_elevation_deg": 25.0}
    with Sky(ground=0.1, **where) as sky:
        got = luminance_along(sky, dirs)
    with Sky(atmosphere=preset("earth").with_albedo(0.1), **where) as sky:
        want = luminance_along(sky, dirs)
    assert np.array_equal(got, want)


def test_surface_albedos_are_the_cmaq_table():
    # the IGBP reference spectral albedos of the U.S. EPA's CMAQ (ALBEDO_REFER_DATA.F) at its
    # band centres, and the named grounds and the measured Earth's presets stand on them
    from skydome.atmosphere import preset
    from skydome.spectra import photopic_efficiency, solar_irradiance, surface_albedo

    published = {  # surface: (467.5, 546.25, 642.3 nm)
        "grassland": (0.045, 0.126, 0.129),
        "forest": (0.033, 0.056, 0.057),
        "desert": (0.179, 0.263, 0.331),
        "snow": (0.992, 0.989, 0.982),
        "ocean": (0.091, 0.078, 0.072),
    }
    for surface, values in published.items():
        wl, albedo = surface_albedo(surface)
        assert np.interp([467.5, 546.25, 642.3], wl, albedo) == pytest.approx(values, abs=1e-12)
    grass = ground_albedo("grassland")
    assert preset("earth").ground_albedo == grass and parse_ground(" Grassland ") == "grassland"
    assert preset("desert").ground_albedo == ground_albedo("desert")
    # grassland under the Sun: a luminous albedo of 0.12 (not the grey 0.3 of before)
    wl = np.arange(380.0, 781.0, 5.0)
    weight = photopic_efficiency(wl) * solar_irradiance(wl)
    assert np.sum(grass.at(wl) * weight) / np.sum(weight) == pytest.approx(0.116, abs=0.002)


@pytest.mark.gl
def test_default_ground_is_grassland_seen_from_the_sky():
    # the user's path: Sky's default ground is the grassland's spectral albedo (bit-identical
    # to ground="grassland"); straight down from the standing eye its luminance over that of
    # a grey 0.3 ground is the ratio of their albedos in daylight, 0.116 / 0.3, within 8 %
    # (the sky's irradiance falls a few per cent with the darker ground: less light goes back
    # up to be scattered down), and it is olive-brown: R > G > B, blue under half the green
    # (the table's blue albedo is a third of its green; its red band holds the red edge)
    from skydome import Sky
    from skydome.core.cameras import DirectionsCamera

    dirs = column_dirs(0.0, [-89.0, -60.0, 30.0])
    where = {"sun_elevation_deg": 40.0, "sun_azimuth_deg": 180.0}
    with Sky(**where) as sky:
        frame = sky.render(DirectionsCamera(dirs), 0, 0, exposure=None)
        rgb = np.asarray(frame.data[..., :3], dtype=np.float64).reshape(-1, 3)
    with Sky(ground="grassland", **where) as sky:
        assert np.array_equal(luminance_along(sky, dirs), rgb @ SRGB_LUMINANCE)
    with Sky(ground=0.3, **where) as sky:
        grey = luminance_along(sky, dirs)
    ratio = (rgb @ SRGB_LUMINANCE)[:2] / grey[:2]
    assert ratio == pytest.approx([0.116 / 0.3] * 2, rel=0.08), ratio
    r, g, b = rgb[0]
    assert r > g > 2.0 * b, rgb[0]


@pytest.mark.gl
def test_air_in_front_of_the_ground_at_dusk():
    # At dusk the ground-level air is lit by the sky alone. Looking 0.25-3 deg down from 37 m
    # the ground is 0.7-20 km away, a path whose extinction (0.01 /km of air and the
    # aerosol's ~0.1 /km) takes 1-T ~ 10-85 % of the light: with a ground that reflects
    # nothing (ground="none") the air there still glows with a sizeable share of the horizon
    # sky's light (measured 23 % just below the horizon), brightening towards the horizon.
    # The bottom row of the tables' ground rays holds zero-length rays: interpolated in the
    # logarithm, it made this air black (0.0 exactly) and the lit ground below the horizon
    # a dark band.
    from skydome import Sky

    below = np.array([-3.0, -2.0, -1.0, -0.6, -0.4, -0.3, -0.25])
    dirs = column_dirs(305.0, np.concatenate([below, [0.3]]))
    with Sky(ground="none", **PARIS_DUSK) as sky:
        air = luminance_along(sky, dirs)
    horizon_sky = air[-1]
    assert 0.1 <= air[len(below) - 1] / horizon_sky <= 1.0, air / horizon_sky
    assert np.all(np.diff(air[: len(below)]) > 0.0), air
    with Sky(**PARIS_DUSK) as sky:
        lit = luminance_along(sky, dirs)
    # the lit ground (grassland) adds its light: brighter than the air alone, and no band
    # darker than the ground further down (the ground seen through the air tends to the
    # air's own glow towards the horizon)
    assert np.all(lit[: len(below)] > air[: len(below)])
    assert lit[len(below) - 1] >= 0.99 * lit[: len(below)].min(), lit


@pytest.mark.gl
def test_cli_ground(tmp_path):
    from skydome.io.exr import read_exr

    # the HDR map (the display image may carry the Sun's glare below the horizon)
    out = tmp_path / "env.exr"
    r = run_cli("render", "--sun-elevation", "10", "--camera", "equirect", "--ground", "black",
                "--size", "64x32", "-o", str(out))  # fmt: skip
    assert r.returncode == 0, r.stderr
    hdr = read_exr(out)
    hdr = np.asarray(hdr[0] if isinstance(hdr, tuple) else hdr)
    assert hdr[17:].max() == 0.0 and hdr[:15, :, :3].min() > 0.0  # the lower half black
    for args, words in (
        (("--ground", "grass"), "--ground: ground 'grass' must be none, black, an albedo"),
        (("--ground", "nowhere.png"), "is not a file"),
        (("--ground", "0.2", "--albedo", "0.2"), "--ground and --albedo"),
    ):
        bad = tmp_path / "bad.png"
        r = run_cli("render", "--sun-elevation", "10", *args, "--size", "32x18", "-o", str(bad))
        assert r.returncode == 2 and not bad.exists(), r.stderr
        assert len(r.stderr.strip().splitlines()) == 1 and words in r.stderr, r.stderr


def _band_panorama(path, srgb: int, top_deg: float = 10.0, width: int = 512) -> None:
    """An equirect panorama, grey ``srgb`` (0-255) and opaque from the nadir up to ``top_deg``
    of elevation, transparent above."""
    from PIL import Image

    h = width // 2
    el = 90.0 - (np.arange(h) + 0.5) / h * 180.0
    img = np.zeros((h, width, 4), np.uint8)
    img[..., :3] = srgb
    img[..., 3] = np.where(el < top_deg, 255, 0)[:, None]
    Image.fromarray(img).save(path)


@pytest.mark.gl
def test_a_landscape_near_by_is_lit_as_the_level_ground(tmp_path):
    # A grey panorama (sRGB 188: reflectance 0.5029) standing 1 m away, in front of the Sun
    # 30 deg up: a Lambertian reflector lit as the level ground, rho E / pi with E the global
    # horizontal illuminance of the tables' probe (atmosphere.horizontal_illuminance, the
    # validated daylight: within 1 % of SPECTRL2), 1 m of air adding < 0.1 %; bound 1 %.
    # Above the panorama (transparent) the sky is the plain sky's to the bit.
    from skydome import Sky
    from skydome.atmosphere.ground import LandscapeLayer
    from skydome.atmosphere.illuminance import horizontal_illuminance

    pano = tmp_path / "band.png"
    _band_panorama(pano, 188)
    rho = ((188 / 255 + 0.055) / 1.055) ** 2.4
    dirs = column_dirs(200.0, [-20.0, -5.0, 0.0, 5.0, 20.0, 45.0])
    where = {"sun_elevation_deg": 30.0, "sun_azimuth_deg": 180.0}
    with Sky(extra_layers=[LandscapeLayer(str(pano), distance_km=0.001)], **where) as sky:
        got = luminance_along(sky, dirs)
        altitude_m = sky.altitude_m()
    with Sky(**where) as sky:
        plain = luminance_along(sky, dirs)
    e = horizontal_illuminance(30.0, altitude_m=altitude_m)[0].total_horizontal_lux
    assert np.allclose(got[:4], rho * e / math.pi, rtol=0.01), (got[:4], rho * e / math.pi)
    assert np.array_equal(got[4:], plain[4:])


@pytest.mark.gl
def test_a_far_landscape_is_veiled_by_the_air(tmp_path):
    # A dark panorama (reflectance ~0.05) 3 km away (the default) against the same 1 m away:
    # the air between adds its light and hides some of the landscape's (Koschmieder): the
    # far one is brighter than the near one, and darker than the sky above the horizon.
    from skydome import Sky
    from skydome.atmosphere.ground import LandscapeLayer

    pano = tmp_path / "dark.png"
    _band_panorama(pano, 64, top_deg=2.0)
    dirs = column_dirs(90.0, [1.0, 3.0])
    where = {"sun_elevation_deg": 30.0, "sun_azimuth_deg": 180.0}
    with Sky(ground=str(pano), **where) as sky:
        far = luminance_along(sky, dirs)
    with Sky(extra_layers=[LandscapeLayer(str(pano), distance_km=0.001)], **where) as sky:
        near = luminance_along(sky, dirs)
    assert near[0] < far[0] < far[1], (near, far)


def test_landscape_files_are_checked(tmp_path):
    from PIL import Image

    from skydome.atmosphere.ground import LandscapeLayer

    square = tmp_path / "square.png"
    Image.new("RGBA", (64, 64)).save(square)
    with pytest.raises(ParameterError, match="twice as wide as it is high"):
        LandscapeLayer(str(square))
    text = tmp_path / "notes.png"
    text.write_text("not an image")
    with pytest.raises(ParameterError, match="notes.png"):
        LandscapeLayer(str(text))
    with pytest.raises(ParameterError, match="is not a file"):
        parse_ground(str(tmp_path / "missing.jpg"))
    assert parse_ground(str(square)) == str(square)
