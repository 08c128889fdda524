"""Cloud noise textures: GLSL against the float64 twin, tiling, determinism, ranges, the curl's
divergence, published properties of gradient and cellular noise, and the caches."""

from __future__ import annotations

import math
from fractions import Fraction

import moderngl
import numpy as np
import pytest

from skydome.clouds import lattice_noise as ref
from skydome.clouds import noise as cn
from skydome.errors import ParameterError

N = 32  # small textures: llvmpipe on 2 cores


@pytest.fixture(scope="module")
def shape(ctx):
    return cn.render_shape(ctx, 7, N)


@pytest.fixture(scope="module")
def detail(ctx):
    return cn.render_detail(ctx, 7, N)


@pytest.fixture(scope="module")
def curl_raw(ctx):
    return cn.render_curl_raw(ctx, 7, 64)


def _texels(rng, n, count):
    idx = rng.integers(0, n, (count, 3))  # (i, j, k)
    return idx, (idx + 0.5) / n


def _twin_shape(u, seed):
    g = ref.worley_fbm(u, cn.SHAPE_WORLEY_PERIODS[0], seed, 16)
    b = ref.worley_fbm(u, cn.SHAPE_WORLEY_PERIODS[1], seed, 32)
    a = ref.worley_fbm(u, cn.SHAPE_WORLEY_PERIODS[2], seed, 48)
    perlin = ref.perlin_fbm(u, cn.SHAPE_PERLIN_PERIOD, cn.SHAPE_PERLIN_OCTAVES, seed, 0)
    p01 = np.clip(0.5 + cn.SHAPE_PERLIN_GAIN * perlin, 0.0, 1.0)
    return np.stack([g + p01 * (1 - g), g, b, a], axis=-1)


def _twin_potential(ij, n, seed):
    u = np.mod(np.asarray(ij, dtype=np.float64) / n, 1.0)
    u3 = np.concatenate([u, np.zeros(u.shape[:-1] + (1,))], axis=-1)
    return ref.perlin_fbm(u3, cn.CURL_PERIOD, cn.CURL_OCTAVES, seed, 112)


# Tolerance of the float32 shaders against the float64 twin: the hash is exact integer math
# (and the jitter exact 24-bit fractions), so only float32 rounding of O(50) operations on
# values of order 1 remains: ~50 ulps of 6e-8; 1e-5 leaves a margin of 3.
TOL_F32 = 1e-5


def test_shape_and_detail_match_the_twin(shape, detail):
    rng = np.random.default_rng(1)
    idx, u = _texels(rng, N, 300)
    got = shape[idx[:, 2], idx[:, 1], idx[:, 0]]
    np.testing.assert_allclose(got, _twin_shape(u, 7), atol=TOL_F32, rtol=0)
    r, g, b = (
        ref.worley_fbm(u, p, 7, s)
        for p, s in zip(cn.DETAIL_WORLEY_PERIODS, (64, 80, 96), strict=True)
    )
    want = np.stack([r, g, b, 0.625 * r + 0.25 * g + 0.125 * b], axis=-1)
    np.testing.assert_allclose(detail[idx[:, 2], idx[:, 1], idx[:, 0]], want, atol=TOL_F32)


def test_curl_matches_the_twin(curl_raw):
    n = curl_raw.shape[0]
    rng = np.random.default_rng(2)
    ij = rng.integers(0, n, (200, 2)) + 0.5  # (i, j) texel centres
    h = 1.0 / n
    dpsi_dx = (_twin_potential(ij + [1, 0], n, 7) - _twin_potential(ij - [1, 0], n, 7)) / (2 * h)
    dpsi_dy = (_twin_potential(ij + [0, 1], n, 7) - _twin_potential(ij - [0, 1], n, 7)) / (2 * h)
    got = curl_raw[ij[:, 1].astype(int), ij[:, 0].astype(int)]
    # A difference quotient divides the potential's float32 error (~1e-6) by 2h = 2/n.
    tol = 1e-6 * n
    np.testing.assert_allclose(got[:, 0], dpsi_dy, atol=tol, rtol=0)
    np.testing.assert_allclose(got[:, 1], -dpsi_dx, atol=tol, rtol=0)


def test_curl_is_divergence_free(curl_raw):
    """Central differences of a curl built from central differences of one potential cancel
    exactly (the difference operators commute): what remains is float32 rounding."""
    vx, vy = curl_raw[..., 0].astype(np.float64), curl_raw[..., 1].astype(np.float64)
    dvx_dx = (np.roll(vx, -1, axis=1) - np.roll(vx, 1, axis=1)) / 2  # per texel
    dvy_dy = (np.roll(vy, -1, axis=0) - np.roll(vy, 1, axis=0)) / 2
    div = dvx_dx + dvy_dy
    scale = np.sqrt(np.mean(dvx_dx**2))  # a typical single derivative term
    assert scale > 0.01 * np.abs(vx).max()  # the field does vary between texels
    assert np.abs(div).max() < 1e-4 * scale


def test_twin_curl_divergence_identity():
    """The same identity on the float64 twin, for the potential at arbitrary points."""
    rng = np.random.default_rng(3)
    ij = rng.random((500, 2)) * 64
    psi = {(a, b): _twin_potential(ij + [a, b], 64, 5) for a in (-2, 0, 2) for b in (-2, 0, 2)}

    def vx(a, b):  # d psi / dy at offset (a, b), central difference of step 1
        return (
            _twin_potential(ij + [a, b + 1], 64, 5) - _twin_potential(ij + [a, b - 1], 64, 5)
        ) / 2

    def vy(a, b):
        return (
            -(_twin_potential(ij + [a + 1, b], 64, 5) - _twin_potential(ij + [a - 1, b], 64, 5)) / 2
        )

    div = (vx(1, 0) - vx(-1, 0)) / 2 + (vy(0, 1) - vy(0, -1)) / 2
    assert psi and np.abs(div).max() < 1e-12


def _assert_wraps_like_inside(t, axes):
    """The step between the last and the first plane along each axis is no larger than the
    steps between neighbouring planes inside: its mean lies within the range of the interior
    planes' means (one plane's mean fluctuates: its texels are correlated), and its largest
    value does not exceed theirs. An untiled noise steps several times farther there."""
    for axis in axes:
        inside = np.abs(np.diff(t, axis=axis))
        across = np.abs(np.take(t, 0, axis=axis) - np.take(t, -1, axis=axis))
        other = tuple(a for a in range(t.ndim - 1) if a != axis)
        plane_means = inside.mean(axis=other)  # (planes - 1, channels)
        across_mean = across.mean(axis=tuple(range(across.ndim - 1)))
        assert (across_mean <= plane_means.max(axis=0)).all()
        assert (across_mean >= plane_means.min(axis=0)).all()
        assert (
            across.max(axis=tuple(range(across.ndim - 1))) <= inside.max(axis=other).max(0)
        ).all()


@pytest.mark.parametrize("which", ["shape", "detail"])
def test_volumes_tile_seamlessly(which, shape, detail):
    _assert_wraps_like_inside(shape if which == "shape" else detail, (0, 1, 2))


def test_curl_tiles_seamlessly(curl_raw):
    _assert_wraps_like_inside(curl_raw, (0, 1))


def test_twin_is_periodic():
    """A noise of period P repeats after P cells exactly (the lattice is wrapped)."""
    rng = np.random.default_rng(4)
    p = rng.random((1000, 3)) * 5
    for axis in range(3):
        shift = np.zeros(3)
        shift[axis] = 5
        salt = ref.noise_salt(3, 9)
        np.testing.assert_allclose(
            ref.perlin_noise(p + shift, 5, salt), ref.perlin_noise(p, 5, salt), atol=1e-12
        )
        np.testing.assert_allclose(
            ref.worley_f1(p + shift, 5, salt), ref.worley_f1(p, 5, salt), atol=1e-12
        )


def test_deterministic_and_seeded(ctx, shape):
    again = cn.render_shape(ctx, 7, N)
    assert np.array_equal(again, shape)  # bit-identical
    other = cn.render_shape(ctx, 8, N)
    assert np.mean(np.abs(other - shape)) > 0.03
    assert cn.render_curl(ctx, 8, 32).tobytes() != cn.render_curl(ctx, 7, 32).tobytes()


def test_ranges(shape, detail, ctx):
    for t in (shape, detail):
        assert np.isfinite(t).all() and t.min() >= 0.0 and t.max() <= 1.0
        assert t.std(axis=(0, 1, 2)).min() > 0.05  # not flat
    # Perlin-Worley has the Worley fBm as its floor.
    assert (shape[..., 0] >= shape[..., 1] - 1e-6).all()
    curl = cn.render_curl(ctx, 7, 64)
    assert np.isfinite(curl).all() and np.abs(curl).max() == pytest.approx(1.0, abs=1e-6)


def test_perlin_variance_matches_the_analytic_value():
    """Gradient noise n(x) = sum_c W_c(x) g_c.(x - c) with independent gradients of
    E[g g^T] = (2/3) I (Perlin 2002's 12 edge vectors) has, averaged over a cell,
    Var n = (2/3) * 8 * 3 * A * B^2, A = int x^2 (1-s)^2, B = int (1-s)^2 over [0, 1], s the
    quintic fade: 16 A B^2 = 0.072919 (exact fractions). 200 000 points over 64^3 cells:
    the variance's standard error is about 0.4 %; tolerance 2 %."""
    one_minus_s = np.polynomial.Polynomial([1, 0, 0, -10, 15, -6])
    sq = (one_minus_s**2).coef
    b = sum(Fraction(round(c)) / (k + 1) for k, c in enumerate(sq))
    a = sum(Fraction(round(c)) / (k + 3) for k, c in enumerate(sq))
    expected = float(16 * a * b * b)
    assert expected == pytest.approx(0.0729189, rel=1e-5)
    rng = np.random.default_rng(5)
    n = ref.perlin_noise(rng.random((200_000, 3)) * 64, 64, ref.noise_salt(1, 0))
    assert n.var() == pytest.approx(expected, rel=0.02)
    assert abs(n.mean()) < 0.005
    # Zero at every lattice point (the defining property of gradient noise).
    lattice = rng.integers(0, 64, (1000, 3)).astype(float)
    assert np.abs(ref.perlin_noise(lattice, 64, ref.noise_salt(1, 0))).max() < 1e-12


def test_worley_f1_small_distance_law():
    """For any stationary point process of unit intensity, P(F1 <= r) = (4/3) pi r^3 +
    O(r^6) (the expected number of points in a ball; Stoyan, Kendall & Mecke, Stochastic
    Geometry, the contact distribution). Jittered grid of one point per cell: unit
    intensity. r = 0.15: 5 600 of 400 000 samples expected, Poisson error 1.3 %, the r^6 term
    under 1 %; tolerance 6 %."""
    rng = np.random.default_rng(6)
    f1 = ref.worley_f1(rng.random((400_000, 3)) * 64, 64, ref.noise_salt(2, 0))
    r = 0.15
    assert np.mean(f1 <= r) == pytest.approx(4 / 3 * math.pi * r**3, rel=0.06)


def test_worley_f1_mean_against_an_independent_jittered_grid():
    """The mean F1 of the twin against a brute-force nearest-neighbour search over a periodic
    jittered grid drawn with NumPy's own generator (an independent implementation with the
    exact nearest point, not a 27-cell search). 20 grids x 4000 queries: standard error
    about 0.1 %; tolerance 1 %."""
    rng = np.random.default_rng(7)
    box = 6
    means = []
    for _ in range(20):
        cells = np.stack(np.meshgrid(*[np.arange(box)] * 3, indexing="ij"), -1).reshape(-1, 3)
        points = cells + rng.random(cells.shape)
        q = rng.random((4000, 3)) * box
        d = q[:, None, :] - points[None, :, :]
        d -= box * np.round(d / box)  # minimum image
        means.append(np.sqrt((d**2).sum(-1)).min(1).mean())
    independent = float(np.mean(means))
    f1 = ref.worley_f1(rng.random((100_000, 3)) * 64, 64, ref.noise_salt(3, 0))
    assert f1.mean() == pytest.approx(independent, rel=0.01)
    # Below the Poisson process's Gamma(4/3) (3 / 4 pi)^(1/3) = 0.554: a jittered grid is
    # more regular than a Poisson one of the same intensity.
    assert f1.mean() < math.gamma(4 / 3) * (3 / (4 * math.pi)) ** (1 / 3)


def test_default_textures_and_caches(ctx, monkeypatch):
    """The default set (128^3, 32^3, 128^2) is drawn once; a second request is served from
    memory; after forgetting the memory copy the disk cache supplies the texels and nothing
    is drawn."""
    cn._MEMORY.clear()
    noise = cn.cloud_noise(ctx, 11)
    assert not noise.from_cache
    assert noise.shape.size == (128, 128, 128) and noise.shape.components == 4
    assert noise.detail.size == (32, 32, 32) and noise.detail.components == 4
    assert noise.curl.size == (128, 128) and noise.curl.components == 2
    # the volumes in 8 bits (the noise lies in [0, 1]), the curl (in [-1, 1]) in float
    assert noise.shape.dtype == noise.detail.dtype == "f1" and noise.curl.dtype == "f4"
    for tex in (noise.shape, noise.detail, noise.curl):
        assert tex.repeat_x and tex.repeat_y
    # the volumes are sampled at level 0 only (a mipmapped filter costs a CPU rasterizer its
    # level selection at every fetch); the cirrus's curl field by its footprint
    assert noise.shape.filter == noise.detail.filter == (moderngl.LINEAR, moderngl.LINEAR)
    assert noise.curl.filter == (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    assert noise.shape.repeat_z and noise.detail.repeat_z
    assert cn.cloud_noise(ctx, 11) is noise
    texels = np.frombuffer(noise.shape.read(), np.uint8).reshape(128, 128, 128, 4)
    cn._MEMORY.clear()

    def no_draw(*args, **kwargs):
        raise AssertionError("drawn despite the disk cache")

    for name in ("render_shape", "render_detail", "render_curl"):
        monkeypatch.setattr(cn, name, no_draw)
    again = cn.cloud_noise(ctx, 11)
    assert again.from_cache and again is not noise
    assert np.array_equal(np.frombuffer(again.shape.read(), np.uint8).reshape(texels.shape), texels)
    again.release()
    assert cn._MEMORY.get(again._key) is None
    noise.release()


def test_bad_arguments(ctx):
    for kwargs, word in (
        ({"seed": -1}, "seed"),
        ({"seed": 2**31}, "seed"),
        ({"seed": 1.5}, "seed"),
        ({"shape_size": 100}, "power of two"),
        ({"detail_size": 2}, "detail_size"),
        ({"curl_size": 0}, "curl_size"),
    ):
        with pytest.raises(ParameterError, match=word):
            cn.cloud_noise(ctx, **{"seed": 1, **kwargs})
