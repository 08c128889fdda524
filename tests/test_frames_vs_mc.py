"""Frames of the precomputed renderer (the sky-view path and the per-pixel path), the ground
included, and the one Lambertian ground shading (common/ground_shading.glsl) against the Monte
Carlo reference at the 16 render wavelengths (tools/make_ms_reference.py --luminance)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from skydome.atmosphere import precompute_probe as probe
from skydome.core.cameras import DirectionsCamera
from skydome.reference import ms as mc
from tests.air_frames import precomputed_frames as precomputed_renderer
from tests.test_default_path_vs_mc import (
    SKY_RMS_BOUNDS,
    load_mc_luminance,
    luminance,
    mc_luminance,
)


def frame_cases(data: dict):
    """(altitude index, altitude, sun index, elevation, sun, mask, ground mask) over every
    view of the reference more than 3 deg from the Sun, sky and ground."""
    dirs = np.asarray(data["view_dirs"], dtype=np.float64)
    for ia, alt in enumerate(np.asarray(data["camera_altitude_m"], dtype=np.float64)):
        ground = np.asarray(data["view_hits_ground"][ia], dtype=bool)
        # Frames from "0 m" are drawn from 1 m (render.base.MIN_ALTITUDE_M); the reference's
        # ground is at the camera. Above -10 deg the 1 m camera sees the ground up to 57 m
        # away through air that scatters the low Sun forwards (+3.7% at -1 deg towards a 5 deg
        # Sun): only the views at -10 and -30 deg (air path <= 6 m) are compared.
        keep = ~ground | (dirs[:, 2] <= math.sin(math.radians(-10.0))) | (alt > 0.0)
        for js, el in enumerate(np.asarray(data["sun_elevation_deg"], dtype=np.float64)):
            sun = mc.sun_direction(float(data["sun_zenith_rad"][js]))
            ok = keep & (np.degrees(np.arccos(np.clip(dirs @ sun, -1, 1))) > 3.0)
            yield ia, alt, js, el, sun, ok, ground[ok]


def mc_total(data: dict, ia: int, js: int, ok: np.ndarray):
    """Y (cd/m^2) of all the light along the views (air + ground), and its standard error
    (low and high bounds, mc_luminance)."""
    spectra = data["radiance"][ia, js][ok] + data["ground_radiance"][ia, js][ok]
    err = np.hypot(data["stderr"][ia, js][ok], data["ground_stderr"][ia, js][ok])
    return mc_luminance(data, spectra, err)


def check(got, want, err_lo, err_hi, el, ground, what, orders):
    # Sky directions: relative RMS per case as test_default_path_vs_mc (SKY_RMS_BOUNDS).
    # Ground directions, each within 3% + 2 standard errors (high bound, 0.06-3.8%) of the
    # reference: measured with 10 orders -1.9..+0.2% by day and -7.0..+1.4% at -6 deg (noise
    # there 2-3.8%). With the default 4 orders the ground from 10 km at -6 deg is darker,
    # -1.4..-9.0% (RMS 5.0%), largest looking 30 deg down towards the Sun's azimuth: the
    # missing orders 5+, bounded by 7% RMS there.
    rel = got / want - 1.0
    sky = ~ground
    rms = np.sqrt(np.mean(rel[sky] ** 2))
    noise = np.sqrt(np.mean((err_lo[sky] / want[sky]) ** 2))
    net = rms if el >= 0.0 else math.sqrt(max(rms**2 - noise**2, 0.0))
    day_bound, twilight_bound = SKY_RMS_BOUNDS[orders]
    assert net <= (day_bound if el >= 0.0 else twilight_bound), (what, el, rms, noise)
    check_ground(rel[ground], err_hi[ground] / want[ground], el, what, orders)
    return rel


def check_ground(rel, rel_err_hi, el, what, orders):
    if el >= 0.0 or orders >= 10:
        assert np.all(np.abs(rel) <= 0.03 + 2 * rel_err_hi), (what, el, rel)
    else:
        assert np.sqrt(np.mean(rel**2)) <= 0.07, (what, el, rel)


@pytest.mark.parametrize(
    ("sky_view", "orders"),
    [(True, 10), (False, 10), (True, 4)],
    ids=["sky-view", "per-pixel", "sky-view-default-4-orders"],
)
def test_frames_match_monte_carlo(sky_view, orders):
    # PrecomputedRenderer frames (default tables; sky_view=True draws them from the per-altitude
    # sky-view tables, False looks every pixel up in the 4D tables), through
    # atmosphere/precomputed_lookup.glsl, common/ground_shading.glsl and atmosphere/surface_radiance.glsl as rendered, on a
    # DirectionsCamera, against the Monte Carlo's air light + its lit ground seen through the
    # air (reference.ms.ground_radiance_mc), luminance Y, cameras at 0 and 10 km, Sun at -6,
    # 0, 5, 20, 60 deg; rays hitting the ground: from 10 km at -4, -10, -30 deg (ground 17-150
    # km away), from 0 m at -1 to -30 deg (the ground at the camera).
    data = load_mc_luminance()
    r = precomputed_renderer(str(data["preset"]), orders=orders, sky_view=sky_view)
    dirs = np.asarray(data["view_dirs"], dtype=np.float64)
    worst_ground = 0.0
    for ia, alt, js, el, sun, ok, ground in frame_cases(data):
        want, err_lo, err_hi = mc_total(data, ia, js, ok)
        frame = r.render(DirectionsCamera(dirs[ok]), 0, 0, sun_direction=sun, altitude_m=alt)
        assert frame.info["path"] == ("sky-view" if sky_view else "direct")
        got = luminance(frame.data[0].astype(np.float64))
        rel = check(got, want, err_lo, err_hi, el, ground, (sky_view, alt), orders)
        worst_ground = max(worst_ground, float(np.abs(rel[ground]).max()))
    assert worst_ground > 0.0


def test_ground_shading_matches_monte_carlo():
    # The one ground shading (common/ground_shading.glsl) through its two other callers: the probe's
    # ground (lambertian_ground, ground="sun_and_sky") along the reference's ground rays, and
    # sun_and_sky_irradiance at the camera's ground point, whose albedo (0.3, grey) / pi times
    # Y(E_sun + E_sky) is the reference's ground radiance there (no air in front from 0 m).
    # Bounds: check_ground with 10 orders (irradiance measured -1.5..-0.1%).
    data = load_mc_luminance()
    pa = precomputed_renderer(str(data["preset"]), orders=10).tables
    albedo = pa.params.coefficients(np.array([550.0]))["ground_albedo"][0]
    assert np.allclose(pa.params.coefficients(data["wavelengths_nm"])["ground_albedo"], albedo)
    dirs = np.asarray(data["view_dirs"], dtype=np.float64)
    for ia, alt, js, el, sun, ok, ground in frame_cases(data):
        sel = ok.copy()
        sel[ok] = ground
        want, _, err_hi = mc_total(data, ia, js, sel)
        # from 1 m, like the frames (render.base.MIN_ALTITUDE_M): at 0 m the ray starts on the ground
        L, _ = probe.sky_radiance(
            pa, dirs[sel], sun, altitude_m=max(alt, 1.0), ground="sun_and_sky"
        )
        check_ground(luminance(L) / want - 1.0, err_hi / want, el, ("probe", alt), 10)
        if alt == 0.0:
            e_sun, e_sky = probe.sun_and_sky_irradiance(pa, [[0.0, 0.0, 1.0]], sun)
            radiance = albedo / math.pi * luminance(e_sun + e_sky)[0]
            assert abs(radiance / want[0] - 1.0) <= 0.03 + 2 * err_hi[0] / want[0], (el, radiance)
