"""Night-vision display pass: CIE 191:2010 mesopic blend, Purkinje shift, acuity blur, noise.

The GPU pass (skydome.display.night_vision, GLSL under shaders/post/) against its float64
twin (skydome.reference.night_vision) and against published numbers: the CIE 1924 and 1951
luminous efficiency tables, CIE 191:2010's constants and range, an independent MES2
implementation (LuxPy), Ferwerda et al. 1996's acuity fit.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from skydome.display.glare import GpuGlare
from skydome.display.gpu_exposure import GpuExposure
from skydome.display.gpu_tonemap import gpu_tonemap, upload_frame
from skydome.display.night_vision import (
    BLUE_GREY,
    NOISE_CAP,
    PHOTOPIC_ANY_SP_CD_M2,
    NightVision,
    acuity_cycles_per_deg,
    blur_plan,
    blur_sigma_deg,
    blur_sigma_px,
    mesopic_coefficient,
    mesopic_weight,
    noise_amplitude,
    photopic_share,
    pyramid_variance_px2,
)
from skydome.errors import ParameterError
from skydome.reference.night_vision import (
    acuity_blur,
    downsample,
    frame_sp_ratio,
    gaussian_blur,
    night_vision_reference,
    upsample,
)
from skydome.spectra import LINEAR_SRGB_TO_XYZ, SRGB_LUMINANCE, spectral_to_rgbs_matrix

H, W = 128, 256


def read_texture(tex) -> np.ndarray:
    """RGBA32F texture -> (H, W, 4) float32, row 0 at the top."""
    w, h = tex.size
    return np.frombuffer(tex.read(), dtype=np.float32).reshape(h, w, 4)[::-1].copy()


def grey_frame(lum: np.ndarray, sp: float = 1.0) -> np.ndarray:
    """A grey frame (D65 white) of luminance ``lum`` (H, W) and S/P ratio ``sp``."""
    f = np.zeros(lum.shape + (4,))
    f[..., :3] = lum[..., None]  # linear sRGB (1, 1, 1) has Y = 1
    f[..., 3] = sp * lum
    return f


def random_frame(rng, scale: float, sp_range=(0.3, 3.0)) -> np.ndarray:
    f = np.zeros((H, W, 4))
    f[..., :3] = rng.uniform(0.0, 1.0, (H, W, 3)) * scale
    f[..., 3] = (f[..., :3] @ SRGB_LUMINANCE) * rng.uniform(*sp_range, (H, W))
    return f


def chroma_uv(rgb: np.ndarray) -> np.ndarray:
    """Distance in CIE 1976 u'v' from the D65 white point (the saturation measure here)."""
    xyz = np.asarray(rgb, dtype=np.float64) @ LINEAR_SRGB_TO_XYZ.T
    d = xyz[..., 0] + 15.0 * xyz[..., 1] + 3.0 * xyz[..., 2]
    u, v = 4.0 * xyz[..., 0] / d, 9.0 * xyz[..., 1] / d
    wx, wy = 0.3127, 0.3290  # D65
    wd = -2.0 * wx + 12.0 * wy + 3.0
    return np.hypot(u - 4.0 * wx / wd, v - 9.0 * wy / wd)


@pytest.fixture(scope="module")
def nv(ctx):
    p = NightVision(ctx, seed=7)
    yield p
    p.release()


def run(nv, ctx, frame, *, adaptation, pixel_deg=0.05, time_s=0.0, noise=False, acuity=True):
    nv.noise, nv.acuity = noise, acuity
    tex = upload_frame(ctx, frame.astype(np.float32))
    try:
        out = nv.apply(
            tex,
            (frame.shape[1], frame.shape[0]),
            pixel_angle_rad=math.radians(pixel_deg),
            adaptation=adaptation,
            time_s=time_s,
        )
        return read_texture(out)
    finally:
        tex.release()


# ---------------------------------------------------------------------------------------------
# CIE 191:2010 MES2


def test_mes2_range_edges():
    # CIE 191:2010: m = 1 for L_mes >= 5 cd/m^2, 0 for L_mes <= 0.005 cd/m^2; with S/P = 1
    # L_mes = L_p, and m = 0.7670 + 0.3334 log10(L_p) in between (the standard's a and b).
    assert mesopic_weight(5.0) == 1.0
    assert mesopic_weight(1e4) == 1.0
    assert mesopic_weight(0.005) == 0.0
    assert mesopic_weight(1e-4) == 0.0
    assert mesopic_weight(1.0) == pytest.approx(0.767, abs=1e-12)
    assert mesopic_weight(0.1) == pytest.approx(0.767 - 0.3334, abs=1e-12)
    # The two ends of a, b: a + b log10(5) = 1.00003 and a + b log10(0.005) = -0.00016, so the
    # clamps, not the line, give the range edges (the standard rounds a, b to 4 digits).
    assert 0.767 + 0.3334 * math.log10(5.0) == pytest.approx(1.0, abs=5e-5)
    assert 0.767 + 0.3334 * math.log10(0.005) == pytest.approx(0.0, abs=5e-4)


def test_mes2_fixed_point_and_monotonic():
    # The returned (m, L_mes) satisfies both of the standard's equations; a bluer field
    # (higher S/P) at the same L_p is more mesopic-luminous and so more photopic (higher m).
    for lp, sp in [(0.01, 2.5), (0.1, 1.6), (0.5, 0.6), (2.0, 2.0), (0.03, 0.25)]:
        m, lmes = mesopic_coefficient(lp, lp * sp)
        v0 = 683.0 / 1699.0
        assert lmes == pytest.approx((m * lp + (1 - m) * lp * sp * v0) / (m + (1 - m) * v0))
        assert m == pytest.approx(min(max(0.767 + 0.3334 * math.log10(lmes), 0.0), 1.0), abs=1e-10)
    ms = [mesopic_weight(0.1, sp) for sp in (0.25, 0.65, 1.0, 1.65, 2.45)]
    assert all(a < b for a, b in zip(ms, ms[1:], strict=False))


# LuxPy 1.12.5 (Smet 2020, LEUKOS 16(3), an independent implementation of CIE 191:2010),
# luxpy.get_cie_mesopic_adaptation(Lp=1.0, SP=sp) -> (Lmes, m). At Lp = 1 its formula, which
# uses SP where the standard has L_s, is the standard's. Its stopping rule is np.isclose
# (rtol 1e-5): agreement to 1e-4 is the test. S/P 0.25-2.45 spans sodium lamps to
# cold white LEDs.
LUXPY_LP1 = {
    0.25: (0.9129610619932867, 0.7538143913997102),
    0.65: (0.9608054208725633, 0.7612106507979404),
    1.0: (1.0, 0.767),
    1.65: (1.067428322182614, 0.7764482089399872),
    2.45: (1.142796664542748, 0.7863265621593378),
}


@pytest.mark.parametrize("sp", sorted(LUXPY_LP1))
def test_mes2_against_luxpy(sp):
    lmes_ref, m_ref = LUXPY_LP1[sp]
    m, lmes = mesopic_coefficient(1.0, sp)
    assert m == pytest.approx(m_ref, abs=1e-4)
    assert lmes == pytest.approx(lmes_ref, rel=1e-4)


def test_gpu_mes2_and_sp_ratio(ctx, nv):
    # A flat grey field of S/P = 2 at L_p = 0.1 cd/m^2: the frame's measured S/P is 2, and each
    # output pixel's luminance is the standard's L_mes of the field (the field is its own
    # adaptation field). float32 in the shader's 64 fixed-point steps: 1e-5.
    frame = grey_frame(np.full((H, W), 0.1), sp=2.0)
    # (rel 1e-7: linear sRGB white (1, 1, 1) has Y = 1 - 2.6e-8 with the inverted matrix)
    assert frame_sp_ratio(frame) == pytest.approx(2.0, rel=1e-7)
    m, lmes = mesopic_coefficient(0.1, 0.2)
    assert 0.4 < m < 0.6
    out = run(nv, ctx, frame, adaptation=0.1, acuity=False)
    lum = out[..., :3] @ SRGB_LUMINANCE
    np.testing.assert_allclose(lum, lmes, rtol=1e-5)
    # The same through a GpuExposure that measured the frame (its log-average read in GLSL).
    exposure = GpuExposure(ctx)
    tex = upload_frame(ctx, frame.astype(np.float32))
    try:
        exposure.measure(tex)
        nv.noise = nv.acuity = False
        out2 = read_texture(
            nv.apply(tex, (W, H), pixel_angle_rad=1e-3, adaptation=exposure, time_s=0.0)
        )
    finally:
        tex.release()
        exposure.release()
    np.testing.assert_allclose(out2[..., :3] @ SRGB_LUMINANCE, lmes, rtol=1e-5)


# ---------------------------------------------------------------------------------------------
# Identity in photopic vision; saturation and Purkinje shift at night


@pytest.mark.parametrize("use_exposure", [False, True])
def test_identity_above_5_cd_m2(ctx, nv, use_exposure):
    # Adaptation >= 5 cd/m^2: m = 1, no blur, no noise: the texture read back equals the input
    # bit for bit, with every component on (a telephoto pixel of 1e-4 deg, where any blur
    # would show).
    rng = np.random.default_rng(3)
    frame = random_frame(rng, 200.0).astype(np.float32)
    frame[5, 7] = (1e6, 2e6, 3e6, 1e6)  # a bright source, still copied exactly
    nv.noise = nv.acuity = True
    tex = upload_frame(ctx, frame)
    exposure = GpuExposure(ctx) if use_exposure else None
    try:
        if exposure is not None:
            exposure.measure(tex)
            assert exposure.read() > 5.0
        out = nv.apply(
            tex,
            (W, H),
            pixel_angle_rad=math.radians(1e-4),
            adaptation=exposure if exposure is not None else 6.0,
            time_s=3.25,
        )
        got = read_texture(out)
    finally:
        tex.release()
        if exposure is not None:
            exposure.release()
    assert np.array_equal(got.view(np.uint32), frame.view(np.uint32))


def test_saturation_at_1e_3_cd_m2(ctx, nv):
    # At 1e-3 cd/m^2 (m = 0: L_mes < 0.005) every pixel is drawn in the blue grey: chroma
    # (distance in u'v' from D65) of every lit pixel = that of C_b, 0.029, below the bound
    # 0.03; the input's saturated primaries have chroma 0.11-0.26.
    frame = np.zeros((H, W, 4))
    prim = np.eye(3)
    for i in range(3):
        block = prim[i] / (prim[i] @ SRGB_LUMINANCE) * 1e-3  # luminance 1e-3 cd/m^2
        frame[:, i * W // 3 : (i + 1) * W // 3, :3] = block
    frame[..., 3] = (frame[..., :3] @ SRGB_LUMINANCE) * np.array([0.05, 1.0, 3.0])[
        np.minimum(np.arange(W) * 3 // W, 2)
    ]
    assert chroma_uv(np.eye(3)).min() > 0.1
    out = run(nv, ctx, frame, adaptation=1e-3, noise=True, acuity=True)
    c = chroma_uv(out[..., :3])
    assert c.max() < 0.03
    assert c == pytest.approx(float(chroma_uv(BLUE_GREY)), abs=1e-4)


def narrowband(center_nm: float, fwhm_nm: float = 0.5) -> np.ndarray:
    """(R, G, B, S) of a narrow Gaussian line, scaled to luminance 1 cd/m^2."""
    wl = np.arange(380.0, 781.0, 0.5)
    s = np.exp(-0.5 * ((wl - center_nm) / (fwhm_nm / 2.3548)) ** 2)
    rgbs = spectral_to_rgbs_matrix(wl, illuminant="none") @ s
    return rgbs / (rgbs[:3] @ SRGB_LUMINANCE)


def test_purkinje_shift(ctx, nv):
    # Equal photopic luminance, 460 nm (blue) and 620 nm (red) halves. In photopic vision
    # they stay equal; at m = 0 the displayed ratio blue / red is the ratio of their scotopic
    # to photopic efficiencies, from the CIE tables V(460) = 0.060, V'(460) = 0.567,
    # V(620) = 0.381, V'(620) = 0.00737: (0.567 / 0.060) / (0.00737 / 0.381) = 488.5 (a 0.5 nm
    # line instead of a monochromatic one: 1e-7; float32 texels: 1e-6; tolerance 1e-4).
    # Between, the ratio grows as m falls.
    blue, red = narrowband(460.0), narrowband(620.0)
    expected = (0.567 / 0.060) / (0.00737 / 0.381)
    ratios = []
    for lum in (10.0, 1.0, 0.1, 0.01, 1e-3):
        frame = np.zeros((H, W, 4))
        frame[:, : W // 2] = blue * lum
        frame[:, W // 2 :] = red * lum
        out = run(nv, ctx, frame, adaptation=lum, acuity=False)
        y = out[..., :3] @ SRGB_LUMINANCE
        ratios.append(float(y[H // 2, W // 4] / y[H // 2, 3 * W // 4]))
    assert ratios[0] == pytest.approx(1.0, rel=1e-6)
    assert all(a < b for a, b in zip(ratios, ratios[1:], strict=False))
    assert ratios[-1] == pytest.approx(expected, rel=1e-4)


# ---------------------------------------------------------------------------------------------
# GPU pass against the float64 twin


@pytest.mark.parametrize(
    ("adaptation", "pixel_deg", "shape", "level"),
    [
        (0.3, 0.02, (H, W), 0),
        (0.02, 0.02, (H, W), 0),
        (1e-3, 0.05, (H, W), 0),
        (1e-3, 0.05, (125, 250), 0),
        (1e-4, 0.02, (H, W), 2),
        (1e-4, 0.02, (125, 250), 2),
    ],
)
def test_gpu_matches_reference_without_noise(ctx, nv, adaptation, pixel_deg, shape, level):
    # Mesopic (m ~ 0.6, 0.25) and scotopic (m = 0); blurs of 0.4 px (none), 0.9 px (full
    # resolution, four channels), 1.25 px (m = 0: the scotopic channel alone, packed four
    # pixels to a texel; also on a width that is no multiple of 4) and 5 px (on the 1/4 level
    # of the pyramid; also on odd sizes). Tolerance: float32 texels, float32 sums of up to 17
    # taps and the bilinear enlargement: 1e-5 of the frame's largest value.
    rng = np.random.default_rng(11)
    frame = random_frame(rng, adaptation * 2.0)[: shape[0], : shape[1]]
    out = run(nv, ctx, frame, adaptation=adaptation, pixel_deg=pixel_deg)
    ref, state = night_vision_reference(
        frame.astype(np.float32),
        pixel_angle_rad=math.radians(pixel_deg),
        adaptation=adaptation,
        noise=False,
    )
    assert state["m"] < 1.0
    assert nv.last_state["level"] == level
    assert nv.last_state["m"] == pytest.approx(state["m"], abs=1e-6)
    np.testing.assert_allclose(out, ref, rtol=0, atol=1e-5 * np.abs(ref).max())


def test_photopic_returns_input(ctx, nv):
    # m = 1: no pass runs at all; the input texture itself comes back. At 50 cd/m^2 not even
    # the S/P ratio is measured (m = 1 whatever it is: below).
    tex = upload_frame(ctx, random_frame(np.random.default_rng(1), 100.0).astype(np.float32))
    try:
        assert nv.apply(tex, (W, H), pixel_angle_rad=1e-3, adaptation=50.0) is tex
        assert nv.last_state["m"] == 1.0 and nv.last_state["lmes"] == 50.0
        assert nv.last_state["sp"] is None
        nv.apply(tex, (W, H), pixel_angle_rad=1e-3, adaptation=5.0)  # mesopic: measured
        assert nv.last_state["sp"] > 0.0
    finally:
        tex.release()


def test_from_photopic_any_sp_cd_m2_mes2_is_photopic_whatever_the_sp_ratio():
    # The fact that lets apply() skip the S/P ratio by day: CIE 191:2010 MES2 gives m = 1 and
    # L_mes = L_p from L_p = 7.01 cd/m^2 on (its first step from m = 0.5 gives L_mes >= 0.713
    # L_p >= 5 cd/m^2, where m = 0.767 + 0.3334 log10(5) = 1), for any scotopic luminance, so
    # from PHOTOPIC_ANY_SP_CD_M2 = 10 with room to spare; and not below 5 cd/m^2 in general.
    for lp in np.geomspace(PHOTOPIC_ANY_SP_CD_M2, 1e7, 60):
        for ls in (0.0, *np.geomspace(1e-6, 1e9, 60)):
            assert mesopic_coefficient(float(lp), float(ls)) == (1.0, float(lp))
    assert mesopic_coefficient(4.0, 0.0)[0] < 1.0


def test_noise_repeatable_and_matches_reference(ctx, nv):
    rng = np.random.default_rng(5)
    frame = random_frame(rng, 4e-4)
    kw = dict(adaptation=2e-4, pixel_deg=0.02, noise=True)
    a = run(nv, ctx, frame, time_s=12.5, **kw)
    b = run(nv, ctx, frame, time_s=12.5, **kw)
    c = run(nv, ctx, frame, time_s=12.5 + 1.0 / 30.0, **kw)
    assert np.array_equal(a.view(np.uint32), b.view(np.uint32))  # same seed and time: same
    assert np.mean(a != c) > 0.5  # another frame time: another pattern
    ref, _ = night_vision_reference(
        frame.astype(np.float32),
        pixel_angle_rad=math.radians(0.02),
        adaptation=2e-4,
        seed=7,
        time_s=12.5,
        noise=True,
    )
    # The same hash on uint32 in NumPy: the same noise, to float32 rounding.
    np.testing.assert_allclose(a, ref, rtol=0, atol=1e-5 * np.abs(ref).max())
    other = NightVision(ctx, seed=8, acuity=True, noise=True)
    try:
        tex = upload_frame(ctx, frame.astype(np.float32))
        d = read_texture(
            other.apply(
                tex, (W, H), pixel_angle_rad=math.radians(0.02), adaptation=2e-4, time_s=12.5
            )
        )
        tex.release()
    finally:
        other.release()
    assert np.mean(a != d) > 0.5  # another seed: another pattern


def test_noise_preserves_mean_of_flat_field(ctx, nv):
    # A flat field at 2e-4 cd/m^2 (moonless sky), S/P = 1: m = 0, relative noise
    # a = 1 / sqrt(5e5 * 2e-4) = 0.1 per pixel. Over N = 32768 pixels the mean's standard
    # error is a / sqrt(N) = 5.5e-4: the mean is kept within 4 standard errors, the measured
    # standard deviation is a within 3 % (its own standard error is about a / sqrt(2N) = 0.4 %,
    # and the hash is not a perfect generator).
    lum = 2e-4
    frame = grey_frame(np.full((H, W), lum))
    a = float(noise_amplitude(lum, 0.0))
    assert a == pytest.approx(0.1, rel=1e-12)
    for t in (0.0, 1.0, 2.0):
        out = run(nv, ctx, frame, adaptation=lum, time_s=t, noise=True)
        y = out[..., :3] @ SRGB_LUMINANCE / lum  # the blue grey has luminance 1
        se = a / math.sqrt(y.size)
        assert abs(y.mean() - 1.0) < 4.0 * se
        assert y.std() == pytest.approx(a, rel=0.03)
        assert y.min() >= 0.0


def test_noise_amplitude_law():
    # Photon-count law: relative noise 1 / sqrt(Q L_s), so ten times the light, sqrt(10) times
    # less noise; capped at 1 / sqrt(6) (1 + a n >= 0 for n in [-sqrt 6, sqrt 6]); none at m = 1.
    a1, a2 = noise_amplitude(1e-3, 0.0), noise_amplitude(1e-2, 0.0)
    assert a1 / a2 == pytest.approx(math.sqrt(10.0), rel=1e-12)
    assert noise_amplitude(1e-9, 0.0) == NOISE_CAP
    assert noise_amplitude(1e-3, 1.0) == 0.0


# ---------------------------------------------------------------------------------------------
# Acuity


def test_acuity_fit_values():
    # Ferwerda et al. 1996, eq. 7 (fit of Shaler 1937): R = 17.25 atan(1.4 log10 L + 0.35) +
    # 25.72 cycles/deg: about 50 c/deg in daylight (1e4 cd/m^2; 0.6 arcmin per half cycle,
    # better than the 30 c/deg of 20/20 Snellen acuity), about 3 c/deg at 1e-3 cd/m^2.
    assert 49.0 < acuity_cycles_per_deg(1e4) < 51.0
    assert acuity_cycles_per_deg(1e-3) == pytest.approx(17.25 * math.atan(-3.85) + 25.72, rel=1e-12)
    assert 2.5 < acuity_cycles_per_deg(1e-3) < 3.5
    assert blur_sigma_deg(5.0) == 0.0 and blur_sigma_deg(50.0) == 0.0


@pytest.mark.parametrize("lum", [1e-3, 0.05])
def test_blur_width_against_acuity(ctx, nv, lum):
    # A point of light (grey, S/P = 1) on a faint floor, adaptation 1e-3 and 0.05 cd/m^2,
    # pixels of 0.005 deg. The blurred point's standard deviation (second moment along x)
    # against the width from Ferwerda's fit: sigma = sqrt(ln 2 / 2) / pi * sqrt(1 / R(L)^2 -
    # 1 / R(5)^2) deg, R from eq. 7 evaluated here by hand. The taps stop at 3 sigma, which
    # narrows a Gaussian's second moment by 1.3 %: tolerance 2 %.
    pixel_deg = 0.005
    k = math.sqrt(math.log(2.0) / 2.0) / math.pi
    r = 17.25 * math.atan(1.4 * math.log10(lum) + 0.35) + 25.72
    r5 = 17.25 * math.atan(1.4 * math.log10(5.0) + 0.35) + 25.72
    sigma_expected = k * math.sqrt(1.0 / r**2 - 1.0 / r5**2) / pixel_deg
    assert blur_sigma_px(lum, math.radians(pixel_deg)) == pytest.approx(sigma_expected)
    lumimg = np.full((H, W), 1e-9)
    lumimg[H // 2, W // 2] = 1.0
    out = run(nv, ctx, grey_frame(lumimg), adaptation=lum, pixel_deg=pixel_deg)
    y = out[..., :3] @ SRGB_LUMINANCE
    row = y[H // 2] - 1e-9
    x = np.arange(W) - W // 2
    sigma_measured = math.sqrt(float((row * x * x).sum() / row.sum()))
    assert sigma_measured == pytest.approx(sigma_expected, rel=0.02)
    assert 2.0 < sigma_expected < 40.0


def test_no_blur_below_half_pixel(ctx, nv):
    # 0.3 cd/m^2 at 0.1 deg pixels: sigma = 0.08 px < 0.5: the blur passes copy exactly.
    assert blur_sigma_px(0.3, math.radians(0.1)) < 0.5
    frame = random_frame(np.random.default_rng(2), 0.6)
    with_blur = run(nv, ctx, frame, adaptation=0.3, pixel_deg=0.1, acuity=True)
    without = run(nv, ctx, frame, adaptation=0.3, pixel_deg=0.1, acuity=False)
    assert np.array_equal(with_blur.view(np.uint32), without.view(np.uint32))


def test_flat_field_stays_flat(ctx, nv):
    # A 10 px blur over a flat field (edges clamped, weights normalised): flat to float32
    # rounding (1e-6).
    lum = 1e-4
    assert blur_sigma_px(lum, math.radians(0.01)) > 10.0
    out = run(nv, ctx, grey_frame(np.full((H, W), lum), sp=1.3), adaptation=lum, pixel_deg=0.01)
    y = out[..., :3] @ SRGB_LUMINANCE
    assert (y.max() - y.min()) / y.mean() < 1e-6
    assert y.mean() == pytest.approx(1.3 * lum, rel=1e-6)  # m = 0: L_mes = L_s


# ---------------------------------------------------------------------------------------------
# Input checks


def test_bad_input(ctx, nv):
    tex = upload_frame(ctx, np.zeros((4, 8, 4), np.float32))
    try:
        with pytest.raises(ParameterError, match="pixel_angle_rad"):
            nv.apply(tex, (8, 4), pixel_angle_rad=0.0, adaptation=1.0)
        with pytest.raises(ParameterError, match="adaptation"):
            nv.apply(tex, (8, 4), pixel_angle_rad=1e-3, adaptation=-1.0)
        with pytest.raises(ParameterError, match="adaptation"):
            nv.apply(tex, (8, 4), pixel_angle_rad=1e-3, adaptation="dark")
        with pytest.raises(ParameterError, match="size"):
            nv.apply(tex, (4, 8), pixel_angle_rad=1e-3, adaptation=1.0)
    finally:
        tex.release()
    with pytest.raises(ParameterError, match="seed"):
        NightVision(ctx, seed=-1)
    with pytest.raises(ParameterError, match="S/P"):
        mesopic_weight(1.0, 0.0)
    with pytest.raises(ParameterError, match="m ="):
        photopic_share(1.5)


# ---------------------------------------------------------------------------------------------
# The pyramid of a wide blur against the exact Gaussian


@pytest.mark.parametrize("level", [1, 2, 3])
def test_pyramid_variance_and_centroid(level):
    # A point halved `level` times ([1, 3, 3, 1] / 8) and enlarged back (bilinear), in the
    # float64 twin, for every phase of the point in the blocks: its centroid stays where it
    # was (1e-12 px), its variance is pyramid_variance_px2's closed form 0.25 (4^k - 1) +
    # (4^k + 1/2) / 6 (1.5, 6.5, 26.5 px^2), numerically summed (1e-9), flux kept.
    x = np.arange(W)
    for phase in range(2**level):
        f = np.zeros((H, W, 1))
        f[64, 100 + phase] = 1.0
        gl = f[::-1]
        for _ in range(level):
            gl = downsample(gl)
        out = upsample(gl, level, (H, W))[::-1]
        row = out.sum(axis=0)[:, 0]
        assert row.sum() == pytest.approx(1.0, abs=1e-12)
        mu = float((row * x).sum())
        assert mu == pytest.approx(100 + phase, abs=1e-12)
        assert float((row * (x - mu) ** 2).sum()) == pytest.approx(
            pyramid_variance_px2(level), abs=1e-9
        )
    assert [pyramid_variance_px2(k) for k in (1, 2, 3)] == [1.5, 6.5, 26.5]


@pytest.mark.parametrize("sigma", [2.4, 5.0, 12.5])
def test_pyramid_blur_against_exact_gaussian(sigma):
    # The stated bound of the reduced-resolution blur (float64 twin; the GPU matches the twin
    # to 1e-5 above). Points at 8 phases: flux kept (1e-12), centroid unmoved (1e-9 px),
    # width (second moment) that of the exact Gaussian within 1 % (the level's taps stop at
    # 3 sigma: at most -0.6 % measured), peak within 10 % of the exact Gaussian's (measured
    # 2-7 %: the pyramid's kernel is a Gaussian widened by B-spline and tent kernels, a little
    # flatter on top). White noise, the worst case (all frequencies), away from the edges
    # (3 sigma): error below 0.2 of the blurred field's own standard deviation (measured
    # 0.08-0.14). At the edges both clamp, in different ways.
    level, s = blur_plan(sigma, (W, H))
    assert level >= 1 and s >= 1.0
    x = np.arange(W)
    for phase in range(8):
        f = np.zeros((H, W, 1))
        f[64, 120 + phase] = 1.0
        a = acuity_blur(f, sigma)[..., 0]
        b = gaussian_blur(f, sigma)[..., 0]
        assert a.sum() == pytest.approx(1.0, abs=1e-12)
        row = a.sum(axis=0)
        mu = float((row * x).sum())
        assert mu == pytest.approx(120 + phase, abs=1e-9)
        width = math.sqrt(float((row * (x - mu) ** 2).sum()))
        assert width == pytest.approx(sigma, rel=0.01)
        assert abs(a.max() - b.max()) < 0.10 * b.max()
    noise = np.random.default_rng(1).uniform(0.0, 1.0, (H, W, 1))
    e = math.ceil(3.0 * sigma)
    exact = gaussian_blur(noise, sigma)[e:-e, e:-e]
    err = np.abs(acuity_blur(noise, sigma)[e:-e, e:-e] - exact).max()
    assert err < 0.2 * exact.std()


def test_blur_plan():
    # No blur below 0.5 px; full resolution while the level's Gaussian would fall under 1 px;
    # every level keeps the total variance: s^2 4^k + pyramid variance = sigma^2.
    assert blur_plan(0.4, (W, H)) == (0, 0.0)
    assert blur_plan(2.0, (W, H)) == (0, 2.0)
    for sigma in (2.4, 5.0, 12.5, 40.0):
        k, s = blur_plan(sigma, (W, H))
        assert k >= 1 and s >= 1.0
        assert s * s * 4.0**k + pyramid_variance_px2(k) == pytest.approx(sigma * sigma)
    # The smallest level keeps 2 px on its smaller side: a blur as wide as the frame stops
    # at 1/64 of 128 px (2 px).
    assert blur_plan(1e4, (W, H))[0] == 6


@pytest.mark.gl
@pytest.mark.parametrize("adaptation", [0.05, 1e-4])  # mesopic (m ~ 0.4) and scotopic (m = 0)
def test_the_tone_map_applies_the_eyes_colours_as_their_pass_does(ctx, adaptation):
    """The eye metering's colours (no blur, no noise) are a blend the tone map applies as it
    reads the frame and its glare (NightVision.colours, MESOPIC_BLEND), measured on the
    frame with its halo: the image is the one of the glared frame through the eye's pass
    and the tone map, code for code, and the pass's state the same."""
    rng = np.random.default_rng(5)
    frame = random_frame(rng, adaptation * 2.0).astype(np.float32)
    frame[40:44, 100:104, :3] *= 1e4  # a bright spot, for a halo
    size = (W, H)
    pixel = math.radians(0.1)
    tex = upload_frame(ctx, frame)
    glare = GpuGlare(ctx)
    passes = [NightVision(ctx, noise=False, acuity=False) for _ in range(2)]
    scale = 0.18 / adaptation
    try:
        halo = glare.halo(tex, size, pixel_angle_rad=pixel, glare="eye")
        assert halo is not None
        seen = passes[0].apply(
            glare.composite(tex, size, halo), size, pixel_angle_rad=pixel, adaptation=adaptation
        )
        want = gpu_tonemap(seen, "filmic", scale, ctx=ctx)
        blend = passes[1].colours(tex, size, adaptation=adaptation, glare_halo=halo)
        assert blend is not None and 0.0 <= blend.u_wp < 1.0
        got = gpu_tonemap(tex, "filmic", scale, ctx=ctx, glare_halo=halo, mesopic=blend)
        # at a photopic adaptation the frame is left as it is: nothing to apply
        assert passes[1].colours(tex, size, adaptation=PHOTOPIC_ANY_SP_CD_M2) is None
        state = passes[1].colours(tex, size, adaptation=adaptation, glare_halo=halo)
    finally:
        for p in passes:
            p.release()
        glare.release()
        tex.release()
    np.testing.assert_array_equal(got, want)
    for key in ("m", "lmes", "sp"):
        assert passes[1].last_state[key] == passes[0].last_state[key]
    assert state == blend
    full = NightVision(ctx)  # with noise and acuity: its blur and noise need its pass
    try:
        with pytest.raises(ParameterError, match="colours"):
            full.colours(tex, size, adaptation=adaptation)
    finally:
        full.release()
