"""Glare (skydome.display.glare, post/glare_*.glsl): the eye's point spread function against
the CIE disability glare equations, a brighter point glares more, and the HDR frame is the
same with glare and without (display only), through Sky and the command line."""

from __future__ import annotations

import math

import numpy as np
import pytest

from skydome import Sky
from skydome.display.exposure import ev100_to_scale
from skydome.display.glare import GpuGlare, glare_fit_error, glare_weights, level_variance_px2
from skydome.display.gpu_tonemap import gpu_tonemap, upload_frame
from skydome.errors import ParameterError
from tests.cli_helpers import run_cli

W, H = 1280, 720
PIXEL_RAD = math.radians(90.0 / W)  # a 90 deg view
#: The PSF check's frame: pixels of a 90 deg, 1280 px wide view, 144 deg across, so that the
#: rings out to 30 deg lie far from the edges (which clamp the pyramid: there, a halo wider
#: than the distance to the edge piles up).
SIDE = 2048


def cie_general(theta_deg, age=25.0, p=0.5):
    """CIE 146:2002 General Disability Glare Equation (L_veil / E, sr^-1), written out here
    from the report (Vos & van den Berg), independently of the package."""
    t = np.asarray(theta_deg, float)
    return 10 / t**3 + (5 / t**2 + 0.1 * p / t) * (1 + (age / 62.5) ** 4) + 0.0025 * p


def stiles_holladay(theta_deg):
    """L_veil = 10 E / theta^2 (theta in deg): the classic disability glare formula."""
    return 10.0 / np.asarray(theta_deg, float) ** 2


def _point_response(ctx, glare, luminance=1.0e6, size=(W, H)):
    """The glared frame (row 0 at the top) of a black frame with one lit pixel at its
    centre."""
    w, h = size
    frame = np.zeros((h, w, 4), np.float32)
    frame[h // 2, w // 2] = luminance
    tex = upload_frame(ctx, frame)
    pass_ = GpuGlare(ctx)
    try:
        out = pass_.apply(tex, (w, h), pixel_angle_rad=PIXEL_RAD, glare=glare)
        data = np.frombuffer(out.read(), np.float32).reshape(h, w, 4)[::-1]
    finally:
        pass_.release()
        tex.release()
    return frame, data


@pytest.mark.gl
def test_eye_psf_matches_cie_disability_glare(ctx):
    # A point source of illuminance E = L * pixel solid angle at the eye: the veil at theta
    # (mean over a thin ring) over E against the CIE general equation. Tolerance 15 %: the
    # Gaussian-sum fit stays within 11 % over 1-30 deg (glare_fit_error over its whole range
    # is larger only near 0.1 deg and the frame's corners), plus the rings' sampling.
    lum = 1.0e6
    _, data = _point_response(ctx, "eye", lum, (SIDE, SIDE))
    e_lux = lum * PIXEL_RAD**2
    y, x = np.mgrid[:SIDE, :SIDE]
    r_px = np.hypot(x - SIDE // 2, y - SIDE // 2)
    veil = data[..., 1]
    for theta in (1.0, 2.0, 3.0, 5.0, 10.0, 20.0, 30.0):
        ring = np.abs(r_px * math.degrees(PIXEL_RAD) - theta) < 0.02 * theta + 0.05
        measured = float(veil[ring].mean()) / e_lux
        assert measured == pytest.approx(float(cie_general(theta)), rel=0.15), theta
        # and within the CIE equations' own spread about Stiles-Holladay (0.65-1.55 here)
        assert 0.6 < measured / float(stiles_holladay(theta)) < 1.65, theta
    # light is conserved: the halo moves it, the frame's total stays within the part the
    # frame's edges cut off (the PSF beyond them)
    total = float(data[..., 1].sum()) / lum
    assert 0.95 < total <= 1.0 + 1e-4


@pytest.mark.gl
def test_brighter_point_glares_more(ctx):
    # The displayed energy around a point (a Venus-like source, then ten times brighter)
    # grows with its illuminance: in the ring 3-30 px from it, the glare adds light in
    # proportion to E (the pass is linear), where without glare there is none.
    y, x = np.mgrid[:H, :W]
    ring = (np.hypot(x - 640, y - 360) > 3) & (np.hypot(x - 640, y - 360) < 30)
    sums = []
    for lum in (1.0e4, 1.0e5):
        frame, data = _point_response(ctx, "eye", lum)
        assert frame[ring].sum() == 0.0
        sums.append(float(data[ring][:, :3].sum()))
    assert sums[0] > 0.0
    assert sums[1] == pytest.approx(10.0 * sums[0], rel=1e-3)


def test_weights_and_modes():
    w_eye, core_eye = glare_weights(PIXEL_RAD, (W, H), "eye")
    w_lens, core_lens = glare_weights(PIXEL_RAD, (W, H), "lens")
    w_off, core_off = glare_weights(PIXEL_RAD, (W, H), "off")
    assert core_off == 1.0 and not w_off.any()
    # the lens scatters ~2 % outside 0.1 deg (the veiling-glare index of a good lens), the
    # eye 15-35 % (CIE general equation integrated from 2 px (0.14 deg) to the frame's corner)
    assert 0.97 < core_lens < 0.995
    assert 0.65 < core_eye < 0.85
    assert (w_eye >= 0).all() and (w_lens >= 0).all()
    assert glare_fit_error(PIXEL_RAD, (W, H), "eye") < 0.7
    assert level_variance_px2(1) == pytest.approx(25.0 / 12.0)
    with pytest.raises(ParameterError, match="glare"):
        glare_weights(PIXEL_RAD, (W, H), "bloom")


@pytest.mark.gl
def test_hdr_frame_unchanged_by_glare():
    # The Sun in view: glare changes the image a lot, the frame's data not at all.
    with Sky("Valletta", "2018-06-21T10:00Z") as sky:
        cam = sky.camera("sun", fov_deg=90.0)
        on = sky.render(cam, 160, 90, tonemap="filmic", glare="eye")
        off = sky.render(cam, 160, 90, tonemap="filmic", glare="off")
        lens = sky.render(cam, 160, 90, tonemap="filmic", glare="lens")
        plain = sky.render(cam, 160, 90)
    assert np.array_equal(on.data, off.data) and np.array_equal(on.data, plain.data)
    assert np.array_equal(lens.data, plain.data)
    assert on.info["glare"] == "eye" and off.info["glare"] == "off"
    assert on.info["exposure_ev100"] == off.info["exposure_ev100"]
    # the Sun's glare brightens the picture, the eye's more than the lens's
    g_on, g_off, g_lens = (f.image.astype(float).mean() for f in (on, off, lens))
    assert g_on > g_lens > g_off


@pytest.mark.gl
def test_cli_glare_and_exr_bit_identical(tmp_path):
    outs = {}
    for g in ("eye", "off"):
        npy, png = tmp_path / f"{g}.npy", tmp_path / f"{g}.png"
        r = run_cli("render", "--sun-elevation", "20", "--look", "sun", "--size", "96x54",
                    "--glare", g, "-o", str(npy), "-o", str(png))  # fmt: skip
        assert r.returncode == 0, r.stderr
        outs[g] = (np.load(npy), png.read_bytes())
    assert np.array_equal(outs["eye"][0], outs["off"][0])
    assert outs["eye"][1] != outs["off"][1]
    r = run_cli("render", "--sun-elevation", "20", "--glare", "bloom", "-o",
                str(tmp_path / "x.png"))  # fmt: skip
    assert r.returncode == 2 and "--glare" in r.stderr


def _b3(t):
    t = np.abs(t)
    return np.where(t < 1, (4 - 6 * t**2 + 3 * t**3) / 6, np.where(t < 2, (2 - t) ** 3 / 6, 0.0))


def test_level_variance_is_the_passes():
    # A float64 1-D twin of the passes (the pyramid is separable): halvings by [1, 3, 3, 1] / 8
    # (post/glare_down.glsl), cubic B-spline enlargements at the texel offsets of
    # post/glare_upsample.glsl; a point's spread after k of each, averaged over its phase in
    # the 2^k blocks, is level_variance_px2(k); the light is conserved.
    n = 512
    for k in (1, 2, 3, 4):
        variances = []
        for phase in range(2**k):
            x = np.zeros(n)
            x[n // 2 + phase] = 1.0
            levels = [x]
            for _ in range(k):
                f = levels[-1]
                idx = np.clip(2 * np.arange((len(f) + 1) // 2)[:, None] - 1 + np.arange(4), 0,
                              len(f) - 1)  # fmt: skip
                levels.append(f[idx] @ np.array([1, 3, 3, 1]) / 8.0)
            z = levels[-1]
            for j in range(k, 0, -1):
                fine = len(levels[j - 1])
                c = (np.arange(fine) + 0.5) / 2 - 0.5
                z = _b3(c[:, None] - np.arange(len(z))[None, :]) @ z
            assert z.sum() == pytest.approx(1.0, abs=1e-12)
            i = np.arange(n)
            mu = (z * i).sum()
            variances.append(float((z * (i - mu) ** 2).sum()))
        assert np.mean(variances) == pytest.approx(level_variance_px2(k), rel=1e-9)


def test_the_eyes_halo_follows_the_magnified_sky():
    # A picture fills about 60 deg of its viewer's sight: a narrower camera magnifies the sky
    # (60 / its field) and the eye's PSF applies in the magnified angles; wide fields, fisheyes
    # and maps are not minified
    from skydome.display.glare import NATURAL_VIEW_DEG, eye_magnification

    assert NATURAL_VIEW_DEG == 60.0
    assert eye_magnification(1.2) == pytest.approx(50.0)
    assert eye_magnification(60.0) == 1.0 and eye_magnification(120.0) == 1.0
    assert eye_magnification(None) == 1.0


@pytest.mark.gl
def test_a_moon_close_up_has_no_eye_halo_beyond_its_disk():
    # The full Moon in a 1.2 deg field (0.52 deg across): with the eye's glare in the sky's
    # own angles the halo's light filled the frame round the disk (a brown glow); magnified,
    # the sky 0.2 deg outside the limb stays within 2 sRGB levels of the frame without glare
    from skydome import Sky

    with Sky("Valletta", "2018-03-01T19:00Z", light_pollution=None) as sky:
        cam = sky.camera("moon", fov_deg=1.2)
        images = {
            g: sky.render(cam, 160, 160, exposure=11.0, tonemap="filmic", glare=g).image
            for g in ("off", "eye")
        }
    corner = (slice(0, 12), slice(0, 12))  # 0.45 deg from the Moon's centre: sky
    diff = np.abs(images["eye"][corner].astype(int) - images["off"][corner].astype(int))
    assert diff.max() <= 2, diff.max()


@pytest.mark.gl
def test_the_tone_map_adds_the_halo_as_the_composite_does():
    """By day the eye's pass leaves the frame as it is, so Sky.render lets the tone map add
    the glare's halo as it reads the frame (GpuToneMapper with a GlareHalo) instead of
    writing the glared frame first: the image must be the composite's, code for code."""
    with Sky("Valletta", "2018-06-21T10:00Z") as sky:
        cam = sky.camera("sun", fov_deg=90.0)
        frame = sky.render(cam, 320, 180, tonemap="filmic", glare="eye")
        assert frame.info["exposure_ev100"] > 10.0  # daylight: the fold is the path taken
        graph = sky.graph
        tex = upload_frame(graph.ctx, frame.data)
        try:
            scale = ev100_to_scale(frame.info["exposure_ev100"])
            glare = graph._glare
            halo = glare.halo(
                tex, (320, 180), pixel_angle_rad=cam.pixel_angle(320, 180), glare="eye"
            )
            assert halo is not None and 0.0 < halo.u_glare_core < 1.0
            folded = gpu_tonemap(tex, "filmic", scale, ctx=graph.ctx, glare_halo=halo)
            composite = gpu_tonemap(
                glare.composite(tex, (320, 180), halo), "filmic", scale, ctx=graph.ctx
            )
        finally:
            tex.release()
    assert np.array_equal(folded, composite)
    # and the user's image is that image (the same frame, exposure and halo)
    assert np.abs(frame.image.astype(int) - folded.astype(int)).max() <= 1
