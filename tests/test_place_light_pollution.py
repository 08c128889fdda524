"""Light pollution by place: a gazetteer city's sky glow estimated from its population
(Berry 1976's b ~ P^0.5 at the centre, calibrated on central Berlin), an observatory's own
Bortle class (dark sites: none), ``--bortle``/``light_pollution=`` overriding; the value used
printed on stderr; and Paris at night without the Milky Way.

The measured values compared (total zenith V, mag/arcsec^2, clear and moonless):
  * Paris centre 17-18 (SQM surveys and the World Atlas of Falchi et al. 2016 put central
    Paris in its brightest class, artificial > 1e-2 cd/m^2, i.e. total < ~17.9);
  * a small town of 10,000-20,000 people, 20-21 (Bortle 4-5, the SQM-per-class table);
  * Paranal 21.8 (ESO's site monitoring: 21.6-21.9 in V over the solar cycle, Patat 2008,
    A&A 481, 575).
The tolerance is the spread of measured city-centre skies for one population: +-0.5 mag
(lighting practice, latitude, aerosol; Kyba et al. 2015, Sci. Rep. 5, 8409, find the
clear-sky zenith of cities of similar size differing by a factor of 2-3).
"""

from __future__ import annotations

import numpy as np
import pytest

from skydome.astro.places import find_place, places
from skydome.description import SkyDescription
from skydome.night import light_pollution as lp
from skydome.night.light_pollution import LightPollution, city_zenith_mag
from tests.cli_helpers import run_cli

NIGHT = "2024-07-06T01:30"  # Paris local time (CEST): the Sun at -18.3 deg, new Moon


def test_paris_centre_is_17_to_18():
    paris = find_place("Paris")
    assert paris.population == pytest.approx(11e6, rel=0.3)
    m = city_zenith_mag(paris.population)
    assert 17.0 <= m <= 18.0, m
    assert LightPollution.for_place(paris).total_zenith_mag() == pytest.approx(m, abs=1e-9)


@pytest.mark.parametrize("population", [10_000, 20_000])
def test_small_town_is_20_to_21(population):
    assert 20.0 <= city_zenith_mag(population) <= 21.0


def test_paranal_is_the_natural_sky():
    """An observatory of Bortle class 1 adds no glow: its zenith is the natural 21.9,
    within 0.25 mag of Paranal's measured 21.8 (the solar cycle moves the airglow by that)."""
    paranal = find_place("Paranal")
    assert paranal.bortle == 1 and LightPollution.for_place(paranal) is None
    assert abs(lp.bortle_zenith_mag(paranal.bortle) - 21.8) <= 0.25
    assert abs(lp.NATURAL_ZENITH_MAG - 21.8) <= 0.25


def test_berry_square_root_law():
    """Four times the people, twice the artificial luminance (Berry 1976: b ~ P^0.5)."""
    natural = float(lp.mag_to_luminance(lp.NATURAL_ZENITH_MAG))
    art = [float(lp.mag_to_luminance(city_zenith_mag(p))) - natural for p in (1e5, 4e5, 1.6e6)]
    assert art[1] / art[0] == pytest.approx(2.0, rel=1e-9)
    assert art[2] / art[1] == pytest.approx(2.0, rel=1e-9)
    # the calibration point itself
    assert city_zenith_mag(lp.CITY_CALIBRATION[0]) == pytest.approx(lp.CITY_CALIBRATION[1])


def test_every_place_has_a_sky():
    """Cities: a population and an estimate between Bortle 4 (the smallest towns) and 9; dark
    observatories (classes 1-2) no glow; observatories in or near cities their class's."""
    for place in places():
        glow = LightPollution.for_place(place)
        if place.kind == "city":
            assert place.population and place.bortle is None, place.name
            assert 16.5 < glow.total_zenith_mag() < 21.5, place.name
        else:
            assert place.population is None and place.bortle in range(1, 10), place.name
            if place.bortle <= 2:
                assert glow is None, place.name
            else:
                assert glow.bortle_class == place.bortle, place.name
    assert find_place("Royal Observatory Greenwich").bortle == 9
    assert lp.bortle_class_of(city_zenith_mag(find_place("Tokyo").population)) == 9


def test_sky_description_defaults_and_overrides():
    t = "2024-07-06T01:30"
    paris = SkyDescription.of("Paris", t)
    assert isinstance(paris.light_pollution, LightPollution)
    assert paris.light_pollution.total_zenith_mag() == pytest.approx(city_zenith_mag(11e6))
    assert "population" in paris.light_pollution.summary()
    assert SkyDescription.of("Paranal", t).light_pollution is None  # a dark site
    assert SkyDescription.of((48.8566, 2.3522), t).light_pollution is None  # numbers: none
    assert SkyDescription.of("Paris", t, light_pollution=None).light_pollution is None
    assert SkyDescription.of("Paris", t, light_pollution=3).light_pollution == 3
    assert SkyDescription.of("Paris", t, night=False).light_pollution is None
    assert SkyDescription.of("Paris", t, model="cie", cie_illuminance=100.0).light_pollution is None
    # a new place keeps the glow unless asked for its own
    moved = paris.with_(place="Paranal")
    assert moved.light_pollution is paris.light_pollution
    assert paris.with_(place="Paranal", light_pollution="auto").light_pollution is None


@pytest.mark.gl
def test_paris_at_night_shows_no_milky_way():
    """The Milky Way's Weber contrast against the sky: over 30 % for the pristine sky above
    Paris at 01:30 CEST (Sun -18 deg, new Moon), under 3 % with Paris's own glow (0.02
    cd/m^2): below the eye's threshold contrast for large targets at that luminance
    (Blackwell 1946, JOSA 36, 624: 3-5 % near 1e-2 cd/m^2)."""
    from skydome import Sky
    from skydome.core.cameras import FisheyeCamera

    cam = FisheyeCamera()
    weights = np.array([0.2126, 0.7152, 0.0722])
    contrast = {}
    for name, glow in (("paris", "auto"), ("pristine", None)):
        sky = Sky("Paris", NIGHT, light_pollution=glow)
        on = sky.render(cam, 160, 160, exposure=None).data[..., :3] @ weights
        sky.layer("milky_way").enabled = False
        off = sky.render(cam, 160, 160, exposure=None).data[..., :3] @ weights
        sky.release()
        sky_px = off > 0
        contrast[name] = (on[sky_px] - off[sky_px]) / off[sky_px]
    assert np.percentile(contrast["pristine"], 99) > 0.3
    assert contrast["paris"].max() < 0.03, contrast["paris"].max()


@pytest.mark.gl
def test_render_prints_the_light_pollution_it_used(tmp_path):
    out = tmp_path / "p.npy"
    args = ["render", "--place", "Paris", "--time", NIGHT, "--size", "32x18", "--look", "zenith"]
    auto = run_cli(*args, "-o", out)
    assert auto.returncode == 0, auto.stderr
    lines = [ln for ln in auto.stderr.splitlines() if ln.startswith("light pollution:")]
    assert len(lines) == 1 and "Paris: estimated from its population" in lines[0], auto.stderr
    assert "Bortle 9" in lines[0] and "--bortle overrides" in lines[0]
    glow = np.median(np.load(out)[..., 1])
    given = run_cli(*args, "--bortle", "3", "-o", out)
    assert given.returncode == 0, given.stderr
    assert "light pollution: zenith 21.79 mag/arcsec^2 (Bortle 3), --bortle" in given.stderr
    assert np.median(np.load(out)[..., 1]) < glow / 10  # Bortle 3 against Paris's 17.4
    dark = run_cli("render", "--place", "Paranal", "--time", "2024-07-05T23:00", "--size",
                   "32x18", "-o", out)  # fmt: skip
    assert dark.returncode == 0, dark.stderr
    assert "light pollution: none: Paranal Observatory is a dark site (Bortle 1)" in dark.stderr
