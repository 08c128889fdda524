"""A uniform cloud deck drawn by ``Sky`` against DISORT (tests/data/disort_cloud_decks.json,
made offline by tools/make_disort_cloud_reference.py: DISORT 2.1.3, 64 streams, Mie droplets
r_eff 10 um, the earth atmosphere in 24 plane-parallel layers, luminous weighting of
380-780 nm; see its provenance).

The deck is the user's: ``Clouds(cloud_type="stratus", optical_depth=tau, uniform=True)``
from 1000 to 2000 m, drawn through ``Sky`` at "best" quality (every pixel marched), with the
atmosphere's ground albedo set to DISORT's. Quantities are over the extraterrestrial luminous
irradiance E_v0 (the renderer's Sun: skydome.spectra.colour.LUMINOUS_SOLAR_CONSTANT_LX
within 0.12 %). Tolerances (issue 22): zenith luminance and horizontal illuminance within
10 %; the gradation L(h)/L(zenith) within 10 % from 10 to 90 deg of elevation at azimuths 0,
90 and 180 deg from the Sun's, except the Sun's own direction (DISORT's radiance there
depends on how the droplets' forward peak is truncated; the reference file says so).
"""

from __future__ import annotations

import json
import math
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from skydome import CloudLayer, Clouds, DirectionsCamera, FisheyeCamera, Sky, preset
from skydome.spectra.colour import LUMINOUS_SOLAR_CONSTANT_LX

DATA = Path(__file__).parent / "data" / "disort_cloud_decks.json"
FISHEYE = 160


@cache
def reference() -> dict:
    return json.loads(DATA.read_text())


def case_key(c: dict) -> tuple:
    return c["cloud_optical_depth"], c["sun_elevation_deg"], c["ground_albedo"]


#: Where the drawn deck misses the issue's 10 % today (strict xfail, so that a fix shows):
#: (optical depth, Sun elevation, albedo) -> why. Since the clouds scatter with the tabulated
#: Mie phase function and the multiple-scattering table samples the light's zenith angle
#: uniformly (2026-12-05), every zenith luminance is 0.94-1.01 of DISORT's and every
#: illuminance 0.90-0.98 (a deficit of 3-9 % that the light model alone does not have: it
#: matches the Monte Carlo of the same truncated phase function within 2.5 %). The gradation
#: of (40, 45, 0), 10.2 % off in one direction, came within 10 % when the phase table was
#: integrated over 16000 radii and the table rebuilt for it (2026-12-05): none is known off.
KNOWN_GAPS: dict[str, dict[tuple, str]] = {"zenith": {}, "gradation": {}}


def cases(check: str):
    out = []
    for c in reference()["cases"]:
        if c["cloud_optical_depth"] not in (5.0, 20.0, 40.0):
            continue
        why = KNOWN_GAPS[check].get(case_key(c))
        marks = [pytest.mark.xfail(strict=True, reason=why)] if why else []
        name = f"tau{c['cloud_optical_depth']:g}-sun{c['sun_elevation_deg']:g}"
        out.append(pytest.param(c, id=f"{name}-albedo{c['ground_albedo']:g}", marks=marks))
    return out


def horizontal_illuminance(frame, n: int) -> float:
    """lx on a horizontal surface from an upward fisheye frame (sum of L cos theta dOmega)."""
    cam = FisheyeCamera()
    x, y = np.meshgrid(np.arange(n) + 0.5, np.arange(n) + 0.5)
    d, ok = cam.directions(x, y, n, n)
    inside = ok & (d[..., 2] > 0)
    return float(
        np.sum(np.where(inside, frame.luminance * d[..., 2] * cam.solid_angle(d, n, n), 0))
    )


def drawn(case: dict):
    """(zenith L/E0, E/E0, L/E0 at the reference's elevations x azimuths) of the drawn deck."""
    ref = reference()
    clouds = Clouds(cloud_type="stratus", base_m=1000.0, thickness_m=1000.0,
                    optical_depth=case["cloud_optical_depth"], uniform=True)  # fmt: skip
    sun_az = 180.0
    els = np.radians(ref["view_elevations_deg"])
    azs = np.radians(sun_az + np.asarray(ref["relative_azimuths_deg"]))
    el, az = np.meshgrid(els, azs, indexing="ij")
    dirs = np.stack([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)], -1)
    with Sky(
        sun_elevation_deg=case["sun_elevation_deg"], sun_azimuth_deg=sun_az,
        atmosphere=preset("earth").with_albedo(case["ground_albedo"]),
        clouds=CloudLayer(clouds, quality="best"),
    ) as sky:  # fmt: skip
        radiance = sky.render(DirectionsCamera(dirs), altitude_m=0.0).luminance
        fisheye = sky.render(FisheyeCamera(), FISHEYE, FISHEYE, altitude_m=0.0)
    e0 = LUMINOUS_SOLAR_CONSTANT_LX
    return radiance[-1, 0] / e0, horizontal_illuminance(fisheye, FISHEYE) / e0, radiance / e0


@cache
def drawn_cached(key: tuple) -> tuple:
    case = next(c for c in reference()["cases"] if case_key(c) == key)
    return drawn(case)


@pytest.mark.parametrize("case", cases("zenith"))
def test_zenith_luminance_and_illuminance_match_disort(case):
    zenith, illuminance, _ = drawn_cached(case_key(case))
    assert zenith == pytest.approx(case["zenith_L_over_E0_per_sr"], rel=0.10)
    assert illuminance == pytest.approx(case["E_global_horizontal_over_E0"], rel=0.10)


@pytest.mark.parametrize("case", cases("gradation"))
def test_gradation_matches_disort(case):
    zenith, _, radiance = drawn_cached(case_key(case))
    ref = np.asarray(case["L_over_E0_per_sr"]) / case["zenith_L_over_E0_per_sr"]
    els = np.asarray(reference()["view_elevations_deg"])
    azs = np.asarray(reference()["relative_azimuths_deg"])
    sun_dir = np.isclose(els, case["sun_elevation_deg"])[:, None] & np.isclose(azs, 0.0)[None]
    rel = np.abs(radiance / zenith / ref - 1.0)
    assert np.all(rel[~sun_dir] < 0.10), np.round(rel, 3)
    assert math.isfinite(zenith)
