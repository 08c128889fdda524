"""Renderer life cycle: shared tables, reuse by get_renderer, GL objects released with the
renderer, GL state restored after a failed draw, frames drawn in tiles."""

from __future__ import annotations

import gc

import numpy as np
import pytest
from skydome.render.api import clear_renderers

from skydome.atmosphere import preset
from skydome.core.cameras import (
    DirectionsCamera,
    EquirectCamera,
    PerspectiveCamera,
    direction_from_angles,
    get_renderer,
)
from skydome.core.cameras import base as render_base
from skydome.errors import ParameterError
from tests.air_frames import precomputed_frames as precomputed_renderer
from tests.air_frames import single_renderer

SUN = direction_from_angles(20.0, 135.0)


def released(gl_object) -> bool:
    return type(gl_object.mglo).__name__ == "InvalidObject"


def test_precomputed_renderers_share_one_set_of_tables():
    from skydome.atmosphere.precomputed import PrecomputedRenderer

    a = precomputed_renderer()
    b = PrecomputedRenderer(preset("earth"), a.config, sky_view=False)
    assert b.tables is a.tables and b.loaded_from_cache
    b.release()
    # Releasing one renderer leaves the shared tables to the other.
    assert not released(a.tables.scattering)
    a.render(PerspectiveCamera(), 32, 16, sun_direction=SUN)


def test_dropped_renderer_releases_its_gl_objects():
    from skydome.atmosphere.precomputed import PrecomputedRenderer

    # A configuration no other test uses, so these tables are this renderer's alone.
    r = PrecomputedRenderer(preset("earth").with_(mie_g=0.75))
    r.render(PerspectiveCamera(), 32, 16, sun_direction=SUN)
    table, view = r.tables.scattering, next(iter(r._passes.values())).program
    sky_view = r.sky_view.textures("sun", 0, (0, 0, 1), {}, {})["u_sun_scattering"]
    assert not released(table) and not released(view) and not released(sky_view)
    del r
    gc.collect()
    assert released(table) and released(view) and released(sky_view)


def test_get_renderer_keys_on_what_changes_the_renderer():
    clear_renderers()
    a = get_renderer("precomputed", "earth", samples=16, jitter=True)
    # The precomputed model has no ray-march samples or jitter: the same renderer.
    assert get_renderer("precomputed", "earth", samples=64, jitter=False) is a
    s16 = get_renderer("single", "earth", samples=16)
    assert get_renderer("single", "earth", samples=32) is not s16
    # Only the two most recently used are kept: `a` is gone from the cache, not destroyed
    # while held here.
    assert get_renderer("precomputed", "earth") is not a
    assert not released(a.tables.scattering)
    clear_renderers()


def test_progress_is_an_argument(tmp_path, monkeypatch):
    monkeypatch.setenv("SKYDOME_CACHE", str(tmp_path))
    clear_renderers()
    stages = []
    get_renderer(
        "precomputed",
        preset("earth").with_(mie_g=0.71),
        spectral="fast",
        orders=2,
        progress=lambda stage, fraction: stages.append((stage, fraction)),
    )
    clear_renderers()
    assert stages and stages[-1] == ("done", 1.0)
    assert all(0.0 <= f <= 1.0 for _, f in stages)


def test_gl_state_is_restored_after_a_failed_draw(monkeypatch):
    # The precomputed frame draws its surface pass with additive blending behind a depth test.
    # If that pass raises, the shared context must come back to GL's defaults: a later pass
    # that does not set them (the single-scattering one) must draw exactly as before.
    single = single_renderer()
    cam = PerspectiveCamera(fov_deg=60, yaw_deg=135, pitch_deg=10)
    before = single.render(cam, 64, 32, sun_direction=SUN).data
    r = precomputed_renderer()
    r.render(cam, 64, 32, sun_direction=SUN)  # sky-view tables drawn: two passes per frame now

    def fail(*args, **kwargs):
        raise RuntimeError("mid-draw failure")

    real = render_base.FullscreenPass.draw
    calls = []

    def second_fails(self, *args, **kwargs):
        calls.append(self)
        if len(calls) == 2:  # the surface pass, after blending and the depth test are on
            fail()
        return real(self, *args, **kwargs)

    monkeypatch.setattr(render_base.FullscreenPass, "draw", second_fails)
    with pytest.raises(RuntimeError, match="mid-draw"):
        r.render(cam, 64, 32, sun_direction=SUN)
    monkeypatch.undo()
    for _ in range(2):  # with blending left on, the second draw would add to the first
        after = single.render(cam, 64, 32, sun_direction=SUN).data
        np.testing.assert_array_equal(after, before)


def test_frames_report_the_altitude_used():
    f = precomputed_renderer().render(PerspectiveCamera(), 16, 8, sun_direction=SUN, altitude_m=0)
    assert f.info["altitude_m"] == render_base.MIN_ALTITUDE_M
    assert f.info["altitude_requested_m"] == 0.0
    g = precomputed_renderer().render(PerspectiveCamera(), 16, 8, sun_direction=SUN, altitude_m=5)
    assert g.info["altitude_m"] == 5.0 and "altitude_requested_m" not in g.info


@pytest.mark.parametrize(
    "make",
    [
        lambda: precomputed_renderer(),
        lambda: precomputed_renderer(sky_view=False),
        lambda: single_renderer(jitter=True),
    ],
    ids=["sky-view", "per-pixel", "single-jittered"],
)
def test_tiled_frames_equal_whole_frames(monkeypatch, make):
    # Tiles see the whole frame through u_resolution and their place through u_tile_offset:
    # the same pixel centres, so the same values (the jitter pattern repeats every 4 pixels,
    # and tiles are multiples of 4 wide).
    r = make()
    cam = EquirectCamera()
    whole = r.render(cam, 200, 100, sun_direction=SUN).data
    monkeypatch.setattr(render_base, "TILE_SIZE", 64)
    tiled = r.render(cam, 200, 100, sun_direction=SUN).data
    np.testing.assert_allclose(tiled, whole, rtol=1e-6, atol=1e-9)


def test_tiled_inputs_and_directions(monkeypatch):
    # Per-pixel inputs (a depth image, a direction map) are cut into the same tiles.
    r = precomputed_renderer()
    rng = np.random.default_rng(3)
    d = rng.normal(size=(70, 90, 3))
    d[..., 2] = np.abs(d[..., 2]) * 0.3
    cam = DirectionsCamera(directions=d)
    depth = rng.uniform(100.0, 30_000.0, size=(70, 90))
    depth[::7] = np.inf  # +inf: no scene along those rays
    whole = r.render(cam, 0, 0, sun_direction=SUN, depth_m=depth)
    monkeypatch.setattr(render_base, "TILE_SIZE", 32)
    tiled = r.render(cam, 0, 0, sun_direction=SUN, depth_m=depth)
    np.testing.assert_allclose(tiled.data, whole.data, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(
        tiled.info["transmittance"], whole.info["transmittance"], rtol=1e-6, atol=1e-9
    )
    # Rays with no scene see the open sky: the same as a frame without a depth image.
    sky = r.render(cam, 0, 0, sun_direction=SUN).data
    np.testing.assert_allclose(whole.data[::7], sky[::7], rtol=1e-5, atol=1e-9)
    np.testing.assert_allclose(whole.info["transmittance"][::7], 0.0, atol=1e-6)


def test_a_frame_as_wide_as_the_largest_size():
    # 16384 pixels, eight tiles: GL memory stays at one tile's targets whatever the frame.
    f = precomputed_renderer().render(EquirectCamera(), 16_384, 8, sun_direction=SUN)
    assert f.data.shape == (8, 16_384, 4)
    assert np.all(np.isfinite(f.data)) and f.luminance.min() > 0
    # Azimuth runs across the whole width: the brightest column is towards the Sun (135°).
    brightest = np.argmax(f.luminance[3]) / 16_384 * 360.0
    assert brightest == pytest.approx(135.0, abs=2.0)


def test_depth_image_errors_name_the_problem():
    r = precomputed_renderer()
    with pytest.raises(ParameterError, match=r"depth_m must be a \(8, 16\) array.*got \(16, 8\)"):
        r.render(PerspectiveCamera(), 16, 8, sun_direction=SUN, depth_m=np.ones((16, 8)))
    with pytest.raises(ParameterError, match="NaN"):
        r.render(PerspectiveCamera(), 16, 8, sun_direction=SUN, depth_m=np.full((8, 16), np.nan))
