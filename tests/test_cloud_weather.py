"""Weather maps: generation (coverage, tiling, determinism), image and array input with their
errors, and the animation (wind shift, flow map against a NumPy twin, evolution, caching)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from PIL import Image

from skydome.clouds.weather import AnimatedWeather, WeatherMap
from skydome.errors import ParameterError

SIZE = 128  # texels per side: small for llvmpipe on 2 cores


#: The animated map is stored in 8 bits: half a step of rounding.
HALF_STEP = 0.5 / 255


@pytest.fixture(scope="module")
def cumulus():
    return WeatherMap.generate(5, size=SIZE, coverage=0.4, precipitation=0.5, cirrus=0.2)


@pytest.mark.parametrize("coverage", [0.05, 0.4, 0.9])
def test_generated_coverage_tracks_the_request(coverage):
    """The soft threshold is found by bisection to 2^-60 of its range; the float32 channel
    then averages to the request within float32 rounding (1e-5)."""
    m = WeatherMap.generate(2, size=SIZE, coverage=coverage)
    assert float(m.coverage.mean()) == pytest.approx(coverage, abs=1e-5)
    # A cloud field, not a uniform grey: thick and thin (or clear) texels both occur.
    assert m.coverage.std() > 0.1 and m.coverage.max() - m.coverage.min() > 0.5


def test_coverage_zero_and_one():
    clear = WeatherMap.generate(3, size=SIZE, coverage=0.0, precipitation=1.0)
    assert not clear.coverage.any() and not clear.precipitation.any()
    overcast = WeatherMap.generate(3, size=SIZE, coverage=1.0)
    assert (overcast.coverage == 1).all()


def test_generated_channels(cumulus):
    d = cumulus.data
    assert d.shape == (SIZE, SIZE, 4) and d.dtype == np.float32
    assert np.isfinite(d).all() and d.min() >= 0 and d.max() <= 1
    np.testing.assert_allclose(cumulus.cloud_type, 2 / 3, rtol=1e-6)
    np.testing.assert_allclose(cumulus.precipitation, 0.5 * cumulus.coverage, atol=1e-7)
    assert float(cumulus.cirrus.mean()) == pytest.approx(0.2, abs=1e-5)


def test_generated_map_tiles_seamlessly(cumulus):
    """The step across each edge is like the steps between neighbouring rows or columns
    inside: its mean lies within the range of theirs, its maximum does not exceed theirs."""
    for channel in (0, 3):
        t = cumulus.data[..., channel]
        for axis in (0, 1):
            inside = np.abs(np.diff(t, axis=axis))
            across = np.abs(np.take(t, 0, axis=axis) - np.take(t, -1, axis=axis))
            lines = inside.mean(axis=1 - axis)
            assert lines.min() <= across.mean() <= lines.max()
            assert across.max() <= inside.max()


def test_generation_is_deterministic(cumulus):
    again = WeatherMap.generate(5, size=SIZE, coverage=0.4, precipitation=0.5, cirrus=0.2)
    assert np.array_equal(again.data, cumulus.data)
    other = WeatherMap.generate(6, size=SIZE, coverage=0.4, precipitation=0.5, cirrus=0.2)
    assert np.mean(np.abs(other.coverage - cumulus.coverage)) > 0.1


def test_from_array_fills_missing_channels():
    cov = np.linspace(0, 1, 12).reshape(3, 4)
    m = WeatherMap.from_array(cov, 10.0)
    assert m.data.shape == (3, 4, 4) and m.tile_km == 10.0
    np.testing.assert_allclose(m.coverage, cov, rtol=1e-7)
    np.testing.assert_allclose(m.cloud_type, 2 / 3, rtol=1e-7)
    assert not m.precipitation.any() and not m.cirrus.any()
    full = np.random.default_rng(0).random((5, 6, 4))
    np.testing.assert_allclose(WeatherMap.from_array(full, 1.0).data, full, rtol=1e-7)
    two = WeatherMap.from_array(full[..., :2], 1.0)
    np.testing.assert_allclose(two.cloud_type, full[..., 1], rtol=1e-7)


@pytest.mark.parametrize(
    "array, tile_km, word",
    [
        (np.full((4, 4), np.nan), 1.0, "NaN"),
        (np.full((4, 4), 1.5), 1.0, r"\[0, 1\]"),
        (np.full((4, 4), -0.1), 1.0, r"\[0, 1\]"),
        (np.zeros((4, 4, 5)), 1.0, "shape"),
        (np.zeros(16), 1.0, "shape"),
        (np.zeros((1, 4)), 1.0, "shape"),
        (np.zeros((4, 4)), 0.0, "tile_km"),
        (np.zeros((4, 4)), -3.0, "tile_km"),
        (np.zeros((4, 4)), float("nan"), "tile_km"),
        ([["a", "b"], ["c", "d"]], 1.0, "numeric"),
    ],
)
def test_from_array_errors(array, tile_km, word):
    with pytest.raises(ParameterError, match=word) as info:
        WeatherMap.from_array(array, tile_km)
    assert "\n" not in str(info.value)


def test_from_image_orientation_and_formats(tmp_path):
    """The first image row is the north edge: it becomes the last row of the map."""
    rgba = np.zeros((4, 6, 4), np.uint8)
    rgba[0, :, 0] = 255  # north row: overcast
    rgba[..., 1] = 85  # stratocumulus, 1/3
    rgba[..., 3] = 51  # cirrus 0.2
    Image.fromarray(rgba, "RGBA").save(tmp_path / "w.png")
    m = WeatherMap.from_image(tmp_path / "w.png", 25.0)
    assert m.size == (6, 4) and m.tile_km == 25.0
    assert (m.coverage[-1] == 1).all() and not m.coverage[:-1].any()
    np.testing.assert_allclose(m.cloud_type, 1 / 3, atol=1e-6)
    np.testing.assert_allclose(m.cirrus, 0.2, atol=1e-6)
    grey = np.array([[0, 255], [128, 64]], np.uint8)
    Image.fromarray(grey, "L").save(tmp_path / "g.jpg", quality=100)
    g = WeatherMap.from_image(tmp_path / "g.jpg", 1.0)
    np.testing.assert_allclose(g.coverage, grey[::-1] / 255, atol=0.03)  # JPEG loss
    np.testing.assert_allclose(g.cloud_type, 2 / 3, rtol=1e-6)
    Image.fromarray(np.array([[0, 65535], [32768, 0]], np.uint16)).save(tmp_path / "h.png")
    np.testing.assert_allclose(
        WeatherMap.from_image(tmp_path / "h.png", 1.0).coverage, [[32768 / 65535, 0], [0, 1]]
    )
    Image.fromarray(np.array([[0.25, 0.5], [0.75, 1.0]], np.float32), "F").save(tmp_path / "f.tif")
    np.testing.assert_allclose(
        WeatherMap.from_image(tmp_path / "f.tif", 1.0).coverage, [[0.75, 1.0], [0.25, 0.5]]
    )


def test_from_image_errors(tmp_path):
    with pytest.raises(ParameterError, match="not found"):
        WeatherMap.from_image(tmp_path / "missing.png", 1.0)
    (tmp_path / "junk.png").write_bytes(b"not an image at all")
    with pytest.raises(ParameterError, match="cannot read") as info:
        WeatherMap.from_image(tmp_path / "junk.png", 1.0)
    assert "\n" not in str(info.value)
    Image.fromarray(np.array([[2.0, 0.0], [0.0, 0.0]], np.float32), "F").save(tmp_path / "b.tif")
    with pytest.raises(ParameterError, match=r"\[0, 1\]"):
        WeatherMap.from_image(tmp_path / "b.tif", 1.0)
    Image.fromarray(np.zeros((2, 2), np.uint8)).save(tmp_path / "ok.png")
    with pytest.raises(ParameterError, match="tile_km"):
        WeatherMap.from_image(tmp_path / "ok.png", 0)


@pytest.mark.parametrize(
    "kwargs, word",
    [
        ({"coverage": 1.2}, "coverage"),
        ({"cirrus": -0.1}, "cirrus"),
        ({"precipitation": float("nan")}, "precipitation"),
        ({"cloud_type": 2}, "cloud_type"),
        ({"tile_km": 0}, "tile_km"),
        ({"size": 4}, "size"),
        ({"seed": -2}, "seed"),
    ],
)
def test_generate_errors(kwargs, word):
    with pytest.raises(ParameterError, match=word):
        WeatherMap.generate(**{"seed": 1, "size": 16, **kwargs})


def test_time_zero_equals_the_map(ctx, cumulus):
    """At t = 0 the flow map's live phase has no displacement and the evolution no change:
    the texture is the map itself, with flow and evolution on."""
    anim = AnimatedWeather(ctx, cumulus, wind_m_s=(7, 3), flow_m_s=5.0, evolution_s=600)
    np.testing.assert_allclose(anim.array_at(0.0), cumulus.data, atol=HALF_STEP + 1e-6)
    anim.release()


def test_wind_moves_the_map_by_wind_times_t(ctx, cumulus):
    """An 8 km tile of 128 texels (62.5 m); wind (12.5, -6.25) m/s for 20 s moves the map by
    (250, -125) m = (+4, -2) texels: the texture is the map rolled by that, to the float32
    precision of the texture coordinate (a 1e-7 tile error is 1e-5 of a texel)."""
    m = WeatherMap(cumulus.data, 8.0)
    anim = AnimatedWeather(ctx, m, wind_m_s=(12.5, -6.25), flow_m_s=0.0, evolution_s=None)
    got = anim.array_at(20.0)
    want = np.roll(m.data, shift=(-2, 4), axis=(0, 1))  # rows are north, columns east
    np.testing.assert_allclose(got, want, atol=HALF_STEP + 1e-4)
    # A long time-lapse: 10 days later (plus 20 s) the same shift, the offset wraps in float64.
    period = 8000.0 / 6.25 * 10 * 16  # a whole number of tiles in both directions
    np.testing.assert_allclose(anim.array_at(period + 20.0), want, atol=HALF_STEP + 1e-4)
    anim.release()


def test_flow_map_against_a_numpy_twin(ctx):
    """A map with coverage 0.5 + 0.5 sin(2 pi x) (x east, tile units), advected by the curl
    flow: each output texel blends the map at x - v_x * reach * (phase_k - 1/2), k = 0, 1,
    with weights 1 - |2 phase_k - 1|, v the flow texel there. Exact for the analytic map up
    to bilinear interpolation of the 128-texel sinusoid, (h^2 / 8) max|f''| = 1.5e-4, and the
    GPU's filter weights (8-bit sub-texel steps: slope pi * h / 256 = 1e-4); tolerance 1e-3."""
    n, tile_km, flow, period = 128, 32.0, 5.0, 3600.0
    x = (np.arange(n) + 0.5) / n
    cov = np.tile(0.5 + 0.5 * np.sin(2 * np.pi * x), (n, 1))
    m = WeatherMap.from_array(cov, tile_km)
    anim = AnimatedWeather(
        ctx, m, flow_m_s=flow, flow_period_s=period, evolution_s=None, flow_size=n, seed=3
    )
    reach = flow * period / (tile_km * 1000)
    vx = anim.flow_texels[..., 0].astype(np.float64)
    for t in (600.0, 900.0, 2500.0):
        phases = ((t / period + 0.5) % 1.0, (t / period) % 1.0)
        w0 = 1 - abs(2 * phases[0] - 1)
        want = sum(
            w * (0.5 + 0.5 * np.sin(2 * np.pi * (x[None, :] - vx * reach * (p - 0.5))))
            for w, p in zip((w0, 1 - w0), phases, strict=True)
        )
        got = anim.array_at(t)[..., 0]
        np.testing.assert_allclose(got, want, atol=HALF_STEP + 1e-3)
        # The flow did distort the map, far beyond the tolerance. (Not a net shift: the two
        # phases' weighted displacements cancel, w0 (p0 - 1/2) + w1 (p1 - 1/2) = 0; each
        # phase drifts along the flow and fades out before it restarts, as flow maps do.)
        assert np.abs(got - cov).max() > 0.05
    anim.release()


def test_evolution_and_purity(ctx, cumulus):
    anim = AnimatedWeather(ctx, cumulus, wind_m_s=(3, 1), flow_m_s=1.0, evolution_s=1800)
    late = anim.array_at(3600.0)
    assert np.isfinite(late).all() and late.min() >= 0 and late.max() <= 1
    # Against the same wind and flow without evolution: clouds grew and decayed, but the
    # sky neither cleared nor closed, and clear air stayed clear.
    still = AnimatedWeather(ctx, cumulus, wind_m_s=(3, 1), flow_m_s=1.0, evolution_s=None)
    base = still.array_at(3600.0)
    still.release()
    assert np.abs(late[..., 0] - base[..., 0]).mean() > 0.02
    assert (late[..., 0] > base[..., 0] + 0.05).mean() > 0.02  # some grew
    assert (late[..., 0] < base[..., 0] - 0.05).mean() > 0.02  # some decayed
    assert abs(late[..., 0].mean() - base[..., 0].mean()) < 0.15
    assert late[..., 0][base[..., 0] == 0].max() <= 2 * HALF_STEP  # (the 8-bit rounding)
    np.testing.assert_array_equal(late[..., 1], base[..., 1])  # the cloud type is carried
    # The same time: the same texture, no redraw; another time then back: bit-identical.
    tex, draws = anim.texture_at(3600.0), anim.draws
    assert anim.texture_at(3600.0) is tex and anim.draws == draws
    anim.array_at(120.0)
    assert np.array_equal(anim.array_at(3600.0), late)
    fresh = AnimatedWeather(ctx, cumulus, wind_m_s=(3, 1), flow_m_s=1.0, evolution_s=1800)
    assert np.array_equal(fresh.array_at(3600.0), late)  # never depends on earlier frames
    for a in (anim, fresh):
        a.release()


def test_clear_sky_stays_clear(ctx):
    clear = WeatherMap.from_array(np.zeros((32, 32)), 10.0)
    anim = AnimatedWeather(ctx, clear, wind_m_s=(10, 0), flow_m_s=3.0, evolution_s=100)
    assert not anim.array_at(5000.0)[..., 0].any()
    anim.release()


def test_animation_errors(ctx, cumulus):
    with pytest.raises(ParameterError, match="wind_m_s"):
        AnimatedWeather(ctx, cumulus, wind_m_s=(1, 2, 3))
    with pytest.raises(ParameterError, match="flow_m_s"):
        AnimatedWeather(ctx, cumulus, flow_m_s=-1)
    with pytest.raises(ParameterError, match="evolution_s"):
        AnimatedWeather(ctx, cumulus, evolution_s=0)
    with pytest.raises(ParameterError, match="WeatherMap"):
        AnimatedWeather(ctx, np.zeros((4, 4, 4)))
    anim = AnimatedWeather(ctx, cumulus, flow_m_s=0.0)
    with pytest.raises(ParameterError, match="time_s"):
        anim.texture_at(math.inf)
    anim.release()
