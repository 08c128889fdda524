"""The scene: a Sky's layers and frame graph against the renderers they are built from, the
GPU post passes against their NumPy references, the moonlit sky against the irradiance
ratio, and a day at 1-minute steps without jumps."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from skydome import Sky
from skydome.astro import to_time
from skydome.atmosphere.layer import AtmosphereLayer
from skydome.celestial.moon import MoonLayer
from skydome.celestial.sun import SunLayer
from skydome.core.cameras import (
    DirectionsCamera,
    EquirectCamera,
    FisheyeCamera,
    PerspectiveCamera,
    direction_from_angles,
    disk_scissor,
)
from skydome.core.layer import Layer
from skydome.description import observer_for
from skydome.display.exposure import log_average_luminance
from skydome.display.gpu_tonemap import gpu_tonemap
from skydome.errors import ParameterError
from skydome.gpu.inputs import ShaderInputs
from skydome.scene.state import state_at, state_series
from tests.air_frames import precomputed_frames as precomputed_renderer

VALLETTA = (35.8989, 14.5146, 56.0)


@pytest.fixture(scope="module")
def abstract_sky():
    return Sky(sun_elevation_deg=30.0, sun_azimuth_deg=200.0)


@pytest.fixture(scope="module")
def valletta():
    # 2018-03-01 19:00 UTC: a full Moon 28 deg up in the east, the Sun 26 deg down. The Sun,
    # the Moon and the air only: the stars and the night glow are tests/test_night_sky.py's.
    return Sky(VALLETTA, "2018-03-01T19:00Z", night=False)


def test_sky_is_the_precomputed_renderer_where_nothing_lies_behind(abstract_sky):
    # The composite adds behind x T and nothing else: away from the Sun's disk, a scene
    # frame is the precomputed renderer's frame of the same atmosphere and Sun (same tables,
    # same pass, one define more). Only float32 rounding may differ.
    cam = PerspectiveCamera(fov_deg=100, yaw_deg=20, pitch_deg=20)  # the Sun behind the camera
    scene = abstract_sky.render(cam, 160, 90, exposure=None).data
    sun = abstract_sky.state.sun.direction_true  # the air is lit from the airless direction
    reference = precomputed_renderer().render(cam, 160, 90, sun_direction=sun, altitude_m=1.7)
    np.testing.assert_allclose(scene, reference.data, rtol=1e-5, atol=1e-6)


def test_layers_turn_off_and_on(abstract_sky):
    cam = abstract_sky.camera("sun", fov_deg=2.0)
    with_sun = abstract_sky.render(cam, 64, 64, exposure=None).luminance
    abstract_sky.layer("sun").enabled = False
    try:
        without = abstract_sky.render(cam, 64, 64, exposure=None).luminance
    finally:
        abstract_sky.layer("sun").enabled = True
    # The disk is 1e8-1e9 cd/m^2 against a sky of 1e4: it is the only difference.
    assert with_sun.max() > 1e3 * without.max()
    assert np.count_nonzero(np.abs(with_sun - without) > 1e-3 * without) < 0.5 * with_sun.size
    with pytest.raises(ParameterError, match="no layer 'clouds'"):
        abstract_sky.layer("clouds")


def test_setting_sun_lower_limb_is_redder(ctx):
    # Per-pixel transmittance: the lower limb of a Sun on the horizon looks through more air.
    sky = Sky(sun_elevation_deg=0.4, sun_azimuth_deg=270.0)
    cam = PerspectiveCamera(fov_deg=1.5, yaw_deg=270.0, pitch_deg=0.4)
    f = sky.render(cam, 96, 96, exposure=None).data
    lum = f[..., :3] @ np.array([0.2126, 0.7152, 0.0722])
    cols = lum.max(axis=0) > 0.2 * lum.max()
    rows = np.flatnonzero(lum[:, cols].max(axis=1) > 0.2 * lum.max())
    top, bottom = f[rows[1], 48], f[rows[-2], 48]
    assert bottom[2] / bottom[0] < 0.8 * (top[2] / top[0])  # B/R lower at the lower limb
    assert bottom[1] < top[1]


def test_gpu_exposure_matches_the_numpy_log_average(valletta, abstract_sky):
    # The GPU pass averages ln L over a 256 x 128 grid of samples; NumPy over every pixel.
    # A smooth sky's log-average from 32768 evenly spread samples is within 1 % (the disk
    # pixels are too few to matter either way).
    for sky, cam in (
        (abstract_sky, PerspectiveCamera(fov_deg=90, yaw_deg=200, pitch_deg=10)),
        (valletta, FisheyeCamera()),
    ):
        # metering "average": key 0.18 at any luminance (the default "eye" lowers the key
        # of this night frame, Krawczyk et al. 2005; tests/test_metering.py)
        frame = sky.render(cam, 320, 240, exposure="auto", metering="average")
        key_scale = 2.0 ** (-frame.info["exposure_ev100"]) / 1.2
        expected = log_average_luminance(frame)
        assert 0.18 / key_scale == pytest.approx(expected, rel=0.01)


def test_draw_into_a_framebuffer_equals_render(ctx, abstract_sky):
    # The viewer's path (draw: no read-back, GPU exposure) and the file path (render) are the
    # same graph and passes: the same 8-bit image, up to one code value (the draw pass does
    # not snap to code values; an RGBA8 target rounds).
    w, h = 128, 72
    cam = PerspectiveCamera(fov_deg=90, yaw_deg=200, pitch_deg=10)
    tex = ctx.texture((w, h), 4, dtype="f1")
    fbo = ctx.framebuffer(color_attachments=[tex])
    try:
        for exposure in ("auto", 14.0):
            abstract_sky.draw(fbo, cam, size=(w, h), exposure=exposure, tonemap="filmic")
            drawn = np.frombuffer(fbo.read(components=3), np.uint8).reshape(h, w, 3)[::-1]
            image = abstract_sky.render(cam, w, h, exposure=exposure, tonemap="filmic").image
            assert np.abs(drawn.astype(int) - image.astype(int)).max() <= 1
    finally:
        fbo.release()
        tex.release()


@pytest.mark.parametrize("night", [False, True])
def test_at_reuses_the_tables_and_equals_a_fresh_sky(valletta, night):
    # With the night layers too: what they cache by date (the stars' apparent places) must
    # follow the new time.
    base = valletta if not night else Sky(VALLETTA, "2018-03-01T19:00Z")
    tables = base.layer("atmosphere").sky.tables
    later = base.at("2018-03-01T23:00Z")
    assert later.layer("atmosphere").sky.tables is tables  # no new tables: shared
    assert later.graph is not base.graph  # its own layers and settings
    fresh = Sky(VALLETTA, "2018-03-01T23:00Z", night=night)
    cam = later.camera("moon", fov_deg=60)
    a = later.render(cam, 96, 64, exposure=None).data
    b = fresh.render(cam, 96, 64, exposure=None).data
    np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-9)
    assert later.state.moon.elevation_deg != base.state.moon.elevation_deg


def test_moonlit_sky_is_blue_and_scaled_by_the_irradiance_ratio(valletta):
    # The Moon is the atmosphere's second light: with the Sun far below the horizon (26 deg:
    # beyond the tables' cut-off, so it adds exactly nothing) the sky is the sunlit sky of a
    # Sun where the Moon is, scaled by E_moon / E_sun, coloured by the Moon's redder
    # spectrum. Measured where the disks are not: the zenith and a ring 30-60 deg from the Moon.
    state = valletta.state
    moon = state.moon
    assert state.sun.elevation_deg < -25
    sunlit = Sky(sun_elevation_deg=moon.elevation_deg, sun_azimuth_deg=moon.azimuth_deg)
    directions = []
    for off in (30.0, 45.0, 60.0):
        for az in (-60.0, 0.0, 60.0, 180.0):
            directions.append(
                direction_from_angles(min(moon.elevation_deg + off, 89.0), moon.azimuth_deg + az)
            )
    directions.append([0.0, 0.0, 1.0])
    cam = DirectionsCamera(np.array(directions))
    night = valletta.render(cam, 0, 0, exposure=None).data[0]
    day = sunlit.render(cam, 0, 0, exposure=None).data[0]
    lum = np.array([0.2126, 0.7152, 0.0722])
    ratio = (night[:, :3] @ lum) / (day[:, :3] @ lum)
    expected = moon.illuminance_lux / sunlit.state.sun.illuminance_lux
    # 5 %: the bound; the Moon's colour moves luminance between channels by ~1 %,
    # and the tables' Sun is the ASTM spectrum (133 177 lx), 0.12 % below the astronomy's.
    np.testing.assert_allclose(ratio, expected, rtol=0.05)
    zenith = night[-1]
    assert zenith[2] > 1.2 * zenith[0]  # blue: B well above R in linear sRGB


def test_frames_with_the_sun_and_the_moon_up_show_both():
    # 2018-03-09 06:00 UTC at Valletta: a waning Moon 33 deg up, the Sun 7 deg up.
    sky = Sky(VALLETTA, "2018-03-09T06:00Z")
    assert sky.state.sun.elevation_deg > 0 and sky.state.moon.elevation_deg > 0
    for look in ("sun", "moon"):
        lum = sky.render(sky.camera(look, fov_deg=2.0), 64, 64, exposure=None).luminance
        # The disk stands out of its sky (a daytime quarter Moon ~3000 cd/m^2 against a
        # morning sky of ~1200: the contrast is lower than the Sun's).
        assert lum.max() > 1.4 * np.median(lum)


def test_a_day_at_one_minute_steps_is_finite_and_never_jumps():
    # 24 h at 1-minute steps (1441 instants), zenith and horizon luminances: all finite, and
    # no step much larger than its neighbours' (a jump, e.g. a light switched at the tables'
    # cut-off or a table not re-aimed, would be a step many times the local rate of change;
    # the physics changes smoothly: the largest second difference of ln L is bounded by
    # the first differences around it).
    air = AtmosphereLayer("earth", sky_view_size=(64, 64))
    sky = Sky(VALLETTA, "2018-03-01T00:00Z", layers=[SunLayer(), MoonLayer(), air])
    states = state_series(sky.observer, 2458178.5 + np.arange(1441) / 1440.0)
    cam = DirectionsCamera(np.array([[0.0, 0.0, 1.0], direction_from_angles(5.0, 180.0)]))
    lum = np.empty((len(states), 2))
    for i, state in enumerate(states):
        frame = sky.graph.render(state, cam, 0, 0, altitude_m=57.7)
        assert np.isfinite(frame.data).all()
        lum[i] = frame.luminance[0]
    assert (lum > 0).all()
    step = np.diff(np.log(lum), axis=0)
    # Each step against the larger of the two steps beside it, plus 0.02 (2 % of light):
    # at the terminator of the night the sky changes by up to ~10 % a minute, smoothly.
    local = np.maximum(np.abs(step[:-2]), np.abs(step[2:]))
    assert (np.abs(step[1:-1]) <= 2.0 * local + 0.02).all(), np.abs(step).max()


def test_disk_scissor_holds_the_disk():
    d = direction_from_angles(10.0, 100.0)
    r = math.radians(0.3)
    for cam in (
        PerspectiveCamera(fov_deg=60, yaw_deg=100, pitch_deg=5),
        FisheyeCamera(),
        EquirectCamera(),
    ):
        rects = disk_scissor(cam, 400, 200, d, r)
        assert rects and all(w > 0 and h > 0 for _, _, w, h in rects)
    # Behind a perspective camera: nothing to draw; an equirect's seam: two rectangles.
    assert disk_scissor(PerspectiveCamera(yaw_deg=280), 400, 200, d, r) == []
    assert len(disk_scissor(EquirectCamera(), 400, 200, direction_from_angles(0.0, 0.1), r)) == 2


def test_disk_scissor_beside_a_perspective_camera_draws_nothing():
    """A disk 90 deg off the view straddles the eye's plane (some of its rim in front, some
    behind): outside the frustum's side plane it is out of the frame, not 'draw everywhere'
    (a full-screen pass of n x n points a pixel, 24 ms a frame in a time-lapse). Just inside
    the margin the rectangle stays, and its pixels are what the projection gives."""
    cam = PerspectiveCamera(fov_deg=90, yaw_deg=180, pitch_deg=0)  # looking south
    r = math.radians(0.3)
    assert disk_scissor(cam, 640, 360, direction_from_angles(15.0, 90.0), r) == []  # east
    assert disk_scissor(cam, 640, 360, direction_from_angles(-10.0, 270.0), r) == []  # west
    # Above the frame's top edge (half-height 29.4 deg at 640x360, 90 deg wide): out.
    assert disk_scissor(cam, 640, 360, direction_from_angles(31.0, 180.0), r) == []
    # Its centre 1 pixel beyond the right edge (at 45 deg, 0.14 deg a pixel): the rim is in
    # the 2-pixel margin, so a rectangle against the edge.
    right = direction_from_angles(0.0, 180.0 + 45.0 + 0.14)
    ((x, _, w, _),) = disk_scissor(cam, 640, 360, right, r)
    assert x + w == 640 and w >= 1
    # A disk wholly in view: its rectangle's width is the disk's 2r projected plus margins.
    ((x, y, w, h),) = disk_scissor(cam, 640, 360, direction_from_angles(0.0, 180.0), r)
    span = 2.0 * math.tan(r) / (2.0 * math.tan(math.radians(45.0))) * 640
    assert span + 2 <= w <= span + 6 and span + 2 <= h <= span + 6


def test_abstract_and_place_arguments_are_checked():
    with pytest.raises(ParameterError, match="a time needs a place"):
        Sky(time="2018-03-01T19:00Z")
    with pytest.raises(ParameterError, match="drop sun_elevation_deg"):
        Sky(VALLETTA, "2018-03-01T19:00Z", sun_elevation_deg=5)
    with pytest.raises(ParameterError, match="needs a time"):
        Sky(VALLETTA)
    with pytest.raises(ParameterError, match="unknown place 'Atlantis'"):
        Sky("Atlantis", "2018-03-01T19:00Z")
    with pytest.raises(ParameterError, match="look"):
        Sky(sun_elevation_deg=5).camera("up")


def test_place_names_and_tuples_give_the_same_sky():
    by_name = Sky("Valletta", "2018-03-01T19:00Z")
    by_tuple = Sky(VALLETTA, "2018-03-01T19:00Z")
    assert by_name.state.moon.elevation_deg == pytest.approx(
        by_tuple.state.moon.elevation_deg, abs=1e-6
    )


def test_repr_png_is_an_image(abstract_sky):
    png = abstract_sky._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 1000


def test_tonemapped_image_needs_an_exposure(abstract_sky):
    with pytest.raises(ParameterError, match="needs an exposure"):
        abstract_sky.render(width=8, height=8, exposure=None, tonemap="filmic")
    # glare off: the tone map alone (the default glare spreads the Sun's light on the image)
    frame = abstract_sky.render(width=8, height=8, exposure=12.0, tonemap="filmic", glare="off")
    np.testing.assert_array_equal(frame.image, gpu_tonemap(frame, "filmic", 2.0**-12 / 1.2))


def test_disks_are_seen_through_the_air_of_their_own_pixels():
    # The composite: a disk pixel's light through the air is the disk's own light times the
    # transmittance of that pixel's ray, per channel with solar-spectrum weights. Against the
    # float64 column densities of skydome.reference.single at each pixel's direction, for a
    # Sun 2 deg up (the limbs differ by ~10 %): within 1 % (the 1024-texel table of the view
    # cosine, float32 transmittance tables and the 16 wavelengths' interpolation).
    from skydome.atmosphere.precomputed import behind_transmittance_weights
    from skydome.reference import single as ref

    sky = Sky(sun_elevation_deg=2.0, sun_azimuth_deg=250.0)
    cam = PerspectiveCamera(fov_deg=1.2, yaw_deg=250.0, pitch_deg=2.0)
    w = h = 48
    full = sky.render(cam, w, h, exposure=None).data.astype(np.float64)
    sky.layer("sun").enabled = False
    air_only = sky.render(cam, w, h, exposure=None).data.astype(np.float64)
    sky.layer("sun").enabled = True
    sky.layer("atmosphere").enabled = False
    disk = sky.render(cam, w, h, exposure=None).data.astype(np.float64)
    sky.layer("atmosphere").enabled = True
    inside = disk[..., 1] > 0.5 * disk[..., 1].max()
    measured = (full - air_only)[inside] / disk[inside]  # (N, 4)
    # Each pixel's direction, the float64 columns and the per-channel weights.
    from skydome.reference.disks import perspective_pixel_directions

    dirs = perspective_pixel_directions(cam, w, h)[inside]
    air = sky.layer("atmosphere")
    params = air.params
    r = params.bottom_radius_m + 1.7
    columns = ref.column_to_top(params, np.full(len(dirs), r), dirs[:, 2])  # (N, 3) m
    basis = air.spectral_basis
    c = params.coefficients(basis.wavelengths_nm)
    tau = (
        c["rayleigh_scattering"] * columns[:, :1]
        + c["mie_extinction"] * columns[:, 1:2]
        + c["absorption_extinction"] * columns[:, 2:3]
    )
    expected = np.exp(-tau) @ behind_transmittance_weights(basis.to_output).T
    np.testing.assert_allclose(measured, expected, rtol=0.01)
    assert expected[:, 1].max() > 1.05 * expected[:, 1].min()  # the limbs do differ


@dataclass(frozen=True)
class GlowInputs(ShaderInputs):
    """The test glow's radiance (cd/m^2 per channel)."""

    u_glow: tuple[float, float, float, float]


class GlowLayer(Layer):
    """A plug-in space layer written outside the package: a uniform radiance from beyond the
    atmosphere (like a night-sky glow), in its own GLSL, touching no other layer."""

    name = "glow"
    stage = "space"
    SOURCE = (
        '#include "common/camera.glsl"\n'
        "uniform vec4 u_glow;\nout vec4 frag;\n"
        "void main() { vec3 d; frag = camera_ray(gl_FragCoord.xy, d) ? u_glow : vec4(0.0); }\n"
    )

    def __init__(self, radiance):
        super().__init__()
        self.radiance = tuple(float(v) for v in radiance)
        self._glow_pass = None

    def draw(self, frame):
        from skydome.core.cameras import CameraInputs
        from skydome.gpu import FullscreenPass

        if self._glow_pass is None:
            defines = {"CAMERA_MODEL": frame.camera.model}
            self._glow_pass = FullscreenPass(
                frame.ctx, "glow.glsl", defines, inputs=(CameraInputs, GlowInputs),
                source=self.SOURCE,
            )  # fmt: skip
        self._glow_pass.draw(frame.fbo, frame.view, GlowInputs(self.radiance))

    def release(self):
        super().release()
        if self._glow_pass is not None:
            self._glow_pass.release()


def test_a_new_layer_plugs_in_without_editing_the_others():
    # The frame graph composites a space layer it has never seen: its light reaches the
    # camera times each ray's transmittance (zero where the ground is), added to the sky.
    glow = GlowLayer((1e-3, 1e-3, 1e-3, 2e-3))
    plain = Sky(sun_elevation_deg=-30.0)  # the Sun far down: the sky adds nothing
    glowing = Sky(sun_elevation_deg=-30.0, extra_layers=[glow])
    up = [direction_from_angles(e, 90.0) for e in (90.0, 30.0, 5.0, -5.0)]
    cam = DirectionsCamera(np.array(up))
    added = (
        glowing.render(cam, 0, 0, exposure=None).data[0]
        - plain.render(cam, 0, 0, exposure=None).data[0]
    )
    t_zenith = added[0, 1] / 1e-3
    # The zenith transmittance of the measured Earth in green, ~0.75-0.9 (Rayleigh 0.097,
    # aerosol 0.1, ozone); lower towards the horizon; nothing through the ground.
    assert 0.7 < t_zenith < 0.95
    assert added[0, 1] > added[1, 1] > added[2, 1] > 0
    assert np.all(added[3] == 0)
    glowing.layer("glow").enabled = False
    off = (
        glowing.render(cam, 0, 0, exposure=None).data[0]
        - plain.render(cam, 0, 0, exposure=None).data[0]
    )
    np.testing.assert_allclose(off, 0.0, atol=1e-9)


def test_lights_below_the_dark_bound_add_exactly_nothing(valletta):
    # AtmosphereLayer.dark_below_deg: below it a light is left out and its table not re-aimed.
    # That is exact only if the tables give nothing there: a precomputed frame (which has no
    # such shortcut) of a Sun just below the bound is black at the ground and at 10 km.
    air = valletta.layer("atmosphere")
    renderer = precomputed_renderer()
    for altitude in (1.7, 10_000.0):
        dark = air.sky.dark_below_deg(altitude)
        assert -40.0 < dark < -20.0  # the cut-off (-23 deg) less the verticals' tilt
        sun = direction_from_angles(dark - 0.01, 180.0)
        frame = renderer.render(EquirectCamera(), 128, 64, sun_direction=sun, altitude_m=altitude)
        assert np.all(frame.data == 0.0)


def test_state_at_keeps_the_time_it_is_given():
    # A Time made with a TT - UT1 of its own (here 100 s more than the model's) must be the
    # time the state is for: the Moon moves ~0.55"/s against the stars, so 100 s moves it by
    # ~55" (measured 0.015 deg); state_at once re-read the tables from the UTC alone.
    obs = observer_for(VALLETTA)
    model = to_time("2018-03-01T23:00Z")
    dt_s = float((model.jd_tt - model.jd_ut1) * 86400.0) + 100.0
    shifted = to_time("2018-03-01T23:00Z", delta_t=dt_s)
    a = state_at(obs, shifted).moon.direction
    b = state_series(obs, to_time(["2018-03-01T23:00Z"], delta_t=dt_s))[0].moon.direction
    c = state_at(obs, model).moon.direction
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
    moved_deg = math.degrees(math.acos(min(1.0, float(np.dot(a, c)))))
    assert 0.005 < moved_deg < 0.03
