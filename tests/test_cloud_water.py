"""The clouds carry the water their parameters ask for, an overcast is overcast, and the sky
probe lights the ground with the sky that is drawn: all through ``Sky`` (the user's path).

The census (``CloudLayer.column_optical_depths``) integrates the same extinction field the
march, the light and the shadows see. Tolerances: the issue's 10 % on the mean column of a
closed deck (seeds and thicknesses other than the calibration's: tools/calibrate_cloud_water.py
measured WATER_NORMALIZATION on seeds 1-3 at one thickness per type; the seed-to-seed spread
there was 2-4 %); 25 % on a cloud's column at half coverage (the map's soft edges thin it).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from skydome import Clouds, DirectionsCamera, FisheyeCamera, PerspectiveCamera, Sky, preset
from skydome.atmosphere.illuminance import horizontal_illuminance
from skydome.clouds.params import CLOUD_TYPES

DISORT = Path(__file__).parent / "data" / "disort_cloud_decks.json"


def census(clouds: Clouds) -> tuple[np.ndarray, float]:
    with Sky(sun_elevation_deg=45.0, clouds=clouds) as sky:
        sky.render(width=4, height=4)
        tau = sky.layer("clouds").column_optical_depths(96)[..., 0]
    return tau, clouds.nominal_optical_depth


@pytest.mark.parametrize("cloud_type", list(CLOUD_TYPES))
def test_a_closed_deck_holds_the_nominal_water(cloud_type):
    thickness = {"cumulonimbus": 4000.0}.get(cloud_type, 1300.0)
    clouds = Clouds(cloud_type=cloud_type, coverage=1.0, cirrus=0.0, base_m=900.0,
                    thickness_m=thickness, seed=7)  # fmt: skip
    tau, nominal = census(clouds)
    assert nominal == pytest.approx(
        1.5
        * {"stratus": 0.25, "stratocumulus": 0.3, "cumulus": 0.5, "cumulonimbus": 1.0}[cloud_type]
        / 1e-2
        * thickness
        / 1e3
    )  # 3 LWC / (2 rho_w r_eff): 150 /km per g/m^3 at 10 um
    assert tau.mean() == pytest.approx(nominal, rel=0.10)


@pytest.mark.parametrize("cloud_type", ["stratocumulus", "cumulus"])
def test_coverage_sets_the_cloudy_fraction_not_the_water_per_cloud(cloud_type):
    full, nominal = census(Clouds(cloud_type=cloud_type, coverage=1.0, cirrus=0.0, seed=4))
    half, _ = census(Clouds(cloud_type=cloud_type, coverage=0.5, cirrus=0.0, seed=4))
    cloudy_full = full > 0.01 * nominal
    cloudy_half = half > 0.01 * nominal
    assert cloudy_half.mean() < 0.75 * cloudy_full.mean()
    assert half[cloudy_half].mean() == pytest.approx(full[cloudy_full].mean(), rel=0.25)


@pytest.mark.parametrize("preset", ["overcast", "nimbostratus"])
def test_a_closed_sheet_has_no_holes(preset):
    tau, nominal = census(Clouds(preset, seed=11))
    assert tau.min() > 0.25 * nominal
    assert tau.mean() == pytest.approx(nominal, rel=0.10)


def test_the_census_is_in_frame_info():
    with Sky(sun_elevation_deg=30.0, clouds="overcast") as sky:
        info = sky.render(width=16, height=8).info
    assert info["cloud_optical_depth"] == pytest.approx(37.5)
    assert info["cloud_fraction"] == 1.0
    assert info["cloud_optical_depth_mean"] == pytest.approx(37.5, rel=0.10)


def horizontal_illuminance_of(frame, width: int) -> float:
    """lx on a horizontal surface from an upward fisheye frame: sum of L cos(theta) dOmega."""
    cam = FisheyeCamera()
    x, y = np.meshgrid(np.arange(width) + 0.5, np.arange(width) + 0.5)
    d, ok = cam.directions(x, y, width, width)
    inside = ok & (d[..., 2] > 0)
    omega = cam.solid_angle(d, width, width)
    lum = frame.luminance
    return float(np.sum(np.where(inside, lum * d[..., 2] * omega, 0.0)))


def test_overcast_lets_through_what_overcasts_do():
    """Measured overcast skies pass 10-35 % of the clear sky's global illuminance (the
    issue's bound; CIE 110-1994 and Kittler et al. 1998 give 10-30 % for dense overcast);
    the Sun's disk does not show through (no pixel above 1e6 cd/m^2 within 2 deg of it;
    the clear Sun's disk is ~1e9)."""
    clear = horizontal_illuminance(45.0)[0]
    clear_global = clear.direct_horizontal_lux + clear.diffuse_horizontal_lux
    n = 192
    with Sky(sun_elevation_deg=45.0, sun_azimuth_deg=180.0, clouds="overcast") as sky:
        fisheye = sky.render(FisheyeCamera(), n, n)
        e = horizontal_illuminance_of(fisheye, n)
        sun_view = PerspectiveCamera(fov_deg=2.0, yaw_deg=180.0, pitch_deg=45.0)
        sun = sky.render(sun_view, 32, 32)
    assert 0.10 * clear_global < e < 0.35 * clear_global, e / clear_global
    assert sun.luminance.max() < 1e6
    # the gradation brightens towards the zenith (CIE overcast: L(h)/Lz = (1 + 2 sin h) / 3)
    assert np.all(np.isfinite(fisheye.data))


def test_the_probe_sees_the_clear_sky_where_there_are_no_clouds():
    """With a cloud deck far too thin to matter (optical depth 1e-4) the probe's horizontal
    irradiance is the clear sky's diffuse light from the atmosphere's own irradiance
    tables (atmosphere.illuminance, another code path): within 3 % (a 64 x 32 map)."""
    clear = horizontal_illuminance(30.0)[0]
    clouds = Clouds(cloud_type="stratus", coverage=1.0, optical_depth=1e-4, cirrus=0.0)
    with Sky(sun_elevation_deg=30.0, clouds=clouds) as sky:
        sky.render(width=8, height=8)
        probe = sky.layer("clouds").sky_probe()
    lum = float(probe.irradiance[:3] @ np.array([0.2126, 0.7152, 0.0722]))
    assert lum == pytest.approx(clear.diffuse_horizontal_lux, rel=0.03)
    assert probe.ratio == pytest.approx((1.0,) * 4, rel=0.03)
    # the spherical harmonics give the same horizontal irradiance (the map's own integral)
    assert probe.irradiance_towards([0.0, 0.0, 1.0]) == pytest.approx(probe.irradiance, rel=0.03)


def test_under_an_overcast_the_ground_is_lit_by_the_cloudy_sky():
    """The ground's colour follows the grey overcast, not the clear sky's blue: the ground's
    B/R ratio under the overcast is within 15 % of the cloud base's (before: navy, 1.9x)."""
    # a grey ground (the default grassland is itself olive)
    with Sky(sun_elevation_deg=45.0, clouds="overcast", ground=0.3) as sky:
        cam = PerspectiveCamera(fov_deg=60.0, yaw_deg=0.0, pitch_deg=0.0)
        f = sky.render(cam, 64, 64)
    ground = f.data[48:, :, :3].reshape(-1, 3).mean(0)
    cloud = f.data[:12, :, :3].reshape(-1, 3).mean(0)
    assert ground[2] / ground[0] == pytest.approx(cloud[2] / cloud[0], rel=0.15)
    assert math.isfinite(float(ground.sum()))


def overcast_gradation(sun_elevation_deg: float, albedo: float, els: np.ndarray) -> np.ndarray:
    """L(h) / L(zenith) of the overcast preset, averaged over 36 azimuths."""
    azs = np.radians(np.arange(0.0, 360.0, 10.0))
    el, az = np.meshgrid(np.radians(els), azs, indexing="ij")
    d = np.stack([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)], -1)
    atmosphere = preset("earth").with_albedo(albedo)
    with Sky(sun_elevation_deg=sun_elevation_deg, clouds="overcast", atmosphere=atmosphere) as sky:
        lum = sky.render(DirectionsCamera(d)).luminance.mean(1)
    return lum / lum[-1]


@pytest.mark.parametrize("sun_elevation_deg", [60.0, 30.0])
def test_the_overcast_gradation_is_the_cie_overcast_sky(sun_elevation_deg):
    """Over a black ground the overcast's gradation is the CIE standard overcast sky's,
    L(h)/Lz = (1 + 2 sin h) / 3 (CIE S 011/E:2003, type 1), within 20 %: DISORT's
    plane-parallel deck of the same optical depth is within 3 % of it
    (tests/data/disort_cloud_decks.json, tau 40, albedo 0); the textured deck departs from
    a plane-parallel one (measured: up to 15 % at 20 deg with the Sun at 60 deg; the spread
    over the 36 azimuths averaged is 4-9 %, so the mean's own noise is ~1.5 %)."""
    els = np.array([10.0, 20.0, 30.0, 45.0, 60.0, 75.0, 90.0])
    cie = (1.0 + 2.0 * np.sin(np.radians(els))) / 3.0
    g = overcast_gradation(sun_elevation_deg, 0.0, els)
    assert np.all(np.abs(g / cie - 1.0) < 0.20), np.round(g / cie, 3)


def test_the_overcast_gradation_over_a_bright_ground_is_disorts():
    """Over the ground of earth (albedo 0.3) the horizon brightens (the ground's light
    reflected back by the cloud base): DISORT's deck of optical depth 37.5 gives 1.28x the
    CIE value at 10 deg; the overcast follows DISORT's gradation within 15 % (as above)."""
    ref = next(c for c in json.loads(DISORT.read_text())["cases"]
               if c["cloud_optical_depth"] == 37.5)  # fmt: skip
    els = np.asarray(json.loads(DISORT.read_text())["view_elevations_deg"], dtype=float)
    disort = np.asarray(ref["L_over_E0_per_sr"]).mean(1) / ref["zenith_L_over_E0_per_sr"]
    g = overcast_gradation(45.0, 0.3, els)
    assert np.all(np.abs(g / disort - 1.0) < 0.15), np.round(g / disort, 3)
