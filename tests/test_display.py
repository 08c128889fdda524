"""Display: sRGB transfer, exposure, tone-mapping operators, and the GLSL pass against NumPy."""

from __future__ import annotations

import math
import zlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from skydome.display import (
    TONEMAPS,
    GpuToneMapper,
    auto_exposure,
    ev100_to_scale,
    exponential,
    filmic,
    gpu_tonemap,
    hvs,
    hvs_coefficients,
    hvs_curve,
    log_average_luminance,
    quantize8,
    reinhard,
    reinhard_luminance,
    scale_to_ev100,
    srgb_decode,
    srgb_encode,
    tonemap,
    upload_frame,
)
from skydome.errors import GLError, ParameterError
from skydome.spectra import SRGB_LUMINANCE

# ---------------------------------------------------------------------------------------------
# sRGB (IEC 61966-2-1)


def test_srgb_reference_points():
    assert srgb_encode(0.0) == 0.0
    assert srgb_encode(1.0) == pytest.approx(1.0, abs=1e-15)  # 1.055 - 0.055
    # 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357; the brief's reference is 0.7354 to 4 decimals.
    assert srgb_encode(0.5) == pytest.approx(0.7354, abs=1e-4)
    # Linear segment: 12.92 * L below the breakpoint.
    assert srgb_encode(0.001) == pytest.approx(0.01292, rel=1e-12)


def test_srgb_breakpoint_continuity():
    # The standard's rounded constants make the two pieces meet to within 3e-8 at 0.0031308
    # (12.92 * 0.0031308 = 0.04044994 vs 1.055 * 0.0031308^(1/2.4) - 0.055 = 0.04044991):
    # 1e-7 allows that and nothing else (a real discontinuity would be > 1e-4).
    b = 0.0031308
    below = srgb_encode(np.nextafter(b, 0.0))
    above = srgb_encode(np.nextafter(b, 1.0))
    assert abs(above - below) < 1e-7
    assert srgb_encode(b) == pytest.approx(0.04045, abs=1e-7)
    # 0.04045 / 12.92 = 0.00313080495: the rounded constants again, 5e-9 off.
    assert srgb_decode(0.04045) == pytest.approx(b, abs=1e-8)


def test_srgb_decode_is_inverse():
    x = np.linspace(0.0, 1.0, 10001)
    # float64 pow/round trip: errors of a few ulp; 1e-12 is ~1e4 ulp of margin.
    np.testing.assert_allclose(srgb_decode(srgb_encode(x)), x, rtol=0, atol=1e-12)
    np.testing.assert_allclose(srgb_encode(srgb_decode(x)), x, rtol=0, atol=1e-12)


def test_quantize8_rounds_half_up_and_clips():
    v = np.array([-1.0, 0.0, 0.4999 / 255, 0.5 / 255, 1.5 / 255, 254.5 / 255, 1.0, 7.0])
    np.testing.assert_array_equal(quantize8(v), [0, 0, 0, 1, 2, 255, 255, 255])
    assert quantize8(v).dtype == np.uint8


# ---------------------------------------------------------------------------------------------
# Exposure


def test_ev0_maps_1p2_cd_to_one_and_each_ev_halves():
    assert 1.2 * ev100_to_scale(0.0) == pytest.approx(1.0, rel=1e-15)
    for ev in range(-10, 20):
        # Powers of two: exact halving in binary floating point.
        assert ev100_to_scale(ev + 1) == ev100_to_scale(ev) / 2
        assert scale_to_ev100(ev100_to_scale(ev)) == pytest.approx(ev, abs=1e-12)
    # +1 EV of compensation doubles the scale, like a camera's exposure compensation.
    assert ev100_to_scale(14.0, compensation_ev=1.0) == 2 * ev100_to_scale(14.0)


def test_ev_range_is_checked():
    with pytest.raises(ParameterError, match="exposure"):
        ev100_to_scale(99.0)
    with pytest.raises(ParameterError):
        ev100_to_scale(float("nan"))


@settings(max_examples=60, deadline=None)
@given(
    lum=st.floats(1e-5, 2e9),
    key=st.floats(0.01, 1.0),
    rgb=st.tuples(*[st.floats(0.05, 1.0)] * 3),
)
def test_auto_exposure_maps_uniform_frame_to_key(lum, key, rgb):
    # Uniform frame of luminance `lum` (any colour): scale * lum == key. The only error is
    # float64 rounding of mean(log) and exp (a few ulp times |log L| < 25): rtol 1e-12.
    c = np.array(rgb) / (np.array(rgb) @ SRGB_LUMINANCE) * lum
    frame = np.empty((6, 7, 4), np.float64)
    frame[...] = [*c, 0.0]
    s = auto_exposure(frame, key=key)
    assert s * (c @ SRGB_LUMINANCE) == pytest.approx(key, rel=1e-12)


def test_auto_exposure_ignores_nan_and_can_exclude_the_sun():
    frame = np.full((40, 50, 4), 1000.0, np.float32)
    frame[0, :5, :3] = np.nan
    lum = float(frame[1, 1, :3].astype(np.float64) @ SRGB_LUMINANCE)
    assert auto_exposure(frame) * lum == pytest.approx(0.18, rel=1e-9)
    # The Sun: 4 pixels at 1.6e9 cd/m^2 (0.2 % of the frame) darken a log-average exposure by
    # a factor (1.6e6)^(0.002) = 1.03; clipping at the 99th percentile removes that exactly.
    frame[20:22, 20:22, :3] = 1.6e9
    assert auto_exposure(frame) * lum < 0.18 / 1.02
    assert auto_exposure(frame, clip_percentile=99.0) * lum == pytest.approx(0.18, rel=1e-9)


def test_auto_exposure_compensation_and_noon_ev():
    frame = np.full((8, 8, 3), 5000.0)  # a bright daylight sky, ~5000 cd/m^2
    lum = 5000.0 * SRGB_LUMINANCE.sum()
    s = auto_exposure(frame)
    assert auto_exposure(frame, compensation_ev=1.0) == pytest.approx(2 * s, rel=1e-15)
    # 5000 / (1.2 * 0.18) = 2^14.5: the "noon sky is EV 14-15" rule of thumb.
    assert scale_to_ev100(s) == pytest.approx(math.log2(lum / (1.2 * 0.18)), abs=1e-9)
    assert 14.0 < scale_to_ev100(s) < 15.0


def test_log_average_black_and_invalid_frames():
    assert log_average_luminance(np.zeros((4, 4, 4))) == pytest.approx(1e-6)  # floor = delta
    with pytest.raises(ParameterError, match="no finite"):
        auto_exposure(np.full((2, 2, 4), np.nan))
    with pytest.raises(ParameterError, match="key"):
        auto_exposure(np.ones((2, 2, 4)), key=0.0)
    with pytest.raises(ParameterError, match="shape"):
        auto_exposure(np.ones((2, 2, 2, 2)))


# ---------------------------------------------------------------------------------------------
# Operators

OPERATORS = {name: op.function for name, op in TONEMAPS.items()}
colours = st.tuples(*[st.floats(0.0, 1.0)] * 3).filter(lambda c: sum(c) > 1e-3)


@settings(max_examples=80, deadline=None)
@given(colour=colours, t1=st.floats(0.0, 1e6), t2=st.floats(0.0, 1e6))
def test_operators_monotonic_in_luminance(colour, t1, t2):
    # Scaling one colour by t scales its luminance by t; every output channel must not
    # decrease. 1e-12 absorbs float64 rounding of the ratio forms (C / L) * L_d.
    lo, hi = sorted((t1, t2))
    c = np.array(colour)
    for name, op in OPERATORS.items():
        a, b = op(lo * c), op(hi * c)
        assert np.all(b >= a - 1e-12), (name, lo, hi, a, b)


@pytest.mark.parametrize("name", sorted(OPERATORS))
def test_operators_zero_and_bounds(name):
    op = OPERATORS[name]
    np.testing.assert_array_equal(op(np.zeros((3, 3))), 0.0)
    x = np.array([[1e-9, 0, 0], [0.18, 0.18, 0.18], [1e4, 3, 0], [1e30, 1e30, 1e30], [-5, 1, 2]])
    y = op(x)
    assert np.all((y >= 0.0) & (y <= 1.0)), y
    # Very bright -> white. SRGB_LUMINANCE sums to 1 + 1.3e-8, so luminance-based operators
    # give grey 1 - 1.3e-8 (still code 255).
    assert np.all(y[3] >= 1.0 - 1e-7)


@settings(max_examples=60, deadline=None)
@given(l_white=st.floats(1e-3, 1e6))
def test_reinhard_maps_l_white_to_exactly_one(l_white):
    assert reinhard_luminance(l_white, l_white) == 1.0  # (Lw + 1) / (1 + Lw), exactly
    # eq. 5.1 limit: L_white -> inf gives L / (1 + L).
    assert reinhard_luminance(3.0, math.inf) == 0.75


def test_reinhard_preserves_chromaticity_before_clipping():
    rng = np.random.default_rng(3)
    c = rng.uniform(0.0, 1.0, (500, 3)) * 10.0 ** rng.uniform(-4, 0.5, (500, 1))
    d = reinhard(c, l_white=4.0)
    unclipped = np.all(d < 1.0, axis=-1)
    assert unclipped.mean() > 0.9
    # C_d = C * (L_d / L) (eq. 5.4): per-pixel ratios C_d / C are one number; rtol 1e-12
    # covers float64 rounding of (C / L) * L_d.
    k = d[unclipped] / c[unclipped]
    np.testing.assert_allclose(k, k[:, :1] * np.ones((1, 3)), rtol=1e-12)
    # Its luminance is eq. 5.2 of the input luminance.
    lum = c[unclipped] @ SRGB_LUMINANCE
    np.testing.assert_allclose(
        d[unclipped] @ SRGB_LUMINANCE, reinhard_luminance(lum, 4.0), rtol=1e-12
    )


def test_hvs_by_hand():
    # Seed 003 eq. 7 with 10^b = a + 2 and 10^(1-b) = I_max - a  =>  t = 10^b solves
    # t^2 - (I_max + 2) t + 10 = 0 (smaller root). Values computed by hand to 6 decimals:
    # I_max = 9: t = (11 - 9) / 2 = 1, a = -1, b = 0; x = 4.5 >= a + 1 = 0:
    #   f = log10(4.5 + 1) = log10(5.5) = 0.740363.
    assert hvs_coefficients(9.0) == pytest.approx((-1.0, 0.0), abs=1e-15)
    assert hvs_curve(4.5, 9.0) == pytest.approx(0.740363, abs=1e-6)
    # I_max = 6: t = 4 - sqrt(6) = 1.550510, a = -0.449490, b = log10(1.550510) = 0.190475;
    #   x = 3 (upper branch, a + 1 = 0.550510): log10(3.449490) + 0.190475 = 0.728230;
    #   x = 0.3 (lower branch): -log10(2 + a - 0.3 = 1.250510) + 0.190475 = 0.093388.
    a, b = hvs_coefficients(6.0)
    assert (a, b) == pytest.approx((-0.449490, 0.190475), abs=1e-6)
    assert hvs_curve(3.0, 6.0) == pytest.approx(0.728230, abs=1e-6)
    assert hvs_curve(0.3, 6.0) == pytest.approx(0.093388, abs=1e-6)
    # I_max = 2 sqrt(10) - 2 (double root): t = sqrt(10), a = 1.162278, b = 0.5; x = 1:
    #   -log10(1.162278 + 2 - 1 = 2.162278) + 0.5 = -0.334912 + 0.5 = 0.165089.
    assert hvs_curve(1.0, 2 * math.sqrt(10) - 2) == pytest.approx(0.165089, abs=1e-6)
    # Through the whole operator: a grey pixel of exposed luminance 0.5 with I_max = 9,
    # white = 1 gets x = 4.5 and the 8-bit code value 255 f = 188.79 -> 189, as eq. 7 says.
    grey = np.full((1, 1, 4), 0.5 / SRGB_LUMINANCE.sum())
    assert tonemap(grey, "hvs", 1.0)[0, 0].tolist() == [189, 189, 189]


@settings(max_examples=40, deadline=None)
@given(i_max=st.floats(2 * math.sqrt(10) - 2, 9.0))
def test_hvs_curve_endpoints_and_continuity(i_max):
    a, _ = hvs_coefficients(i_max)
    # f(0) = 0 and f(I_max) = 1 by the constraints; both branches meet at x = a + 1.
    # Tolerances: float64 log10 of values in [1, 10], a few ulp -> 1e-12.
    assert hvs_curve(0.0, i_max) == pytest.approx(0.0, abs=1e-12)
    assert hvs_curve(i_max, i_max) == pytest.approx(1.0, abs=1e-12)
    j = a + 1.0
    assert hvs_curve(j - 1e-9, i_max) == pytest.approx(hvs_curve(j, i_max), abs=1e-8)
    assert 0.0 <= j <= i_max


def test_hvs_range_is_checked():
    with pytest.raises(ParameterError, match="i_max"):
        hvs(np.ones(3), i_max=20.0)


def test_exponential_and_filmic_values():
    # Seed 000 eq. 4.14 with T_s = 4: T(1) = 1 - e^-4 = 0.981684.
    assert exponential(np.ones(3), k=4.0)[0] == pytest.approx(1 - math.exp(-4), rel=1e-12)
    # Narkowicz: "1 on input maps to ~0.8": 2.54 / 3.16 = 0.803797.
    assert filmic(np.ones(3))[0] == pytest.approx(2.54 / 3.16, rel=1e-12)


def test_filmic_grey_response_is_narkowicz():
    # Grey goes through Narkowicz's curve unchanged (max RGB = the grey value), as with the
    # per-channel operator before: by hand, f(0.18) = 0.18 * 0.4818 / (0.18 * 1.0274 + 0.14)
    # = 0.0867240 / 0.3249320 = 0.266898 (6 decimals, so abs 1e-6).
    assert filmic(np.full(3, 0.18)) == pytest.approx(0.266898, abs=1e-6)
    # pre_scale 0.6: f(0.6) = 0.6 * 1.536 / (0.6 * 2.048 + 0.14) = 0.9216 / 1.3688 = 0.673290.
    assert filmic(np.full(3, 1.0), pre_scale=0.6) == pytest.approx(0.673290, abs=1e-6)


def test_filmic_preserves_channel_ratios_below_the_shoulder():
    # In-gamut colours (max channel <= 1, the EV saturation point, where no desaturation
    # applies) over four decades of exposure: the output is the input times one number per
    # pixel, so every ratio between channels is the input's. float64 rounding of
    # x / max * f(max) is ~1e-16 relative; 1e-6 is the brief's bound and far above it.
    rng = np.random.default_rng(11)
    c = rng.uniform(0.0, 1.0, (2000, 3)) * 10.0 ** rng.uniform(-4.0, 0.0, (2000, 1))
    d = filmic(c)
    big = c > 1e-3 * c.max(axis=-1, keepdims=True)  # ratios of near-zero channels are noise
    k = np.where(big, d / np.where(big, c, 1.0), np.nan)
    k_ref = (d.max(axis=-1) / c.max(axis=-1))[:, None]
    np.testing.assert_allclose(k[big], np.broadcast_to(k_ref, k.shape)[big], rtol=1e-6)
    # And the brightest channel gets the grey response of the same value.
    np.testing.assert_allclose(
        d.max(axis=-1), filmic(np.repeat(c.max(axis=-1, keepdims=True), 3, -1))[:, 0], rtol=1e-12
    )


@pytest.mark.parametrize("scale", [0.1, 1.0, 10.0])
def test_filmic_very_bright_saturated_colours_go_to_white(scale):
    # The case: a very bright, out-of-gamut orange (blue 0) must end near white,
    # not at yellow (1, 1, 0) as per-channel ACES gives. max = 10 ... 1000 exposed is 3.3 to
    # 10 stops above saturation: every channel > 0.9 (code > 243), blue not 0.
    d = filmic(np.array([100.0, 30.0, 0.0]) * scale)
    assert np.all(d > 0.9), d
    assert d[2] > 0.0
    # The Sun -15 deg horizon pixel of the issue (exposed, blue slightly negative).
    assert np.all(filmic(np.array([21.6, 4.88, -0.027])) > 0.9)


def test_filmic_path_to_white_keeps_the_hue():
    # Orange (1, 0.3, 0) from 1/16 to 64 times saturation: below saturation the colour keeps
    # its ratios; above, it mixes with white, so the saturation 1 - min/max falls steadily
    # to 0 while the hue vector (d - min) / (max - min), the HSV hue of linear RGB, stays
    # (1, 0.3, 0): orange -> pale orange -> white, never yellow. 1e-9: float64 rounding of
    # differences of values ~1.
    orange = np.array([1.0, 0.3, 0.0])
    d = filmic(orange * 2.0 ** np.linspace(-4.0, 6.0, 201)[:, None])
    saturation = 1.0 - d.min(axis=-1) / d.max(axis=-1)
    assert np.all(np.diff(saturation) <= 1e-12)
    assert saturation[0] == pytest.approx(1.0, abs=1e-12) and saturation[-1] < 1e-9
    coloured = saturation > 1e-6
    hue = (d - d.min(-1, keepdims=True))[coloured] / np.ptp(d[coloured], axis=-1)[:, None]
    np.testing.assert_allclose(hue, np.broadcast_to(orange, hue.shape), atol=1e-9)


@pytest.mark.parametrize(
    "colour", [(1.0, 0.3, 0.0), (0.05, 0.2, 1.0), (0.0, 1.0, 0.0), (0.9, 0.8, 0.7), (1, 1, 1)]
)
def test_filmic_monotonic_and_continuous_in_exposure(colour):
    # A dense exposure sweep over 8 decades (0.2 % steps) crosses the desaturation start
    # (max = 1) and end (max = 8): each channel and the luminance never decrease (1e-12:
    # float64 rounding), and no step jumps (a 0.46 % exposure step moved a display value by
    # at most 0.0034 here; 0.01 would catch a discontinuity at either end of the blend).
    exposure = 10.0 ** np.linspace(-4.0, 4.0, 4001)[:, None]
    d = filmic(np.array(colour) * exposure)
    steps = np.diff(d, axis=0)
    assert np.all(steps >= -1e-12)
    assert np.all(np.diff(d @ SRGB_LUMINANCE) >= -1e-12)
    assert np.abs(steps).max() < 0.01


def test_tonemap_registry_and_errors():
    frame = np.zeros((2, 3, 4), np.float32)
    frame[0] = 100.0  # bright top row
    img = tonemap(frame, "reinhard", 0.01)
    assert img.dtype == np.uint8 and img.shape == (2, 3, 3)
    assert np.all(img[0] > 0) and np.all(img[1] == 0)  # row 0 stays the top row
    with pytest.raises(ParameterError) as exc:
        tonemap(frame, "drago", 1.0)
    for name in TONEMAPS:
        assert name in str(exc.value)
    with pytest.raises(ParameterError, match="l_white"):
        tonemap(frame, "exponential", 1.0, l_white=2.0)
    with pytest.raises(ParameterError, match="white"):
        tonemap(frame, "reinhard", 1.0, l_white=-2.0)
    with pytest.raises(ParameterError, match="exposure"):
        tonemap(frame, "filmic", 0.0)
    frame[1, 2, 1] = np.nan
    with pytest.raises(ParameterError, match="row 1, column 2"):
        tonemap(frame, "filmic", 1.0)


# ---------------------------------------------------------------------------------------------
# GLSL pass against the NumPy reference


@pytest.fixture(scope="module")
def mapper():
    try:
        m = GpuToneMapper()
    except GLError as exc:  # pragma: no cover - DESIGN rule 3: llvmpipe is always there
        pytest.skip(f"no OpenGL 3.3 context: {exc}")
    yield m
    m.release()


def random_hdr_frame(rng, h, w):
    """A frame spanning 8 decades (0.01 to 1e6 cd/m^2), random colours, some black and
    saturated pixels, some negative (out-of-gamut) components and a Sun."""
    lum = 10.0 ** rng.uniform(-2, 6, (h, w, 1))
    rgb = rng.uniform(0.0, 1.0, (h, w, 3)) ** 2
    frame = np.concatenate([rgb * lum, lum * 0.5], axis=-1).astype(np.float32)
    frame[rng.uniform(size=(h, w)) < 0.05] = 0.0
    frame[rng.uniform(size=(h, w)) < 0.05, 1] *= -0.1
    frame[: h // 8, : w // 8, :3] = 1.6e9
    return frame


CASES = [
    ("linear", {}),
    ("exponential", {}),
    ("exponential", {"k": 4.0}),
    ("reinhard", {}),
    ("reinhard", {"l_white": math.inf}),
    ("hvs", {}),
    ("hvs", {"i_max": 5.0, "white": 2.0}),
    ("filmic", {}),
    ("filmic", {"pre_scale": 0.6}),
]


@pytest.mark.parametrize(("name", "params"), CASES)
def test_gl_equals_numpy(mapper, name, params):
    # GLSL runs in float32 (relative rounding ~6e-8 per operation; llvmpipe's exp/log/pow are
    # accurate to a few ulp), NumPy in float64: display values agree to ~1e-6, so an 8-bit code
    # can differ only where the exact value lies within ~3e-4 codes of a .5 rounding boundary,
    # and then by exactly 1. We require max |diff| <= 1 and such pixels to be rare (< 1 %).
    rng = np.random.default_rng(zlib.crc32(f"{name}{params}".encode()))
    frame = random_hdr_frame(rng, 61, 83)  # odd, non-square: catches row/column mix-ups
    for scale in (auto_exposure(frame, clip_percentile=99.0), ev100_to_scale(14.0)):
        ref = tonemap(frame, name, scale, **params)
        gl = mapper.render(frame, name, scale, **params)
        assert gl.dtype == np.uint8 and gl.shape == ref.shape
        diff = np.abs(gl.astype(int) - ref.astype(int))
        assert diff.max() <= 1, (name, params, np.argwhere(diff > 1)[:5])
        assert (diff > 0).mean() < 0.01
        assert ref.std() > 10  # not a black or flat image


@pytest.mark.parametrize("pre_scale", [1.0, 0.6])
def test_gl_filmic_shoulder_equals_numpy(mapper, pre_scale):
    # The random frames above put few pixels in the filmic shoulder; here every pixel's max
    # channel is 0.1 to 100 exposed (through the desaturation blend, max 1 to 8), with
    # saturated colours (one channel 0 or negative in a third of them). Same criterion as
    # test_gl_equals_numpy: float32 vs float64 moves a code by at most 1, and rarely.
    rng = np.random.default_rng(23)
    h, w = 47, 71
    rgb = rng.uniform(0.0, 1.0, (h, w, 3)) ** 3
    rgb /= rgb.max(axis=-1, keepdims=True)
    rows, cols = np.nonzero(rng.uniform(size=(h, w)) < 0.3)
    rgb[rows, cols, rng.integers(0, 3, rows.size)] *= -0.05
    frame = np.zeros((h, w, 4), np.float32)
    frame[..., :3] = rgb * 10.0 ** rng.uniform(-1.0, 2.0, (h, w, 1))
    ref = tonemap(frame, "filmic", 1.0, pre_scale=pre_scale)
    gl = mapper.render(frame, "filmic", 1.0, pre_scale=pre_scale)
    diff = np.abs(gl.astype(int) - ref.astype(int))
    assert diff.max() <= 1, np.argwhere(diff > 1)[:5]
    assert (diff > 0).mean() < 0.01
    assert ref.std() > 10


def test_gl_from_texture_and_orientation(mapper):
    # A texture in GL row order (as a renderer's target) gives the same image as the array.
    frame = np.zeros((4, 5, 4), np.float32)
    frame[0, 0, :3] = 1.0  # top-left pixel white (exposed 1.0, linear operator)
    tex = upload_frame(mapper.ctx, frame)
    try:
        img = mapper.render(tex, "linear", 1.0)
    finally:
        tex.release()
    assert img[0, 0].tolist() == [255, 255, 255]
    assert img.sum() == 3 * 255
    np.testing.assert_array_equal(gpu_tonemap(frame, "linear", 1.0), img)
    with pytest.raises(ParameterError, match="unknown tone map"):
        mapper.render(frame, "nope", 1.0)


def test_frame_objects_are_accepted(mapper):
    from skydome.core.frame import Frame

    data = random_hdr_frame(np.random.default_rng(5), 9, 11)
    frame = Frame(data, {"model": "test"})
    s = auto_exposure(frame)
    assert s == auto_exposure(data)
    np.testing.assert_array_equal(tonemap(frame, "reinhard", s), tonemap(data, "reinhard", s))
    np.testing.assert_array_equal(mapper.render(frame, "hvs", s), mapper.render(data, "hvs", s))


def test_large_frames_expose_from_a_subgrid():
    # Above AVERAGE_MAX_PIXELS the log-average comes from a regular subgrid; on a sky-like
    # frame (a smooth gradient over four decades, a bright Sun spot, unlit corners) it agrees
    # with the every-pixel average within 0.1 %.
    from skydome.display import exposure

    h, w = 2300, 2000  # 4.6 Mpixel > 4.19 Mpixel
    y, x = np.mgrid[0:h, 0:w]
    lum = 10.0 ** (4.0 * y / h) * (1.0 + 0.3 * np.sin(x / 97.0))
    lum[(y - 400) ** 2 + (x - 900) ** 2 < 30**2] = 1e9
    lum[:50, :50] = 0.0
    full = exposure.log_average_luminance(lum, clip_percentile=99.5)
    original = exposure.AVERAGE_MAX_PIXELS
    try:
        exposure.AVERAGE_MAX_PIXELS = h * w  # the same frame, every pixel
        every = exposure.log_average_luminance(lum, clip_percentile=99.5)
    finally:
        exposure.AVERAGE_MAX_PIXELS = original
    assert full == pytest.approx(every, rel=1e-3)


def test_large_frames_tone_map_in_bands(monkeypatch):
    # Bands of rows give the same bytes as one texture (tone maps are per pixel).
    import importlib

    gt = importlib.import_module("skydome.display.gpu_tonemap")
    rng = np.random.default_rng(5)
    frame = (10.0 ** rng.uniform(-2, 4, size=(90, 70, 4))).astype(np.float32)
    whole = gt.gpu_tonemap(frame, "filmic", 0.01)
    monkeypatch.setattr(gt, "BAND_PIXELS", 70 * 16 + 5)  # bands of 16 rows, the last of 10
    np.testing.assert_array_equal(gt.gpu_tonemap(frame, "filmic", 0.01), whole)
