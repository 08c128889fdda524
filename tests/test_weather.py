"""The weather's physics against published numbers, and the weather through Sky and the CLI.

References: Marshall & Palmer (1948) with extinction efficiency 2 (the issue's closed form,
1.55 /km at 10 mm/h); Gunn & Kinzer (1949)'s measured fall speeds; ITU-R P.1814's rain
attenuation for free-space optics (1.076 R^0.67 dB/km, from measurements); Transport
Canada's visibility-in-snow chart (built on Rasmussen et al. 1999's observations); Kunkel
(1984)'s fog extinction fitted to measured droplet spectra.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from skydome.errors import ParameterError
from skydome.physics.droplets import KOSCHMIEDER, droplet_extinction_per_m
from skydome.weather import PRESETS, Weather, rain, snow
from skydome.weather.fog import kunkel_extinction_per_m
from skydome.weather.humidity import growth_factor
from tests.cli_helpers import run_cli

DIAMETERS_MM = np.linspace(1e-4, 12.0, 60001)


def test_marshall_palmer_extinction_is_the_closed_form():
    # pi N0 / Lambda^3 at 10 mm/h: 1.55 /km (the number, 3 %)
    assert rain.rain_extinction_per_m(10.0) * 1e3 == pytest.approx(1.55, rel=0.03)
    # and the distribution integrated numerically with Q = 2 (quadrature error << 0.5 %)
    for rate in (0.5, 10.0, 100.0):
        n = rain.marshall_palmer(DIAMETERS_MM, rate)
        beta = 2.0 * np.trapezoid(math.pi / 4 * DIAMETERS_MM**2 * n, DIAMETERS_MM) * 1e-6
        assert rain.rain_extinction_per_m(rate) == pytest.approx(beta, rel=5e-3)


def test_best_extinction_is_its_distribution_integrated():
    for rate in (1.0, 10.0, 50.0):
        n = rain.best_distribution(DIAMETERS_MM, rate)
        beta = 2.0 * np.trapezoid(math.pi / 4 * DIAMETERS_MM**2 * n, DIAMETERS_MM) * 1e-6
        # the integrand goes as D^0.25 at 0: the trapezoid is within 1 % there
        assert rain.rain_extinction_per_m(rate, "best") == pytest.approx(beta, rel=0.01)


@pytest.mark.parametrize(
    "diameter_mm, measured_m_s",
    [(0.5, 2.06), (1.0, 4.03), (2.0, 6.49), (3.0, 8.06), (4.0, 8.83), (5.0, 9.09)],
)
def test_fall_speed_against_gunn_kinzer(diameter_mm, measured_m_s):
    # Gunn & Kinzer (1949) table 2; Atlas et al.'s fit is within 2 % of it (3 % allowed)
    assert rain.fall_speed_m_s(diameter_mm) == pytest.approx(measured_m_s, rel=0.03)


def test_distributions_carry_their_rain_rate():
    """A distribution falling at Gunn-Kinzer speeds carries a rain rate: Best's (fitted with
    its water content to measured rates) gives back the rate within 6 %; Marshall-Palmer's
    (fitted to drop counts) is known to run high: within 20 %."""
    for rate in (1.0, 10.0, 50.0):
        best = rain.rain_rate_mm_h(rain.best_distribution(DIAMETERS_MM, rate), DIAMETERS_MM)
        mp = rain.rain_rate_mm_h(rain.marshall_palmer(DIAMETERS_MM, rate), DIAMETERS_MM)
        assert best == pytest.approx(rate, rel=0.06)
        assert mp == pytest.approx(rate, rel=0.20)


def test_rain_visibility_against_itu():
    """ITU-R P.1814's measured rain attenuation, 1.076 R^0.67 dB/km: Marshall-Palmer within a
    factor 1.5 (the drop counts of one rate differ by more between storms: Joss & Waldvogel
    1969's N0 spans 1400-30000 m^-3 mm^-1), Best within 25 %."""
    for rate in (1.0, 4.0, 10.0, 25.0, 50.0):
        itu = 1.076 * rate**0.67 / (10 * math.log10(math.e)) * 1e-3  # dB/km -> 1/m
        assert 1 / 1.5 < rain.rain_extinction_per_m(rate) / itu < 1.5
        assert rain.rain_extinction_per_m(rate, "best") / itu == pytest.approx(1.0, rel=0.25)


@pytest.mark.parametrize("rate_mm_h, chart_km", [(0.4, 3.22), (1.0, 1.41), (2.5, 0.60)])
def test_snow_visibility_against_the_chart(rate_mm_h, chart_km):
    """Transport Canada's chart (daylight, below -1 deg C): light/very light at 2 statute
    miles for 0.4 mm/h, moderate/light at 7/8 mile for 1 mm/h, heavy at 3/8 mile for 2.5
    mm/h. Rasmussen et al. (1999) find one rate's visibility spreads by a factor 3-10
    between storms: within a factor 2."""
    v = KOSCHMIEDER / snow.snow_extinction_per_m(rate_mm_h) / 1e3
    assert 0.5 < v / chart_km < 2.0


def test_fog_extinction_against_kunkel():
    """Kunkel's fit to measured advection fogs; his droplets shrink as the water thins, ours
    stay at 10 um: within 30 % over 0.05-0.5 g/m^3."""
    for lwc in (0.05, 0.1, 0.2, 0.5):
        ours = droplet_extinction_per_m(lwc, 10e-6)
        assert ours / kunkel_extinction_per_m(lwc) == pytest.approx(1.0, abs=0.30)


def test_humidity_growth():
    assert growth_factor(80.0) == pytest.approx(1.0)
    assert growth_factor(0.0) == pytest.approx(5.0**-0.25)  # Kasten's law from OPAC's 80 %
    assert growth_factor(100.0) == growth_factor(97.0)  # droplets take over past activation
    with pytest.raises(ParameterError):
        growth_factor(101.0)


def test_humidity_whitens_the_aerosol():
    """The Angstrom exponent's change with humidity is OPAC's water-soluble component's:
    recomputed here from its files' extinction at 450 and 650 nm (Hess et al. 1998, waso00,
    waso80, waso95, waso98; /km per particle per cm^3), to 0.002; the weather's air carries
    it (the exponent of any pair of wavelengths moves by it; 440/870 nm read back), held at
    activation (97 %)."""
    from skydome.atmosphere.precompute_config import PrecomputeConfig
    from skydome.atmosphere.presets import preset
    from skydome.weather.humidity import angstrom_change
    from skydome.weather_effects import weathered

    extinction = {0: (5.180e-6, 3.003e-6), 80: (1.244e-5, 7.521e-6), 95: (2.561e-5, 1.643e-5),
                  98: (4.167e-5, 2.805e-5)}  # fmt: skip
    alpha = {rh: math.log(a / b) / math.log(650.0 / 450.0) for rh, (a, b) in extinction.items()}
    for rh in (0, 95):
        assert angstrom_change(rh) == pytest.approx(alpha[rh] - alpha[80], abs=0.002)
    at_97 = alpha[95] + 2.0 / 3.0 * (alpha[98] - alpha[95])  # linear between the files
    assert angstrom_change(97.0) == pytest.approx(at_97 - alpha[80], abs=0.002)
    assert angstrom_change(80.0) == 0.0
    assert angstrom_change(100.0) == angstrom_change(97.0) < -0.2  # whiter near saturation
    air = {}
    for rh in (50.0, 80.0, 95.0):
        air[rh], _, _ = weathered(Weather("hazy", humidity_pct=rh), preset("earth"), None,
                                  PrecomputeConfig())  # fmt: skip
    for rh in (50.0, 95.0):
        change = air[rh].angstrom_exponent - air[80.0].angstrom_exponent
        assert change == pytest.approx(angstrom_change(rh), abs=1e-6)


def test_presets_and_bad_values():
    for name in PRESETS:
        w = Weather(name)
        assert w.preset == name
    assert Weather("fog").visibility_km == 0.2
    assert Weather("rain", rain_mm_h=10).rain_extinction_per_m == pytest.approx(1.5556e-3, rel=1e-3)
    for bad in (dict(preset="blizzard"), dict(visibility_km=0.0), dict(rain_mm_h=-1.0),
                dict(snow_mm_h=float("nan")), dict(humidity_pct=120.0), dict(wind_m_s=(1.0,)),
                dict(rain_distribution="gamma")):  # fmt: skip
        with pytest.raises(ParameterError):
            Weather(**bad)


def test_weather_sets_the_visibility_of_the_sky():
    from skydome.description import SkyDescription

    for name, km in (("fog", 0.2), ("mist", 2.5), ("hazy", 8.0)):
        d = SkyDescription.of(sun_elevation_deg=20, weather=name)
        assert d.visibility_km == pytest.approx(km, rel=1e-6)
    rainy = SkyDescription.of(sun_elevation_deg=20, weather=Weather("rain", rain_mm_h=10))
    air, clouds, config = rainy.effective
    assert clouds.precipitation_extinction_per_m == pytest.approx(1.5556e-3, rel=1e-3)
    assert config.orders == 4  # the air itself is clear: the usual tables
    hazy = SkyDescription.of(sun_elevation_deg=20, weather="hazy").effective[2]
    assert hazy.orders == 50 and hazy.tolerance > 0  # hazy air: orders until they converge
    with pytest.raises(ParameterError, match="fall from clouds"):
        SkyDescription.of(sun_elevation_deg=20, weather="rain", clouds="clear")


@pytest.mark.gl
def test_every_knob_at_its_ends_gives_a_finite_frame():
    from skydome import Sky

    cases = [
        Weather("fog", visibility_km=0.02, fog_top_m=5.0, fog_droplet_um=1.0),
        Weather("fog", fog_top_m=2000.0, fog_droplet_um=50.0, humidity_pct=0.0),
        Weather("heavy-rain", rain_mm_h=300.0, snow_cover=1.0),
        Weather("snow", snow_mm_h=50.0, humidity_pct=100.0),
        Weather("rain", rain_mm_h=0.0, snow_mm_h=0.0, snow_cover=0.0),
    ]
    for weather in cases:
        with Sky(sun_elevation_deg=10, weather=weather) as sky:
            frame = sky.render(sky.camera("south", fov_deg=90, pitch_deg=5), 32, 18)
            assert np.all(np.isfinite(frame.data)) and frame.data[..., 1].max() > 0, weather


@pytest.mark.gl
def test_weather_darkens_the_ground_light():
    """The CLI's illuminance under a weather: a nimbostratus rain lets through 2-15 % of the
    clear sky's light (overcast skies: 10-25 % under a stratus deck of optical depth ~40;
    this deck's is 150), a radiation fog 150 m deep most of it; the JSON says the
    visibility."""
    from skydome.description import SkyDescription

    def lux(*args):
        result = run_cli("illuminance", "--sun-elevation", "30", "--json", *args)
        assert result.returncode == 0, result.stderr
        return json.loads(result.stdout)

    clear = lux()
    rainy = lux("--weather", "rain")
    foggy = lux("--weather", "fog")
    expected = SkyDescription.of(sun_elevation_deg=30, weather="rain").visibility_km
    assert rainy["visibility_km"] == pytest.approx(expected, rel=1e-9)
    assert 3.0 < expected < 6.0  # 4 mm/h of Marshall-Palmer rain (1.0 /km) and the haze
    assert 0.02 < rainy["total_horizontal_lux"] / clear["total_horizontal_lux"] < 0.15
    assert foggy["visibility_km"] == pytest.approx(0.2, rel=1e-6)
    assert 0.3 < foggy["total_horizontal_lux"] / clear["total_horizontal_lux"] < 1.0
    assert foggy["weather"] == "fog" and rainy["rain_mm_h"] == 4.0


@pytest.mark.gl
@pytest.mark.gl
def test_a_places_light_under_a_weather_is_its_own_skys():
    """At a place and time the CLI's light under a weather is the place's sky's, as a render
    (and the batch manifest) take it: its ground, its Sun's distance, its clouds; the same
    numbers as ``ground_illuminance`` of that sky (the manifest's columns), to rounding. A
    radiation fog lets through 30-100 % of the clear sky's light there too (above), and
    --altitude, which such a sky cannot honour, is refused in one line."""
    from skydome import Sky
    from skydome.core.cameras import EquirectCamera
    from skydome.weather_illuminance import ground_illuminance

    when = "2021-06-21T10:00Z"
    res = run_cli("illuminance", "--place", "Valletta", "--time", when, "--weather", "fog",
                  "--json")  # fmt: skip
    assert res.returncode == 0, res.stderr
    got = json.loads(res.stdout)
    with Sky("Valletta", when, weather="fog", night=False, light_pollution=None) as sky:
        sky.render(EquirectCamera(), 16, 8, exposure=None)
        manifest = ground_illuminance(sky)
    assert got["altitude_m"] == 56.0
    for key in ("direct_horizontal_lux", "diffuse_horizontal_lux", "zenith_luminance_cd_m2"):
        assert got[key] == pytest.approx(manifest[key], rel=1e-9), key
    assert got["total_horizontal_lux"] == pytest.approx(manifest["global_horizontal_lux"])
    clear = json.loads(run_cli("illuminance", "--place", "Valletta", "--time", when,
                               "--json").stdout)  # fmt: skip
    assert 0.3 < got["total_horizontal_lux"] / clear["total_horizontal_lux"] < 1.0
    bad = run_cli("illuminance", "--place", "Valletta", "--time", when, "--weather", "fog",
                  "--altitude", "100")  # fmt: skip
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1, bad.stderr
    assert "--altitude" in bad.stderr


@pytest.mark.parametrize("visibility_km", [0.2, 1.0])
def test_koschmieder_in_fog(visibility_km):
    """A black target at the visibility distance (a depth image through Sky) shows 2 % +-
    0.3 % contrast against the horizon sky in the same directions, in the fog preset's layer
    (150 m; sight lines within a degree of the horizontal, as Koschmieder's homogeneous air
    asks); its transmittance is 0.02 (the droplets' forward peak counts against a target of
    the pixels' size)."""
    from skydome import Sky

    weather = Weather("fog", visibility_km=visibility_km)
    with Sky(sun_elevation_deg=20, sun_azimuth_deg=90, weather=weather) as sky:
        camera = sky.camera("south", fov_deg=2, pitch_deg=0.6)
        w, h = 16, 8
        horizon = sky.render(camera, w, h, exposure=None).data[..., 1]
        depth = np.full((h, w), visibility_km * 1e3)
        frame = sky.render(camera, w, h, depth_m=depth, exposure=None)
    contrast = 1.0 - frame.data[..., 1] / horizon  # black: scene x T adds nothing
    # the target's (its pixels' mean); a pixel alone carries the march's sampling noise (its
    # ordered step offsets: +-0.3 % of the light, i.e. +-0.3 % of contrast)
    assert abs(contrast.mean() - 0.02) <= 0.003, contrast.mean()
    assert np.all(np.abs(contrast - 0.02) <= 0.006), contrast
    assert np.allclose(frame.info["transmittance"][..., 1], 0.02, rtol=0.01)


@pytest.mark.gl
def test_the_sun_is_a_pale_disk_in_fog():
    """Through 150 m of fog with 200 m of visibility (slant optical depth 11) the Sun's disk
    keeps its unscattered light only: brighter than the fog around it, but not blinding
    (within 1.05-3 times the fog beside it; with the forward peak counted as unscattered it
    was ~100 times)."""
    from skydome import Sky

    weather = Weather("fog", visibility_km=0.2, fog_top_m=150.0)
    with Sky(sun_elevation_deg=15, sun_azimuth_deg=90, weather=weather) as sky:
        frame = sky.render(sky.camera("sun", fov_deg=4), 64, 64, exposure=None)
    luminance = frame.data[..., 1]
    ratio = luminance.max() / np.median(luminance[:, :8])
    assert 1.05 < ratio < 3.0, ratio


def test_direction_table_texels_fall_on_their_centres():
    """The fog's direction table (skydome.clouds.direction_table): each texel's own direction
    maps back to its centre (within 1e-3 of the texture: the texels nearest the horizon sit
    1e-6 in q off it, which the square root makes 5e-4); the lower half's rays are those
    below the ground's horizon, -acos(R / r), and the upper half's above it; texel 0 looks
    towards the light's azimuth; the texels crowd at the horizon."""
    from skydome.clouds.direction_table import table_directions, table_frame, table_texcoords

    size = (256, 128)
    light = np.array([-0.3, 0.5, 0.6])
    frame = table_frame(light, 6360.5, 6360.0)
    d = table_directions(size, frame)
    assert np.allclose(np.linalg.norm(d, axis=-1), 1.0, atol=1e-12)
    elevation = np.degrees(np.arcsin(d[..., 2]))
    horizon = -np.degrees(np.arccos(6360.0 / 6360.5))
    assert np.all(elevation[:64] < horizon) and np.all(elevation[64:] > horizon)
    uv = table_texcoords(d, size, frame)
    centres_u = (np.arange(256) + 0.5) / 256
    centres_v = (np.arange(128) + 0.5) / 128
    assert np.allclose(uv[..., 0], centres_u[None, :], atol=1e-9)
    assert np.allclose(uv[..., 1], centres_v[:, None], atol=1e-3)
    azimuth = np.arctan2(d[:, 0, 1], d[:, 0, 0])
    assert np.allclose(azimuth, math.atan2(light[1], light[0]), atol=1e-9)
    steps = np.diff(elevation[64:, 0])
    assert steps[0] < 0.02 and steps[-1] > 1.0  # deg: (1 / 63)^2 rad = 0.014 at the horizon


@pytest.mark.gl
@pytest.mark.parametrize("altitude_m, pitch_deg", [(2.0, 10.0), (400.0, -5.0)])
def test_fog_alone_is_drawn_from_its_direction_table(altitude_m, pitch_deg):
    """A fog with no clouds over it is the same everywhere, so Sky draws it from a table of
    view directions marched once (skydome.clouds.direction_table) and kept while the view
    turns (another height, time or light marches it afresh). Inside the fog and above its
    sea, that frame equals the march of every pixel (the
    path a user's depth image takes, here one with no scene in it): median within 0.3 %, 95th
    percentile within 1.5 % (the table interpolates 1.4 x <= 0.7 deg texels; the
    per-pixel march's own step offsets leave +-5 % on a few pixels at the horizon)."""
    from skydome import Sky

    w, h = 160, 90
    with Sky(sun_elevation_deg=20, weather="fog") as sky:
        camera = sky.camera("south", fov_deg=90, pitch_deg=pitch_deg)
        tabled = sky.render(camera, w, h, altitude_m=altitude_m, exposure=None).data[..., :3]
        layer = sky.layer("clouds")
        table = layer._table
        no_scene = np.full((h, w), np.inf)
        marched = sky.render(camera, w, h, altitude_m=altitude_m, exposure=None,
                             depth_m=no_scene).data[..., :3]  # fmt: skip
        # turned, or another camera: the same table; another height: marched afresh
        sky.render(sky.camera("east", fov_deg=60), 32, 18, altitude_m=altitude_m)
        assert layer._table is table
        sky.render(camera, 32, 18, altitude_m=altitude_m + 50.0)
        assert layer._table is not table
    error = np.abs(tabled / marched - 1.0)
    assert np.all(np.isfinite(tabled)) and tabled.min() > 0.0
    assert np.median(error) < 0.003, np.median(error)
    assert np.percentile(error, 95) < 0.015, np.percentile(error, 95)


@pytest.mark.gl
@pytest.mark.parametrize("tau", [10.0, 20.0, 50.0])
def test_fog_slab_matches_monte_carlo(tau, monkeypatch):
    """A fog 1 km deep of optical depth 10-50 (its top sharp: the fade off), lit by the Sun
    60 deg up over a black ground: the light it reflects (looking straight down from 2.5 km)
    and lets through (looking straight up from the ground) within 5 % of the float64 Monte
    Carlo (every order: the multiple-scattering table is its source function; the MC's own
    standard error added twice)."""
    from skydome import Sky
    from skydome.atmosphere.layer import AtmosphereLayer
    from skydome.clouds import layer as cloud_layer
    from skydome.clouds.layer import CloudLayer
    from skydome.clouds.params import Clouds
    from skydome.clouds.phase import PEAK_FRACTION, RENDER_PHASE
    from skydome.core.cameras import PerspectiveCamera
    from skydome.reference.clouds_mc import slab_radiance
    from tests.conftest import TINY_TABLES

    monkeypatch.setattr(cloud_layer, "FOG_TOP_FADE", 1e-6)
    fog = CloudLayer(Clouds("clear", fog_top_m=1000.0, fog_extinction_per_m=tau / 1000.0))
    sky = Sky(
        sun_elevation_deg=60.0,
        layers=[AtmosphereLayer("earth", config=TINY_TABLES), fog],
    )
    try:
        sky.graph.update(sky.state)
        mc = slab_radiance(
            tau * (1.0 - PEAK_FRACTION), math.sin(math.radians(60.0)),
            np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]), phase=RENDER_PHASE,
            photons=60_000, seed=11,
        )  # fmt: skip
        got = []
        for pitch, altitude in ((-90.0, 2500.0), (90.0, 0.5)):
            camera = PerspectiveCamera(fov_deg=0.5, yaw_deg=0.0, pitch_deg=pitch)
            radiance, _ = fog.probe(camera, 4, 4, altitude, test_irradiance=1.0)
            got.append(radiance[2, 2, 1])
    finally:
        sky.release()
    for k in range(2):
        ref, err = mc.radiance[k], mc.radiance_se[k]
        assert abs(got[k] / ref - 1.0) < 0.05 + 2.0 * err / ref, (k, got[k], ref)


@pytest.mark.parametrize(
    "args, words",
    [
        (["--visibility", "0"], "--visibility 0 km is outside the valid range"),
        (["--weather", "rain", "--rain", "-1"], "--rain -1 mm/h is outside the valid range"),
        (["--weather", "blizzard"], "--weather blizzard: unknown weather"),
        (["--snow", "60"], "--snow 60 mm/h is outside the valid range"),
        (["--weather", "rain", "--clouds", "clear"], "fall from clouds"),
        (["--weather", "fog", "--shutter", "5"], "--shutter 5 s is outside the valid range"),
    ],
)
def test_bad_weather_is_one_line_and_exit_2(tmp_path, args, words):
    out = tmp_path / "sky.png"
    res = run_cli("render", "--sun-elevation", "20", "--size", "8x8", *args, "-o", str(out))
    assert res.returncode == 2 and words in res.stderr, (res.returncode, res.stderr)
    assert len(res.stderr.strip().splitlines()) == 1 and not out.exists()
