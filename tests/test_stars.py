"""The stars layer: positions against skydome.astro's apparent places, photometry against the
magnitudes (unattenuated and through the float64 transmittance of the air), colours against
Planck through the full CIE table, the Moon's disk, twinkling, and a layer turned off."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from skydome import Sky
from skydome.astro import Observer
from skydome.astro.stars import catalog, find_star
from skydome.celestial.scintillation import (
    Scintillation,
    airmass_kasten_young,
    scintillation_sigma,
    young_sigma,
)
from skydome.celestial.stars import StarsLayer
from skydome.core.cameras import (
    EquirectCamera,
    PerspectiveCamera,
)
from skydome.errors import ParameterError
from skydome.spectra import LINEAR_SRGB_TO_XYZ, SRGB_LUMINANCE
from skydome.spectra.blackbody import planck_relative

VALLETTA = Observer(35.8989, 14.5146, 56.0)
WINTER_EVENING = "2018-01-20T20:00Z"  # Orion high in the south, the Moon set, the Sun -45 deg


@pytest.fixture(scope="module")
def stars_sky():
    sky = Sky(VALLETTA, WINTER_EVENING, layers=[StarsLayer()])
    sky.graph.update(sky.state)  # the layer's directions, before any frame
    yield sky
    sky.graph.release()


def with_air(*layers):
    """The Sun, the Moon, ``layers`` and the default atmosphere (and nothing else)."""
    from skydome.atmosphere.layer import AtmosphereLayer
    from skydome.celestial.moon import MoonLayer
    from skydome.celestial.sun import SunLayer

    return [SunLayer(), MoonLayer(), *layers, AtmosphereLayer("earth")]


def frame_geometry(camera, w, h):
    fw, fh = camera.frame_size(w, h)
    rows, cols = np.mgrid[0:fh, 0:fw]
    gx, gy = cols + 0.5, (fh - 1 - rows) + 0.5
    dirs, _ = camera.directions(gx, gy, fw, fh)
    return dirs, camera.solid_angle(dirs, fw, fh), gx, gy


def aperture_flux(data, dirs, omega, direction, radius_deg):
    """(R, G, B, scotopic) flux within radius_deg of direction."""
    near = (dirs @ direction) > math.cos(math.radians(radius_deg))
    return (data.astype(np.float64) * omega[..., None])[near].sum(axis=0)


def aperture_lux(data, dirs, omega, direction, radius_deg):
    """Photopic flux (lux) within radius_deg of direction."""
    return float(aperture_flux(data, dirs, omega, direction, radius_deg)[:3] @ SRGB_LUMINANCE)


def test_directions_are_the_apparent_refracted_places(stars_sky):
    # Observer.sky(stars=True): the same apparent places, diurnal aberration and Saemundsson
    # refraction with the observer's weather, computed its own way (the full Observer chain
    # at this instant, no cached places). 0.05" (float64; the hour-long cache of the places
    # is not used: it is this instant).
    layer = stars_sky.layer("stars")
    ref = VALLETTA.sky(WINTER_EVENING, bodies=(), stars=True, star_mag_limit=9.0).stars
    assert np.array_equal(ref.hip.ravel(), layer.hip)
    up = ref.alt.ravel() > 0
    cos = np.sum(layer.directions[up] * ref.enu[up], axis=-1)
    sep_arcsec = np.degrees(np.arccos(np.clip(cos, -1, 1))) * 3600
    assert sep_arcsec.max() < 0.05
    refracted = np.degrees(layer.altitude_rad[up] - ref.alt_unrefracted.ravel()[up]) * 60
    assert refracted.min() >= 0 and refracted.max() > 30  # arcmin: 0 at the zenith, 34' low


def test_image_centroids_of_the_brightest_stars(stars_sky):
    # The 50 brightest stars more than 5 deg up, isolated (no other star with > 1 % of the
    # light within 8 px), in a 4096 x 2048 frame drawn as two tiles: each centroid within
    # 0.3 px of the star's astronomical (apparent, refracted) position.
    cam, w, h = EquirectCamera(), 4096, 2048
    data = stars_sky.render(cam, w, h, exposure=None).data[..., 1].astype(np.float64)
    ref = VALLETTA.sky(WINTER_EVENING, bodies=(), stars=True, star_mag_limit=9.0).stars
    enu, lux = ref.enu, ref.illuminance_lux
    x, y, _ = cam.project(enu, w, h)
    checked = 0
    for i in np.argsort(-lux):
        if checked == 50:
            break
        if ref.alt[i] < math.radians(5.0) or not 20 < x[i] < w - 20 or y[i] > h - 20:
            continue
        d = np.hypot(x - x[i], y - y[i])
        if np.any((d < 8.0) & (d > 0) & (lux > 0.01 * lux[i])):
            continue
        c0, r0 = int(x[i]), h - 1 - int(y[i])
        box = data[r0 - 5 : r0 + 6, c0 - 5 : c0 + 6]
        gx = np.arange(c0 - 5, c0 + 6) + 0.5
        gy = (h - 1 - np.arange(r0 - 5, r0 + 6)) + 0.5
        cx = (box.sum(axis=0) * gx).sum() / box.sum()
        cy = (box.sum(axis=1) * gy).sum() / box.sum()
        assert abs(cx - x[i]) < 0.3 and abs(cy - y[i]) < 0.3, (ref.hip[i], cx - x[i], cy - y[i])
        checked += 1
    assert checked == 50


@pytest.mark.parametrize(
    "camera,w,h",
    [
        (EquirectCamera(), 1024, 512),
        (EquirectCamera(), 4096, 2048),
        (PerspectiveCamera(fov_deg=30), 800, 600),  # aimed in the test
    ],
)
def test_flux_is_the_illuminance(stars_sky, camera, w, h):
    # Sirius (V = -1.46) and Rigel: the flux within 1 deg is the illuminance of the catalogue
    # stars within it (their own V through E = 10^(-0.4 (V + 14.18)) lx), 2 %.
    layer = stars_sky.layer("stars")
    for name in ("Sirius", "Rigel"):
        i = find_star(name).index
        target = layer.directions[i]
        if isinstance(camera, PerspectiveCamera):
            alt = math.degrees(layer.altitude_rad[i])
            az = math.degrees(math.atan2(target[0], target[1]))
            camera = PerspectiveCamera(fov_deg=30, yaw_deg=az, pitch_deg=alt)
        data = stars_sky.render(camera, w, h, exposure=None).data
        dirs, omega, _, _ = frame_geometry(camera, w, h)
        got = aperture_lux(data, dirs, omega, target, 1.0)
        inside = (layer.directions @ target) > math.cos(math.radians(1.0))
        expected = layer.lux[inside].sum()
        assert layer.lux[i] > 0.9 * expected  # the star dominates its aperture
        assert got == pytest.approx(expected, rel=0.02)


def test_sirius_over_vega_as_their_magnitudes_say():
    # Sirius in January, Vega in July (never both up here): the flux ratio is
    # 10^(-0.4 (V_Sirius - V_Vega)) of the catalogue's V (-1.460, 0.075: 4.11), 3 %.
    # (SIMBAD's V of Vega is 0.03: the catalogue's V comes from Hp and B-V.)
    fluxes = {}
    for name, time in (("Sirius", "2018-01-20T22:00Z"), ("Vega", "2018-07-01T22:00Z")):
        sky = Sky(VALLETTA, time, layers=[StarsLayer(mag_limit=1.0)])  # bright only: alone
        layer = sky.layer("stars")
        sky.graph.update(sky.state)
        i = int(np.flatnonzero(layer.hip == find_star(name).hip)[0])
        d = layer.directions[i]
        cam = PerspectiveCamera(
            fov_deg=10,
            yaw_deg=math.degrees(math.atan2(d[0], d[1])),
            pitch_deg=math.degrees(layer.altitude_rad[i]),
        )
        data = sky.render(cam, 256, 256, exposure=None).data
        dirs, omega, _, _ = frame_geometry(cam, 256, 256)
        fluxes[name] = aperture_lux(data, dirs, omega, d, 2.0)
        sky.graph.release()
    v_s, v_v = find_star("Sirius").vmag, find_star("Vega").vmag
    assert fluxes["Sirius"] / fluxes["Vega"] == pytest.approx(10 ** (-0.4 * (v_s - v_v)), rel=0.03)


def test_through_the_air_the_flux_is_times_the_transmittance():
    # With the atmosphere: the star's added flux (frame with the stars minus frame without)
    # is its illuminance times the photopic transmittance of its black body through the
    # float64 column densities of skydome.reference.single at its direction (Beer-Lambert
    # per wavelength, weighted by Planck x y-bar on a 1 nm grid): 2 %. The graph weights each
    # channel's transmittance for the solar spectrum; Rigel (10500 K) and Betelgeuse
    # (3800 K) bracket that.
    from skydome.reference import single as ref
    from skydome.spectra.tables import cmf_xyz

    sky = Sky(VALLETTA, WINTER_EVENING, layers=with_air(StarsLayer()))
    layer, air = sky.layer("stars"), sky.layer("atmosphere")
    sky.graph.update(sky.state)
    params, wl = air.params, air.spectral_basis.wavelengths_nm
    c = params.coefficients(wl)
    fine = np.arange(360.0, 831.0)
    for name in ("Rigel", "Betelgeuse"):
        i = find_star(name).index
        d = layer.directions[i]
        cam = PerspectiveCamera(
            fov_deg=6,
            yaw_deg=math.degrees(math.atan2(d[0], d[1])),
            pitch_deg=math.degrees(layer.altitude_rad[i]),
        )
        with_stars = sky.render(cam, 256, 256, exposure=None).data.astype(np.float64)
        layer.enabled = False
        without = sky.render(cam, 256, 256, exposure=None).data.astype(np.float64)
        layer.enabled = True
        dirs, omega, _, _ = frame_geometry(cam, 256, 256)
        got = aperture_lux(with_stars - without, dirs, omega, d, 1.0)
        inside = (layer.directions @ d) > math.cos(math.radians(1.0))
        r = params.bottom_radius_m + sky.altitude_m()
        col = ref.column_to_top(params, np.array([r]), np.array([d[2]]))[0]
        tau = (
            c["rayleigh_scattering"] * col[0]
            + c["mie_extinction"] * col[1]
            + c["absorption_extinction"] * col[2]
        )
        t_fine = np.interp(fine, wl, np.exp(-tau))
        weight = planck_relative(fine, [layer.teff_k[i]])[:, 0] * cmf_xyz(fine)[:, 1]
        transmittance = (weight * t_fine).sum() / weight.sum()
        assert 0.5 < transmittance < 0.95
        assert got == pytest.approx(layer.lux[inside].sum() * transmittance, rel=0.02), name
    sky.graph.release()


def test_colours_are_the_black_body_chromaticities(stars_sky):
    # Betelgeuse (3794 K) and Rigel (10516 K): the image's CIE 1931 (x, y) against Planck's
    # law integrated with the full 5 nm CIE table read here from the CSV. Tolerance 0.002:
    # the frame's colour samples Planck / solar at the 16 wavelengths 25 nm apart and
    # interpolates linearly (times the solar spectrum at 1 nm); that reshaping moves x and y
    # by < 0.001 for 2700-20000 K (checked against this integral when the layer was written).
    table = np.loadtxt(
        "src/skydome/data/cie1931_2deg_cmf_5nm.csv", delimiter=",", comments="#", skiprows=2
    )
    layer = stars_sky.layer("stars")
    results = {}
    for name in ("Betelgeuse", "Rigel"):
        i = find_star(name).index
        d = layer.directions[i]
        cam = PerspectiveCamera(
            fov_deg=4,
            yaw_deg=math.degrees(math.atan2(d[0], d[1])),
            pitch_deg=math.degrees(layer.altitude_rad[i]),
        )
        data = stars_sky.render(cam, 128, 128, exposure=None).data
        dirs, omega, _, _ = frame_geometry(cam, 128, 128)
        rgb = aperture_flux(data, dirs, omega, d, 0.3)[:3]
        xyz = LINEAR_SRGB_TO_XYZ @ rgb
        planck = planck_relative(table[:, 0], [layer.teff_k[i]])[:, 0]
        ref = table[:, 1:].T @ planck
        results[name] = xyz[:2] / xyz.sum()
        np.testing.assert_allclose(results[name], ref[:2] / ref.sum(), atol=0.002)
    assert results["Betelgeuse"][0] > results["Rigel"][0] + 0.1  # orange against blue-white


def test_the_moon_hides_the_stars_behind_it(stars_sky):
    # The Moon moved onto Alnilam: the star adds nothing; Mintaka, 1.4 deg away, is whole.
    layer = stars_sky.layer("stars")
    stars_sky.graph.update(stars_sky.state)
    alnilam = layer.directions[find_star("Alnilam").index].copy()
    state = stars_sky.state
    moved = dataclasses.replace(state, moon=dataclasses.replace(state.moon, direction=alnilam))
    cam = PerspectiveCamera(
        fov_deg=6,
        yaw_deg=math.degrees(math.atan2(alnilam[0], alnilam[1])),
        pitch_deg=math.degrees(math.asin(alnilam[2])),
    )
    alt = stars_sky.altitude_m()
    data = stars_sky.graph.render(moved, cam, 256, 256, altitude_m=alt).data
    dirs, omega, _, _ = frame_geometry(cam, 256, 256)
    radius = math.degrees(state.moon.angular_radius_rad)
    assert np.all(aperture_flux(data, dirs, omega, alnilam, radius) == 0.0)
    mintaka = layer.directions[find_star("Mintaka").index]
    got = aperture_lux(data, dirs, omega, mintaka, 0.2)
    assert got == pytest.approx(layer.lux[find_star("Mintaka").index], rel=0.02)
    plain = stars_sky.graph.render(state, cam, 256, 256, altitude_m=alt).data
    assert aperture_lux(plain, dirs, omega, alnilam, radius) > 0


def test_scintillation_amplitude_and_its_sources():
    # Kasten & Young (1989) Table: air mass 37.92 at the horizon; Young's (1967) law for the
    # eye, 0.09 x 0.7^(-2/3) x 0.2^(-1/2) = 0.2553 at the zenith at sea level, smaller at
    # altitude (exp(-h / 8 km)); capped at saturation, rising towards the horizon.
    assert airmass_kasten_young(0.0) == pytest.approx(37.92, abs=0.01)
    assert young_sigma(1.0) == pytest.approx(0.2553, abs=1e-4)
    at_paranal = young_sigma(1.0, altitude_m=2635.0)
    assert at_paranal == pytest.approx(young_sigma(1.0) * math.exp(-2635 / 8000), rel=1e-12)
    s = scintillation_sigma(np.radians([90.0, 60.0, 30.0, 10.0, 2.0, 0.0]))
    assert s[0] == pytest.approx(0.2553 / math.sqrt(1 + 0.2553**2), rel=1e-3)
    assert np.all(np.diff(s) > 0) and s[-1] <= 1.0
    with pytest.raises(ParameterError):
        young_sigma(0.5)


def test_twinkling_means_one_and_is_seeded():
    # Mean of the factors over random times and stars: 1 within 1 % (N = 4e5 independent
    # samples of relative s.d. <= 1: standard error 0.16 %); exact time mean by construction.
    rng = np.random.default_rng(5)
    scint = Scintillation(2000, seed=3)
    sigma = np.full(2000, 1.0)
    means = [scint.factors(t, sigma).mean() for t in rng.uniform(0, 1e6, 200)]
    assert np.mean(means) == pytest.approx(1.0, abs=0.01)
    a = Scintillation(10, seed=3).factors(1234.5, np.full(10, 0.5))
    b = Scintillation(10, seed=3).factors(1234.5, np.full(10, 0.5))
    c = Scintillation(10, seed=4).factors(1234.5, np.full(10, 0.5))
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    # Several changes a second: over 0.25 s the factors move.
    d = Scintillation(10, seed=3).factors(1234.75, np.full(10, 0.5))
    assert np.abs(d - a).max() > 0.05


def test_twinkling_phases_against_float64():
    # The process is evaluated from float64 phases at the start of each 1024 s stretch and
    # float32 within it; against the direct float64 sum of the cosines (whole cycles of f t
    # dropped with np.mod): within 0.01 (g has unit variance; the phases' float32 error is
    # < 5e-4 cycles after 4096 cycles, times 12 terms of amplitude 0.41: 0.015 at worst;
    # measured 0.004), at the start, the middle and the end of stretches, and at t = 1e9 s.
    scint = Scintillation(3000, seed=2)
    for t in (6.08e8 + 1023.9, 6.08e8 + 0.01, 6.5e8 + 512.3, 1.0e9 + 1023.99, 3.3):
        cycles = np.mod(scint.frequency_hz * t, 1.0)
        direct = scint.amplitude * np.cos(2 * np.pi * cycles + scint.phase).sum(axis=-1)
        np.testing.assert_allclose(scint.gaussian(t), direct, atol=0.01)


def test_twinkling_in_the_layer():
    # Same seed and time: the same frame; 0.3 s later: another; a low star twinkles more.
    sky = Sky(VALLETTA, WINTER_EVENING, layers=[StarsLayer(twinkle=True, seed=7)])
    cam = EquirectCamera()
    a = sky.render(cam, 512, 256, exposure=None).data
    b = Sky(VALLETTA, WINTER_EVENING, layers=[StarsLayer(twinkle=True, seed=7)])
    assert np.array_equal(a, b.render(cam, 512, 256, exposure=None).data)
    later = sky.at("2018-01-20T20:00:00.3Z")
    assert not np.array_equal(a, later.render(cam, 512, 256, exposure=None).data)
    layer = sky.layer("stars")
    high, low = layer.altitude_rad > math.radians(60), np.abs(layer.altitude_rad) < 0.1
    spread = [np.std(np.log(layer.factors[m])) for m in (high, low)]
    assert spread[0] < spread[1]
    # The factors are computed when drawn, for the stars drawn: the same as every star's.
    some = np.flatnonzero(high)[::7]
    np.testing.assert_array_equal(layer.twinkle_factors(some), layer.factors[some])
    for s in (sky, b):
        s.graph.release()


def test_a_redrawn_frame_reuses_the_placement(stars_sky, monkeypatch):
    # The same state, camera and frame again: the point pass re-issues its last draws from
    # the GPU's buffers (no placement) and the frame is bit-identical; another camera in
    # between, or a new state, places the stars anew.
    from skydome.celestial.point_sources import PointSources

    cam, other = PerspectiveCamera(fov_deg=60, yaw_deg=180, pitch_deg=30), EquirectCamera()
    first = stars_sky.render(cam, 320, 200, exposure=None).data
    placed = []
    original = PointSources._positions

    def counting(*args):
        placed.append(1)
        return original(*args)

    monkeypatch.setattr(PointSources, "_positions", staticmethod(counting))
    again = stars_sky.render(cam, 320, 200, exposure=None).data
    assert np.array_equal(first, again) and not placed
    stars_sky.render(other, 128, 64, exposure=None)
    assert len(placed) == 1
    assert np.array_equal(stars_sky.render(cam, 320, 200, exposure=None).data, first)
    assert len(placed) == 2
    later = stars_sky.at("2018-01-20T20:10Z")
    moved = later.render(cam, 320, 200, exposure=None).data
    assert len(placed) == 3 and not np.array_equal(moved, first)
    stars_sky.graph.update(stars_sky.state)  # the fixture's graph (shared by later) as it was


def test_layer_off_is_bit_identical_and_abstract_mode_draws_nothing():
    cam = EquirectCamera()
    plain = Sky(VALLETTA, WINTER_EVENING, layers=with_air()).render(cam, 256, 128, exposure=None)
    plain = plain.data
    off = Sky(VALLETTA, WINTER_EVENING, layers=with_air(StarsLayer(enabled=False)))
    assert np.array_equal(off.render(cam, 256, 128, exposure=None).data, plain)
    off.layer("stars").enabled = True
    on = off.render(cam, 256, 128, exposure=None)
    assert not np.array_equal(on.data, plain)
    assert on.info["stars_drawn"] > 10000  # about half the catalogue is up
    abstract = Sky(sun_elevation_deg=-30.0, layers=with_air(StarsLayer()))
    bare = Sky(sun_elevation_deg=-30.0, layers=with_air())
    np.testing.assert_array_equal(
        abstract.render(cam, 128, 64, exposure=None).data,
        bare.render(cam, 128, 64, exposure=None).data,
    )
    assert abstract.render(cam, 16, 8, exposure=None).info["stars_drawn"] == 0


def test_info_and_parameters():
    sky = Sky(VALLETTA, WINTER_EVENING, layers=[StarsLayer(mag_limit=3.0)])
    info = sky.render(EquirectCamera(), 64, 32, exposure=None).info
    n_bright = int(np.count_nonzero(catalog().vmag <= 3.0))
    assert 0 < info["stars_drawn"] < n_bright and info["stars_mag_limit"] == 3.0
    for bad in ({"mag_limit": 99.0}, {"psf_sigma_px": 0.0}, {"seeing_fwhm_arcsec": -1.0}):
        with pytest.raises(ParameterError):
            StarsLayer(**bad)
