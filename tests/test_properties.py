"""Property-based tests (hypothesis): random, often invalid, input to the public API and the
command line gives a result or a ``SkydomeError``, never another exception (DESIGN rule 8);
every frame is finite, with its colour (CIE XYZ) and scotopic channel non-negative.

Cases per run: the sum of ``max_examples`` below, 1322 (hypothesis runs that many passing
cases unless its strategy is exhausted, which none of these is), plus 23 ``@example`` cases,
the inputs that found the bugs fixed with these tests (each raised TypeError, ValueError,
OverflowError, AttributeError or IndexError before):

===============================  =====  =====  ===============================================
test                             cases  GL     what
===============================  =====  =====  ===============================================
test_preset_knobs                  150         ``atmosphere.preset(name, knobs)``
test_clouds_parameters             150         ``Clouds(preset, fields)``
test_light_pollution_parameters    100         ``LightPollution``, ``from_bortle``, ``City``
test_sky_description               150         ``SkyDescription.of``: places, times, the Sun,
                                               the air, clouds, night, display; its state
test_camera_parameters             200         cameras by name and angles, frame sizes,
                                               ``direction_from_angles``
test_directions_camera             100         ``DirectionsCamera`` of random arrays
test_camera_round_trip             150         the float64 twins: ``directions`` are unit
                                               vectors, ``project`` brings them back
test_sky_frames                     80  yes    ``Sky(...).render(...)``: settings and cameras,
                                               frames of 32x16 or less, depth and shadow images
test_cli_arguments                 200         ``skydome render`` (and ``timelapse``) flags
                                               up to the render (the Sky is not built)
test_cli_astro_commands             30         ``skydome ephemeris`` and ``events`` flags
test_cli_renders                    12  yes    ``skydome render`` of small frames to .npy
===============================  =====  =====  ===============================================

The GL cases (marked ``slow`` in conftest.py) share the session's cached tables
(``tests.conftest.TINY_TABLES``; the command line's ``--spectral fast``) and draw from a few
atmospheres, so that most cases reuse a table: 20 to 40 s in all on 2 CPU cores. The other
cases take about 5 s. Most GL cases are valid (one value in three is made wrong), so that
frames are drawn; ``--hypothesis-show-statistics`` shows what happened to them.

Linear sRGB may be negative in a frame: a colour outside its gamut (the deep red Sun at the
horizon) is kept as it is, as in EXR files; the colour it stands for is not negative.
"""

from __future__ import annotations

import datetime as dt
import math
import os
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, assume, event, example, given, settings
from hypothesis import strategies as st

from skydome.errors import SkydomeError
from tests.cli_helpers import run_cli
from tests.conftest import TINY_TABLES

# Health checks off: several strategies build big values (lists of floats), and the GL ones
# are slow per case on a CPU rasterizer; ``deadline=None`` for the same reason.
FAST = settings(deadline=None, suppress_health_check=list(HealthCheck), max_examples=100)
#: The GL cases: no explain phase (it reruns a failing case hundreds of times).
GL = settings(FAST, phases=[Phase.explicit, Phase.reuse, Phase.generate, Phase.shrink])


def outcome(fn, *args, **kwargs):
    """``fn(*args, **kwargs)``, or None when it raises a SkydomeError (the one exception a
    bad argument may raise); any other exception fails the test. NumPy's floating-point
    warnings on absurd values are not the subject here."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        try:
            return fn(*args, **kwargs)
        except SkydomeError:
            return None


# ---------------------------------------------------------------------------- strategies

#: Values of the wrong kind for anything (but None, often a default).
some_junk = st.one_of(
    st.booleans(),
    st.text(max_size=6),
    st.binary(max_size=3),
    st.complex_numbers(allow_nan=True, allow_infinity=True),
    st.lists(st.integers(-3, 3), max_size=3),
    st.dictionaries(st.text(max_size=2), st.integers(), max_size=2),
    st.just(object()),
    st.just(10**400),
    st.just(-(10**400)),
)
#: Values of the wrong kind for anything.
junk = st.one_of(st.none(), some_junk)
#: Any float, NaN and infinities included.
any_float = st.floats(allow_nan=True, allow_infinity=True)


def number(lo: float, hi: float):
    """Mostly a float in [lo, hi] (a valid value), else one outside it, a special float, a
    huge integer or junk."""
    span = hi - lo
    other = st.one_of(
        st.floats(lo - span, hi + span),
        st.sampled_from([math.nan, math.inf, -math.inf, 1e308, -1e308, 10**30]),
        junk,
    )
    return st.integers(0, 3).flatmap(lambda k: other if k == 0 else st.floats(lo, hi))


def maybe(strategy):
    return st.one_of(st.none(), strategy)


PRESET_NAMES = [
    "earth",
    "typical",
    "hazy",
    "urban",
    "maritime",
    "desert",
    "earth_bruneton",
    "earth_nishita",
    "mars",
]
preset_name = st.one_of(
    st.sampled_from(PRESET_NAMES), st.sampled_from(["", "Earth", "venus", "earth "]), junk
)
PLACES = [
    "Valletta",
    "Paranal",
    "Longyearbyen",
    "Ushuaia",
    "Nowhere at all",
    "",
    "  ",
    "35.9, 14.5",
]
place = st.one_of(
    st.sampled_from(PLACES),
    st.tuples(number(-90, 90), number(-180, 360)),
    st.tuples(number(-90, 90), number(-180, 360), number(-1000, 100_000)),
    st.lists(st.floats(-90, 90), max_size=4),
    junk,
)
iso_time = st.datetimes(dt.datetime(1, 1, 1), dt.datetime(9999, 12, 31)).map(
    lambda d: d.isoformat() + "Z"
)
time = st.one_of(
    iso_time,
    st.datetimes(dt.datetime(1, 1, 1), dt.datetime(9999, 12, 31)),
    st.sampled_from(["2018-03-01T19:00Z", "2024-07-05", "yesterday", "", "2024-13-45T99:00Z"]),
    any_float,  # Julian Dates
    st.lists(iso_time, max_size=2),
    junk,
)
cloud_preset = st.sampled_from(["fair", "overcast", "storm", "cirrus", "clear", "fog"])
overlays = st.one_of(
    st.sampled_from(["", "none", "lines", "labels", "grid", "all", "lines,grid", "stars"]),
    st.lists(st.sampled_from(["lines", "labels", "grid", "stars", ""]), max_size=3),
    junk,
)


# ---------------------------------------------------------------------------- the air


@settings(FAST, max_examples=150)
@given(
    name=preset_name,
    aod=maybe(number(0, 5)),
    angstrom=maybe(number(-0.5, 3)),
    ozone=maybe(number(0, 700)),
    albedo=maybe(number(0, 1)),
    ssa=maybe(number(0, 1)),
)
@example(name=[], aod=None, angstrom=None, ozone=None, albedo=None, ssa=None)
@example(name="typical", aod=None, angstrom=None, ozone=None, albedo=10**400, ssa=10**400)
def test_preset_knobs(name, aod, angstrom, ozone, albedo, ssa):
    from skydome.atmosphere import AtmosphereParams, preset

    params = outcome(
        preset, name, aod_550=aod, angstrom=angstrom, ozone_du=ozone, albedo=albedo, ssa=ssa
    )
    if params is not None:
        assert isinstance(params, AtmosphereParams)
        if aod is not None:
            assert params.aod_550 == pytest.approx(float(aod), rel=1e-6, abs=1e-9)


@settings(FAST, max_examples=150)
@given(
    name=st.one_of(cloud_preset, some_junk),
    fields=st.fixed_dictionaries(
        {},
        optional={
            "coverage": number(0, 1),
            "cloud_type": st.one_of(
                st.sampled_from(["stratus", "cumulus", "nimbus"]), number(0, 1)
            ),
            "base_m": number(0, 1e7),
            "thickness_m": number(1, 20_000),
            "precipitation": number(0, 1),
            "cirrus": number(0, 1),
            "cirrus_base_m": number(0, 1e7),
            "cirrus_thickness_m": number(1, 5000),
            "wind_m_s": st.one_of(
                st.tuples(number(-200, 200), number(-200, 200)),
                st.lists(number(-200, 200), max_size=3),
                junk,
            ),
            "seed": st.one_of(st.integers(-3, 2**40), junk),
            "tile_km": number(1, 1000),
        },
    ),
)
@example(name=[], fields={})
@example(name="fair", fields={"coverage": 10**400, "wind_m_s": (10**400, 0)})
def test_clouds_parameters(name, fields):
    from skydome.clouds import Clouds

    clouds = outcome(Clouds, name, **fields)
    if clouds is not None:
        assert 0.0 <= clouds.coverage <= 1.0 and 0.0 <= clouds.type_value <= 1.0
        assert clouds.thickness_m > 0 and math.isfinite(clouds.top_m)
        assert all(math.isfinite(v) for v in clouds.wind_m_s)


@settings(FAST, max_examples=100)
@given(
    bortle=st.one_of(st.integers(-1, 11), number(1, 9)),
    zenith=st.fixed_dictionaries(
        {}, optional={"zenith_mag_arcsec2": number(10, 30), "zenith_cd_m2": number(0, 1)}
    ),
    options=st.fixed_dictionaries(
        {},
        optional={
            "lamp": st.one_of(st.sampled_from(["hps", "led4000", "led"]), junk),
            "extinction_mag": number(0.05, 1),
            "natural_zenith_mag": number(15, 25),
            "cities": st.one_of(
                st.lists(st.tuples(number(-360, 360), number(1, 500), number(1, 1e8)), max_size=9),
                junk,
            ),
        },
    ),
)
@example(bortle=[], zenith={}, options={})
@example(bortle=1, zenith={}, options={"natural_zenith_mag": ""})
@example(bortle=1, zenith={}, options={"cities": None})
def test_light_pollution_parameters(bortle, zenith, options):
    from skydome.night.light_pollution import City, LightPollution

    options = dict(options)
    cities = options.get("cities")
    if isinstance(cities, list) and all(isinstance(c, tuple) for c in cities):
        made = [outcome(City, *c) for c in cities]
        if any(c is None for c in made):
            return
        options["cities"] = made
    for make, args in ((LightPollution, zenith), (LightPollution.from_bortle, {})):
        lp = outcome(make, *([] if args else [bortle]), **args, **options)
        if lp is not None:
            up = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [1.0, 0.0, 0.0]])
            lum = lp.luminance(up)
            assert np.all(np.isfinite(lum)) and np.all(lum >= 0.0)


# ---------------------------------------------------------------------------- descriptions


def description_settings():
    """Keyword arguments of ``SkyDescription.of`` (and ``Sky``), valid or not."""
    abstract = st.fixed_dictionaries(
        {"sun_elevation_deg": number(-90, 90)},
        optional={
            "sun_azimuth_deg": number(-360, 360),
            "pressure_hPa": number(0, 2000),
            "temperature_C": number(-100, 100),
            "time": time,
            "model": st.just("single"),
        },
    )
    placed = st.fixed_dictionaries(
        {"place": place, "time": time},
        optional={
            "pressure_hPa": number(0, 1200),
            "temperature_C": number(-100, 70),
            "sun_elevation_deg": number(-90, 90),
            "night": st.booleans(),
            "light_pollution": st.one_of(st.integers(-1, 11), junk),
        },
    )
    common = st.fixed_dictionaries(
        {},
        optional={
            "atmosphere": preset_name,
            "clouds": st.one_of(cloud_preset, junk),
            "night_vision": st.booleans(),
            "overlays": overlays,
            "cloud_quality": st.sampled_from(["full", "best", "interactive", "draft"]),
            "samples": st.one_of(st.integers(-2, 5000), junk),
            "sky_view_size": st.one_of(st.tuples(st.integers(-2, 600), st.integers(-2, 600)), junk),
        },
    )
    return st.tuples(st.one_of(abstract, placed), common).map(lambda ab: {**ab[0], **ab[1]})


@settings(FAST, max_examples=150)
@given(kwargs=description_settings())
@example({"sun_elevation_deg": 0.0, "sun_azimuth_deg": ""})
@example({"sun_elevation_deg": 10**400})
@example({"sun_elevation_deg": 0.0, "pressure_hPa": object()})
@example({"sun_elevation_deg": 0.0, "overlays": 5})
@example({"sun_elevation_deg": 0.0, "overlays": None})
@example({"place": "Valletta", "time": "2018-03-01T19:00Z", "pressure_hPa": [0]})
@example({"place": "Valletta", "time": "2018-03-01T19:00Z", "temperature_C": []})
@example({"place": "Valletta", "time": 10**400})
@example({"place": "Valletta", "time": 1.3221776208540553e40})  # a finite JD no theory holds
def test_sky_description(kwargs):
    from skydome.description import SkyDescription

    kwargs = dict(kwargs)
    place = kwargs.pop("place", None)
    when = kwargs.pop("time", None)
    description = outcome(SkyDescription.of, place, when, **kwargs)
    if description is None:
        return
    state = outcome(description.state)
    if state is not None:
        sun = state.sun
        assert -90.0 <= sun.elevation_deg <= 90.0 and math.isfinite(sun.azimuth_deg)
    outcome(description.layers)


# ---------------------------------------------------------------------------- cameras

camera_name = st.one_of(
    st.sampled_from(["perspective", "fisheye", "equirect", "cubemap"]),
    st.sampled_from(["pinhole", "", "Perspective"]),
    junk,
)
side = st.one_of(st.integers(1, 64), st.integers(-2, 20_000), st.floats(0, 64), junk)


@settings(FAST, max_examples=200)
@given(
    name=camera_name,
    angles=st.fixed_dictionaries(
        {},
        optional={
            "fov_deg": number(0.01, 179),
            "yaw_deg": number(-360, 360),
            "pitch_deg": number(-90, 90),
            "roll_deg": number(-360, 360),
        },
    ),
    width=side,
    height=side,
)
@example(name="perspective", angles={"pitch_deg": ""}, width=8, height=4)
def test_camera_parameters(name, angles, width, height):
    from skydome import direction_from_angles
    from skydome.core.cameras import Camera, PerspectiveCamera, make_camera

    d = outcome(direction_from_angles, angles.get("pitch_deg", 0.0), angles.get("yaw_deg", 0.0))
    if d is not None:
        assert d.shape == (3,) and abs(np.linalg.norm(d) - 1.0) < 1e-12

    camera = outcome(make_camera, name, **angles)
    direct = outcome(PerspectiveCamera, **angles)
    if direct is not None:
        assert camera is None or name != "perspective" or camera == direct
    if camera is None:
        return
    assert isinstance(camera, Camera)
    size = outcome(camera.frame_size, width, height)
    if size is not None:
        w, h = size
        assert isinstance(w, int) and isinstance(h, int) and w >= 1 and h >= 1
        assert isinstance(width, (int, np.integer)) and isinstance(height, (int, np.integer))
    if isinstance(camera, PerspectiveCamera):
        basis = camera.basis()
        assert np.all(np.isfinite(basis))
        np.testing.assert_allclose(basis.T @ basis, np.eye(3), atol=1e-9)


directions_array = st.one_of(
    st.integers(1, 5).flatmap(
        lambda n: st.lists(st.lists(any_float, min_size=3, max_size=3), min_size=n, max_size=n)
    ),
    st.lists(st.lists(st.floats(-2, 2), min_size=3, max_size=3), min_size=1, max_size=6),
    st.lists(st.lists(st.floats(-2, 2), min_size=0, max_size=4), max_size=3),
    st.lists(
        st.lists(st.lists(st.floats(-1, 1), min_size=3, max_size=3), min_size=2, max_size=2),
        min_size=1,
        max_size=2,
    ),
    st.lists(st.lists(junk, min_size=3, max_size=3), min_size=1, max_size=2),
    junk,
)


@settings(FAST, max_examples=100)
@given(directions=directions_array)
@example([[], [0.0]])
@example([[0.0, 0.0, 1.3407807929942597e154]])
@example({})
def test_directions_camera(directions):
    from skydome.core.cameras import DirectionsCamera

    camera = outcome(DirectionsCamera, directions)
    if camera is not None:
        d = camera.view_directions
        assert d.ndim == 3 and d.shape[-1] == 3 and np.all(np.isfinite(d))
        np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0, rtol=1e-12)
        w, h = camera.frame_size()
        assert (h, w) == d.shape[:2]


def valid_camera():
    from skydome.core.cameras import (
        CubemapCamera,
        EquirectCamera,
        FisheyeCamera,
        PerspectiveCamera,
    )

    perspective = st.builds(
        PerspectiveCamera,
        fov_deg=st.floats(1.0, 170.0),
        yaw_deg=st.floats(-360, 360),
        pitch_deg=st.floats(-90, 90),
        roll_deg=st.floats(-360, 360),
    )
    others = st.sampled_from([FisheyeCamera(), EquirectCamera(), CubemapCamera()])
    return st.one_of(perspective, others)


@settings(FAST, max_examples=150)
@given(
    camera=valid_camera(),
    width=st.integers(1, 4096),
    height=st.integers(1, 4096),
    u=st.lists(st.floats(0.0, 1.0), min_size=1, max_size=16),
    v=st.lists(st.floats(0.0, 1.0), min_size=1, max_size=16),
)
def test_camera_round_trip(camera, width, height, u, v):
    """Frame positions -> directions -> positions comes back (where the camera sees the
    direction) and directions are unit vectors."""
    from skydome.core.cameras import CubemapCamera, EquirectCamera, FisheyeCamera

    size = outcome(camera.frame_size, width, height)
    assume(size is not None)  # a cube map's frame is 6 faces wide: at most MAX_SIDE
    w, h = size
    n = min(len(u), len(v))
    x = np.asarray(u[:n]) * w
    y = np.asarray(v[:n]) * h
    if isinstance(camera, CubemapCamera):
        x = np.minimum(x, w * (1 - 1e-9))  # x == w is past the last face
    d, seen = camera.directions(x, y, w, h)
    assert d.shape == (n, 3) and np.all(np.isfinite(d))
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0, rtol=1e-12)
    px, py, visible = camera.project(d, w, h)
    assert np.all(np.isfinite(px[visible])) and np.all(np.isfinite(py[visible]))
    keep = seen & visible
    if isinstance(camera, FisheyeCamera):
        # The centre (the zenith) has no azimuth, and the rim is the horizon.
        rho = np.hypot(x - 0.5 * w, y - 0.5 * h) / (0.5 * min(w, h))
        keep &= (rho > 1e-6) & (rho < 1.0 - 1e-9)
    if isinstance(camera, EquirectCamera):
        # The poles (top and bottom rows' edges) have no azimuth; azimuth 0 wraps to w.
        keep &= (y > 1e-6 * h) & (y < h * (1 - 1e-6))
        px = np.where(px > w - 1e-6 * w, px - w, px)
        xx = np.where(x > w - 1e-6 * w, x - w, x)
    else:
        xx = x
    if isinstance(camera, CubemapCamera):
        # A cube edge belongs to either face.
        fx = np.mod(x, h) / h
        keep &= (fx > 1e-9) & (fx < 1 - 1e-9) & (y > 1e-9 * h) & (y < h * (1 - 1e-9))
    tol = 1e-6 * max(w, h)
    np.testing.assert_allclose(px[keep], xx[keep], atol=tol)
    np.testing.assert_allclose(py[keep], y[keep], atol=tol)
    if camera.has_projection:
        omega = camera.solid_angle(d, w, h)
        assert np.all(np.isfinite(omega)) and np.all(omega >= 0)


# ---------------------------------------------------------------------------- frames (GL)


def bad_number(lo: float, hi: float):
    """A value outside [lo, hi]: beyond either end, NaN, an infinity or junk."""
    span = max(hi - lo, 1.0)
    return st.one_of(
        st.floats(hi, hi + span, exclude_min=True),
        st.floats(lo - span, lo, exclude_max=True),
        st.sampled_from([math.nan, math.inf, -math.inf]),
        junk,
    )


def corrupted(valid: st.SearchStrategy, bad: dict[str, st.SearchStrategy]):
    """Settings drawn from ``valid``; one time in three, one of them replaced by a value of
    ``bad`` (so that most cases reach the renderer and the rest try one wrong value)."""

    @st.composite
    def build(draw):
        kwargs = draw(valid)
        if draw(st.integers(0, 2)) == 0:
            key = draw(st.sampled_from(sorted(bad)))
            kwargs[key] = draw(bad[key])
        return kwargs

    return build()


def sky_settings():
    """Settings of a small Sky: an abstract Sun or a place and time, a few atmospheres (most
    share their tables), clouds, night and display; sometimes one value wrong."""
    atmosphere = st.one_of(
        st.sampled_from(["earth", "earth", "hazy", "mars", "earth_nishita"]),
        st.fixed_dictionaries(
            {"name": st.sampled_from(["earth", "typical"])},
            optional={
                "aod_550": st.sampled_from([0.0, 0.4, 5.0]),
                "angstrom": st.sampled_from([-0.5, 3.0]),
                "ozone_du": st.sampled_from([0.0, 700.0]),
            },
        ),
    )
    abstract = st.fixed_dictionaries(
        {"sun_elevation_deg": st.floats(-90, 90)},
        optional={
            "sun_azimuth_deg": st.floats(-360, 360),
            "pressure_hPa": st.floats(0, 2000),
            "temperature_C": st.floats(-100, 100),
        },
    )
    placed = st.fixed_dictionaries(
        {
            "place": st.one_of(
                st.sampled_from(["Valletta", "Paranal", "Longyearbyen", "Ushuaia", "Mauna Kea"]),
                st.tuples(st.floats(-90, 90), st.floats(-180, 359.9)),
                st.tuples(st.floats(-90, 90), st.floats(-180, 359.9), st.floats(-1000, 100_000)),
            ),
            "time": st.one_of(
                iso_time, st.sampled_from(["2018-03-01T19:00Z", "2024-07-05T23:00Z"])
            ),
        },
        optional={
            "night": st.booleans(),
            "light_pollution": st.integers(1, 9),
            "pressure_hPa": st.floats(0, 1200),
            "temperature_C": st.floats(-100, 70),
        },
    )
    common = st.fixed_dictionaries(
        {"atmosphere": atmosphere},
        optional={
            "clouds": st.sampled_from(["fair", "overcast", "storm", "cirrus", "clear"]),
            "night_vision": st.booleans(),
            "overlays": st.sampled_from(["", "lines", "labels", "grid", "all"]),
        },
    )
    valid = st.tuples(st.one_of(abstract, placed), common).map(lambda ab: {**ab[0], **ab[1]})
    bad = {
        "sun_elevation_deg": bad_number(-90, 90),
        "sun_azimuth_deg": bad_number(-360, 360),
        "pressure_hPa": bad_number(0, 2000),
        "place": st.one_of(
            st.sampled_from(["Atlantis", ""]),
            st.tuples(bad_number(-90, 90), st.floats(-180, 180)),
            junk,
        ),
        "time": st.one_of(st.sampled_from(["noon", "2024-02-30T00:00Z"]), any_float, junk),
        "atmosphere": st.one_of(st.sampled_from(["venus", "", "Earth"]), junk),
        "clouds": st.one_of(st.just("fog"), junk),
        "light_pollution": st.one_of(st.sampled_from([0, 10, 5.5]), junk),
        "overlays": st.one_of(st.sampled_from(["stars", "lines,,x"]), junk),
        "model": st.sampled_from(["single", "double"]),
        "config": junk,
    }
    return corrupted(valid, bad)


def render_settings():
    """What ``Sky.render`` takes: a camera or a look, a small size, altitude, exposure, tone
    map, and per-pixel depth or shadow images; sometimes one value wrong."""
    from skydome.core.cameras import DirectionsCamera

    camera = st.one_of(
        st.none(),
        valid_camera(),
        st.lists(st.lists(st.floats(-1, 1), min_size=3, max_size=3), min_size=1, max_size=8).map(
            lambda d: DirectionsCamera(np.asarray(d) + [0.0, 0.0, 2.0])
        ),  # none zero
    )
    valid = st.fixed_dictionaries(
        {"camera": camera, "width": st.integers(1, 32), "height": st.integers(1, 16)},
        optional={
            "look": st.sampled_from(["sun", "zenith", "west", "moon"]),
            "altitude_m": st.one_of(st.floats(0, 100), st.floats(0, 1e8)),
            "exposure": st.one_of(st.just("auto"), st.none(), st.floats(-20, 40)),
            "compensation_ev": st.floats(-20, 20),
            "tonemap": st.sampled_from(
                [None, "filmic", "linear", "hvs", "reinhard", "exponential"]
            ),
            "depth_m": st.integers(0, 2**32 - 1).map(PixelSeed),
            "shadow_length_m": st.integers(0, 2**32 - 1).map(PixelSeed),
        },
    )
    bad = {
        "camera": some_junk,
        "width": st.one_of(st.sampled_from([0, -1, 16385, 1.5]), junk),
        "height": st.one_of(st.sampled_from([0, -3, 20000, 2.0]), junk),
        "look": st.one_of(st.sampled_from(["up", "Sun", ""]), some_junk),
        "altitude_m": bad_number(0, 1e8),
        "exposure": st.one_of(bad_number(-20, 40), st.just("manual")),
        "compensation_ev": bad_number(-20, 20),
        "tonemap": st.one_of(st.just("sepia"), some_junk),
        "depth_m": some_junk,
        "shadow_length_m": some_junk,
    }
    return corrupted(valid, bad)


#: Per-pixel distances (m) for the depth and shadow images: none (0, +inf, < 0), near, far.
DISTANCES_M = np.array([0.0, math.inf, -5.0, 1.0, 250.0, 1e4, 3e5, 1e7, 1e30])


class PixelSeed(int):
    """The seed of a per-pixel image (depth or shadow lengths) of the frame's size."""


def per_pixel_images(render_kwargs: dict, size) -> dict:
    """``render_kwargs`` with each PixelSeed made an image of DISTANCES_M of the frame's
    ``size`` (W, H)."""
    out = dict(render_kwargs)
    for key in ("depth_m", "shadow_length_m"):
        seed = out.get(key)
        if isinstance(seed, PixelSeed):
            rng = np.random.default_rng(int(seed))
            out[key] = rng.choice(DISTANCES_M, size=(size[1], size[0]))
    return out


def _make_sky(settings_: dict):
    from skydome import Sky
    from skydome.atmosphere import preset

    kwargs = {"config": TINY_TABLES, **settings_}
    atmosphere = kwargs.pop("atmosphere")
    if isinstance(atmosphere, dict) and "name" in atmosphere:  # else junk: Sky must refuse it
        atmosphere = preset(**atmosphere)
    place, when = kwargs.pop("place", None), kwargs.pop("time", None)
    return Sky(place, when, atmosphere, **kwargs)


def check_frame(data: np.ndarray) -> None:
    """A frame's data is finite and physical: float32 (H, W, 4), linear sRGB (cd/m^2) and
    scotopic cd/m^2. Linear sRGB itself may go negative for a colour outside its gamut (the
    deep red Sun at the horizon: the frames keep it, as EXR files do), the colour it stands
    for may not: its CIE XYZ and the scotopic channel are >= 0 (to float32 rounding)."""
    from skydome.spectra import LINEAR_SRGB_TO_XYZ

    assert data.dtype == np.float32 and data.ndim == 3 and data.shape[-1] == 4
    assert np.all(np.isfinite(data)), "a frame holds NaN or Inf"
    rgb = data[..., :3].astype(np.float64)
    xyz = rgb @ LINEAR_SRGB_TO_XYZ.T
    rounding = 1e-5 * np.abs(rgb).max(axis=-1, keepdims=True)
    assert np.all(xyz >= -rounding), f"negative XYZ {xyz.min()} in a frame"
    assert data[..., 3].min() >= 0.0, f"negative scotopic luminance {data[..., 3].min()}"


@settings(GL, max_examples=80)
@given(sky_kwargs=sky_settings(), render_kwargs=render_settings())
@example(
    {"sun_elevation_deg": 0.0, "atmosphere": "earth"},
    {"camera": None, "width": 1, "height": 1},  # the red Sun: linear sRGB < 0, XYZ >= 0
)
@example(
    {"sun_elevation_deg": 0.0, "atmosphere": "earth"}, {"camera": object(), "width": 1, "height": 1}
)
@example(
    {"sun_elevation_deg": 0.0, "atmosphere": "earth"},
    {"camera": None, "width": 1, "height": 1, "altitude_m": ""},
)
@example(
    {"sun_elevation_deg": 0.0, "atmosphere": "earth"},
    {"camera": None, "width": 1, "height": 1, "depth_m": ""},
)
def test_sky_frames(ctx, sky_kwargs, render_kwargs):
    """Every frame of a random Sky and camera is finite and non-negative (RGB and the
    scotopic channel), or the settings raise a SkydomeError."""
    from skydome.core.cameras import Camera, check_size

    try:
        sky = _make_sky(sky_kwargs)
        event("Sky: made")
    except SkydomeError as exc:
        event(f"Sky: {str(exc)[:40]}")
        sky = None
    if sky is None:
        return
    with sky:
        camera = render_kwargs.get("camera")
        size = (render_kwargs.get("width"), render_kwargs.get("height"))
        if isinstance(camera, Camera):
            size = outcome(camera.frame_size, *size)
        elif camera is None:
            size = outcome(check_size, *size)
        try:
            frame = sky.render(**per_pixel_images(render_kwargs, size or (1, 1)))
            event("render: a frame")
        except SkydomeError as exc:
            event(f"render: {str(exc)[:40]}")
            return
    check_frame(frame.data)
    if render_kwargs.get("tonemap") is not None:
        assert frame.image is not None and frame.image.dtype == np.uint8
        assert frame.image.shape == frame.data.shape[:2] + (3,)


# ---------------------------------------------------------------------------- the command line


class _Rendered(Exception):
    """Raised instead of building a Sky: the command line took its arguments."""


cli_text = st.text(st.characters(codec="utf-8", exclude_categories=("Cs", "Cc")), max_size=6)


def cli_number(lo: float, hi: float):
    """A number for a flag, as text: mostly in [lo, hi], else beyond it, NaN, an infinity or
    an overflowing literal."""
    span = hi - lo
    other = st.one_of(
        st.floats(lo - span, hi + span).map(repr),
        st.sampled_from(["nan", "inf", "-inf", "1e400", "0x10", "1,5"]),
    )
    return st.integers(0, 2).flatmap(lambda k: other if k == 0 else st.floats(lo, hi).map(repr))


def cli_flags():
    """``skydome render`` flags, valid or not: (flag, value) pairs and a flag without its
    value now and then."""

    def value(*choices):
        return st.one_of(st.sampled_from(choices), cli_text)

    pairs = {
        "--sun-elevation": cli_number(-90, 90),
        "--sun-azimuth": cli_number(-360, 360),
        "--place": value("Valletta", "Paranal", "Atlantis", ""),
        "--lat": cli_number(-90, 90),
        "--lon": cli_number(-180, 360),
        "--elevation": cli_number(-1000, 100_000),
        "--time": value("2018-03-01T19:00Z", "2024-07-05T02:00Z", "tomorrow"),
        "--atmosphere": value("earth", "hazy", "mars", "venus"),
        "--aod": cli_number(0, 5),
        "--angstrom": cli_number(-0.5, 3),
        "--ozone": cli_number(0, 700),
        "--albedo": cli_number(0, 1),
        "--orders": value("1", "4", "21", "0", "x"),
        "--spectral": value("fast", "accurate", "slow"),
        "--bortle": value("1", "5", "9", "0", "10", "x"),
        "--overlay": value("lines", "grid,labels", "all", "stars"),
        "--clouds": value("fair", "overcast", "fog"),
        "--coverage": cli_number(0, 1),
        "--cloud-base": cli_number(0, 10_000),
        "--cloud-thickness": cli_number(0, 20_000),
        "--cloud-type": value("cumulus", "stratus", "nimbus"),
        "--cirrus": cli_number(0, 1),
        "--cloud-seed": value("0", "7", "-1", "x"),
        "--wind": value("5,90", "300,0", "5", "a,b", "nan,0"),
        "--weather-map": value("/nonexistent.png", ""),
        "--look": value("sun", "moon", "zenith", "up"),
        "--camera": value("perspective", "fisheye", "equirect", "cubemap", "pinhole"),
        "--fov": cli_number(0.01, 179),
        "--pitch": cli_number(-90, 90),
        "--yaw": cli_number(-360, 360),
        "--roll": cli_number(-360, 360),
        "--altitude": cli_number(0, 1e8),
        "--exposure": value("auto", "12", "99", "bright"),
        "--exposure-compensation": cli_number(-20, 20),
        "--tonemap": value("filmic", "linear", "sepia"),
        "--model": value("precomputed", "single", "double"),
        "--samples": value("4", "0", "5000", "x"),
        "--size": value("8x4", "16x8", "0x4", "8x", "99999x99999"),
        "--no-such-flag": value("1"),
    }
    missing = st.sampled_from(["--fov", "--time", "--size"])  # their value left out
    flags = st.lists(st.sampled_from(sorted(pairs)), max_size=5, unique=True)
    chosen = flags.flatmap(
        lambda names: st.tuples(*[pairs[n].map(lambda v, n=n: [n, v]) for n in names])
    )
    extra = st.one_of(st.just([]), st.just(["--night-vision"]), missing.map(lambda f: [f]))
    return st.tuples(chosen, extra).map(lambda ce: [a for p in ce[0] for a in p] + ce[1])


def cli_render_flags():
    """``skydome render`` flags of a small frame with the ``earth`` air (its tables are
    shared by every case): a valid command, one time in three with one value wrong."""
    number = lambda lo, hi: st.floats(lo, hi).map(lambda v: f"{v:.6g}")  # noqa: E731
    scene = st.one_of(
        st.just([]),
        st.tuples(number(-90, 90), number(-360, 360)).map(
            lambda ea: ["--sun-elevation", ea[0], "--sun-azimuth", ea[1]]
        ),
        st.tuples(st.sampled_from(["Valletta", "Paranal", "Longyearbyen"]), iso_time).map(
            lambda pt: ["--place", pt[0], "--time", pt[1]]
        ),
        st.tuples(number(-90, 90), number(-180, 360), iso_time).map(
            lambda llt: ["--lat", llt[0], "--lon", llt[1], "--time", llt[2]]
        ),
    )
    options = {
        "--look": st.sampled_from(["sun", "zenith", "west"]),
        "--camera": st.sampled_from(["perspective", "fisheye", "equirect", "cubemap"]),
        "--fov": number(1, 179),
        "--pitch": number(-90, 90),
        "--yaw": number(-360, 360),
        "--roll": number(-360, 360),
        "--altitude": st.one_of(number(0, 100), number(0, 1e8)),
        "--exposure": st.one_of(st.just("auto"), number(-20, 40)),
        "--exposure-compensation": number(-20, 20),
        "--tonemap": st.sampled_from(["filmic", "linear", "hvs", "reinhard", "exponential"]),
        "--size": st.tuples(st.integers(1, 16), st.integers(1, 8)).map(lambda s: f"{s[0]}x{s[1]}"),
        "--clouds": st.sampled_from(["fair", "overcast", "cirrus", "clear"]),
    }
    bad = {
        "--sun-elevation": st.sampled_from(["91", "nan", "x"]),
        "--fov": st.sampled_from(["0", "180", "inf"]),
        "--camera": st.just("pinhole"),
        "--size": st.sampled_from(["0x4", "8", "x"]),
        "--look": st.just("moon"),  # without a place there is no Moon
        "--exposure": st.sampled_from(["41", "bright"]),
        "--bortle": st.just("5"),  # needs a place
        "--coverage": st.just("0.5"),  # needs --clouds
    }

    @st.composite
    def build(draw):
        args = list(draw(scene))
        names = draw(st.lists(st.sampled_from(sorted(options)), max_size=4, unique=True))
        for name in names:
            args += [name, draw(options[name])]
        if draw(st.integers(0, 2)) == 0:
            name = draw(st.sampled_from(sorted(bad)))
            args += [name, draw(bad[name])]
        if draw(st.booleans()):
            args.append("--night-vision")
        return args

    return build()


def _check_cli_result(res, out):
    assert res.returncode in (0, 2), (res.returncode, res.stderr)
    assert "Traceback" not in res.stderr and "Traceback" not in res.stdout
    if res.returncode == 2:
        lines = res.stderr.splitlines()
        errors = [line for line in lines if line.startswith("skydome: error:")]
        assert len(errors) == 1 and lines[-1] == errors[0], res.stderr
        assert not [line for line in lines if not line.startswith("skydome: ")], res.stderr
        assert not os.path.exists(out), f"{out} written by a failed command"


def timelapse_flags():
    """``skydome timelapse``'s own flags, valid or not (with cli_flags' shared ones)."""
    value = lambda *choices: st.one_of(st.sampled_from(choices), cli_text)  # noqa: E731
    return st.fixed_dictionaries(
        {
            "--start": value("2024-06-21T19:00Z", "2024-06-21", "dusk"),
            "--end": value("2024-06-21T19:02Z", "2024-06-21T18:00Z", "2999-01-01T00:00Z"),
        },
        optional={
            "--step": value("30s", "1min", "0s", "-1h", "2 fortnights"),
            "--fps": cli_number(1, 240),
            "--format": value("png", "exr", "gif"),
            "--adaptation-speed": cli_number(0.01, 1e6),
            "--exposure": value("adapt", "auto", "12", "99"),
        },
    ).map(lambda d: [a for k, v in d.items() for a in (k, v)])


#: render's flags that timelapse does not take (it has no Sun, tables or night flags).
RENDER_ONLY = {
    "--sun-elevation", "--sun-azimuth", "--time", "--orders", "--spectral", "--bortle",
    "--overlay", "--roll", "--model", "--samples", "--night-vision",
}  # fmt: skip


def _timelapse_shared(args: list[str]) -> list[str]:
    """cli_flags' ``args`` without render's own flags (and their values), with a place
    when they give none (most are then valid up to the Sky)."""
    out, i = [], 0
    while i < len(args):
        if args[i] in RENDER_ONLY:
            i += 1 if args[i] == "--night-vision" else 2
            continue
        out.append(args[i])
        i += 1
    if not {"--place", "--lat", "--lon"} & set(out):
        out = ["--lat", "35.9", "--lon", "14.5", *out]
    return out


@settings(FAST, max_examples=200)
@given(
    command=st.integers(0, 3).map(lambda k: "timelapse" if k == 0 else "render"),
    args=cli_flags(),
    timelapse=timelapse_flags(),
    mp4=st.booleans(),
)
def test_cli_arguments(tmp_path_factory, command, args, timelapse, mp4):
    """Random ``skydome render`` (or ``timelapse``) flags, as far as the render: exit status
    2 with one ``skydome: error:`` line on stderr and nothing written, or a valid command
    (the Sky is not built: see test_cli_renders)."""
    import skydome.sky

    folder = tmp_path_factory.mktemp("cli")
    if command == "render":
        out = folder / "sky.png"
    else:
        out = folder / ("day.mp4" if mp4 else "frames")
        args = timelapse + _timelapse_shared(args)
    with pytest.MonkeyPatch.context() as mp:

        def refuse(*a, **k):
            raise _Rendered

        mp.setattr(skydome.sky, "Sky", refuse)
        try:
            res = run_cli(command, *args, "-o", out)
        except _Rendered:
            event(f"{command}: valid, a Sky would be built")
            return
    event(f"{command} exit {res.returncode}: {res.stderr[16:46]}")
    _check_cli_result(res, out)
    assert res.returncode == 2, f"{args} exited {res.returncode} without building a sky"


def astro_flags():
    """``skydome ephemeris`` and ``skydome events`` flags, valid or not."""
    given = st.fixed_dictionaries(
        {"--lat": cli_number(-90, 90), "--lon": cli_number(-360, 360)},
        optional={"--elevation": cli_number(-1000, 100_000)},
    )
    missing = st.fixed_dictionaries({}, optional={"--lat": cli_number(-90, 90)})  # no --lon
    place = st.integers(0, 4).flatmap(lambda k: missing if k == 0 else given)
    ephemeris = st.fixed_dictionaries(
        {"--time": st.one_of(iso_time, st.sampled_from(["2024-06-21", "soon", ""]))},
        optional={
            "--pressure": cli_number(0, 1200),
            "--temperature": cli_number(-100, 70),
            "--bodies": st.one_of(
                st.sampled_from(["sun", "moon,mars", "sirius", "", ",", "pluto", "vega,sun"]),
                cli_text,
            ),
            "--atmosphere": st.sampled_from(["earth", "mars", "venus"]),
        },
    )
    events = st.fixed_dictionaries(
        {
            "--date": st.one_of(
                iso_time.map(lambda t: t[:10]),
                st.sampled_from(["2024-02-30", "2024-06-21T00:00", "x", ""]),
            )
        },
        optional={"--days": st.sampled_from(["1", "0", "3661", "-1", "x", "1.5"])},
    )
    command = st.one_of(
        st.tuples(st.just("ephemeris"), place, ephemeris),
        st.tuples(st.just("events"), place, events),
    )
    return command.map(lambda c: [c[0]] + [a for d in c[1:] for k, v in d.items() for a in (k, v)])


@settings(FAST, max_examples=30)
@given(args=astro_flags(), as_json=st.booleans())
def test_cli_astro_commands(args, as_json):
    """Random ``skydome ephemeris`` / ``events`` flags (NumPy only, no GL): exit status 0,
    or 2 with one ``skydome: error:`` line and no traceback."""
    res = run_cli(*args, *(["--json"] if as_json else []))
    event(f"{args[0]} exit {res.returncode} {res.stderr[16:50]}")
    _check_cli_result(res, "/nonexistent/never-written")
    if res.returncode == 0 and as_json:
        import json

        json.loads(res.stdout)  # JSON with no NaN/Infinity (they are null)
        assert "NaN" not in res.stdout and "Infinity" not in res.stdout


@settings(GL, max_examples=12)
@given(args=cli_render_flags())
def test_cli_renders(ctx, tmp_path_factory, args):
    """A few random ``skydome render`` commands that draw (small frames, the fast tables):
    exit status 0 and a finite frame written, or 2 with one error line and nothing."""
    if "--size" not in args:
        args += ["--size", "8x4"]
    out = tmp_path_factory.mktemp("cli") / "sky.npy"
    res = run_cli("render", *args, "--spectral", "fast", "-o", out)
    event(f"exit {res.returncode}")
    _check_cli_result(res, out)
    if res.returncode == 0:
        check_frame(np.load(out))
