"""Metering modes (skydome.display.exposure, post/log_luminance.glsl, the frame graph): the
eye's key of Krawczyk et al. 2005, the weights on the GPU against their NumPy twin, and what
the user sees through Sky and the command line: a dark blue-grey moonless sky, a Moon
close-up exposed for the Moon, daylight unchanged."""

from __future__ import annotations

import math

import numpy as np
import pytest
from PIL import Image

from skydome import Sky
from skydome.core.cameras import FisheyeCamera
from skydome.display.exposure import (
    DEFAULT_KEY,
    SPOT_AREA_FRACTION,
    eye_key,
    log_average_luminance,
    metered_luminance,
    metering_weights,
)
from skydome.display.gpu_exposure import GpuExposure, GridMean
from skydome.display.gpu_tonemap import upload_frame
from skydome.errors import ParameterError
from tests.cli_helpers import run_cli

LUMA = np.array([0.2126, 0.7152, 0.0722])


def test_eye_key_is_krawczyk_2005():
    # Krawczyk, Myszkowski & Seidel 2005: key = 1.03 - 2 / (2 + log10(L + 1)), written out
    # here independently; capped at middle grey 0.18 (Reinhard 2002) from 1.25 cd/m^2 up.
    for lum in (0.0, 2e-4, 0.01, 0.1, 1.0):
        assert eye_key(lum) == pytest.approx(1.03 - 2.0 / (2.0 + math.log10(lum + 1.0)), 1e-12)
    assert eye_key(2e-4) == pytest.approx(0.0301, abs=1e-4)  # a moonless sky
    assert eye_key(1.0) == pytest.approx(0.161, abs=1e-3)
    for lum in (1.3, 100.0, 1e4, 1e9):  # daylight keeps today's key
        assert eye_key(lum) == DEFAULT_KEY
    with pytest.raises(ParameterError):
        eye_key(-1.0)


def _disc_frame(h=180, w=320):
    """A dim surround (0.1 cd/m^2) with a bright disc (1000 cd/m^2) filling the spot."""
    y, x = np.mgrid[:h, :w] + 0.5
    d2 = (y - h / 2) ** 2 + (x - w / 2) ** 2
    frame = np.zeros((h, w, 4), np.float32)
    lum = np.where(d2 <= 1.5 * SPOT_AREA_FRACTION * w * h / math.pi, 1000.0, 0.1)
    frame[..., :3] = lum[..., None]
    return frame


def test_metering_weights_and_numpy_twin():
    frame = _disc_frame()
    avg = log_average_luminance(frame)
    assert metered_luminance(frame, "average") == avg == metered_luminance(frame, "eye")
    # The spot lies inside the disc: it reads the disc alone.
    assert metered_luminance(frame, "spot") == pytest.approx(1000.0, rel=1e-7)  # float32 in
    center = metered_luminance(frame, "center")
    assert avg < center < 1000.0
    w = metering_weights(180, 320, "spot")
    assert w.sum() / w.size == pytest.approx(SPOT_AREA_FRACTION, rel=0.05)
    with pytest.raises(ParameterError, match="metering"):
        metering_weights(4, 4, "matrix")


@pytest.mark.gl
def test_gpu_metering_matches_numpy(ctx):
    frame = _disc_frame()
    meter = GpuExposure(ctx)
    tex = upload_frame(ctx, frame)
    try:
        for mode in ("average", "center", "spot"):
            meter.measure(tex, mode)
            # The GPU reads a 256 x 128 grid of the 320 x 180 frame: the weighted
            # log-averages agree to a few per cent (sampling of the disc's edge).
            assert meter.read() == pytest.approx(metered_luminance(frame, mode), rel=0.05), mode
    finally:
        tex.release()
        meter.release()


@pytest.fixture(scope="module")
def paranal():
    with Sky("Paranal", "2024-07-05T04:00Z") as sky:
        yield sky


@pytest.mark.gl
def test_moonless_paranal_is_dark_and_blue_grey(paranal):
    # The check: mean sRGB below 70 with blue >= red (it was 136, tan: R 160, B 109).
    frame = paranal.render(FisheyeCamera(), 320, 320, tonemap="filmic")
    lit = frame.data[..., :3].sum(-1) > 0
    rgb = frame.image[lit].astype(float).mean(0)
    assert frame.info["metering"] == "eye"
    assert rgb.mean() < 70.0
    assert rgb[2] >= rgb[0]
    # the camera's average metering shows it as before: bright and tan
    before = paranal.render(FisheyeCamera(), 320, 320, tonemap="filmic", metering="average")
    old = before.image[lit].astype(float).mean(0)
    assert old.mean() > 100.0 and old[0] > old[2]
    # the HDR data are the same whatever the metering
    assert np.array_equal(frame.data, before.data)


@pytest.mark.gl
def test_moonlit_paranal_is_dim_and_blue(paranal):
    # Under the full Moon (2024-06-22T04:00Z) the sky is ~0.03-0.1 cd/m^2: the eye's key is
    # ~0.04 and the picture dim and blue (it was a daylight-bright blue at mean sRGB 145).
    with paranal.at("2024-06-22T04:00Z") as sky:
        frame = sky.render(FisheyeCamera(), 320, 320, tonemap="filmic")
    lit = frame.data[..., :3].sum(-1) > 0
    rgb = frame.image[lit].astype(float).mean(0)
    assert 30.0 < rgb.mean() < 90.0
    assert rgb[2] > rgb[0] + 5.0


@pytest.mark.gl
def test_daylight_unchanged_by_eye_metering():
    # Above 1.25 cd/m^2 the eye metering is the average metering: the same image, bit for bit.
    with Sky(sun_elevation_deg=30.0) as sky:
        a = sky.render(width=96, height=54, tonemap="filmic", metering="average", glare="off")
        b = sky.render(width=96, height=54, tonemap="filmic", glare="off")
    assert np.array_equal(a.image, b.image)
    assert a.info["exposure_ev100"] == b.info["exposure_ev100"]


@pytest.mark.gl
def test_full_moon_close_up_center_and_spot_metering(tmp_path):
    # Full Moon 2024-06-22 01:08 UTC; at 04:00Z it is high over Paranal. Centre-weighted
    # metering picks the Moon (the check: the Moon's median between 150 and 230).
    png, npy = tmp_path / "moon.png", tmp_path / "moon.npy"
    args = ("render", "--place", "Paranal", "--time", "2024-06-22T04:00Z", "--look", "moon",
            "--fov", "1", "--size", "320x180", "-o", str(png), "-o", str(npy))  # fmt: skip
    r = run_cli(*args, "--metering", "center")
    assert r.returncode == 0, r.stderr
    assert "center metering" in r.stdout
    data = np.load(npy)
    image = np.asarray(Image.open(png)).astype(float)
    moon = data[..., :3] @ LUMA > 100.0  # the Moon ~3000 cd/m^2, the sky beside it < 1
    assert 0.3 < moon.mean() < 0.5  # a 0.52 deg disc in a 1 x 0.56 deg frame: 0.38
    median = float(np.median(image[moon].mean(-1)))
    assert 150.0 <= median <= 230.0, median
    # Spot metering reads the middle of the disc and puts it at middle grey: the exposure
    # of the photographers' "looney 11" rule for the sunlit Moon (f/11 at 1/ISO s: EV100 =
    # log2(11^2 * 100) = 13.56), within 0.5 EV (the Moon's albedo varies by 2x over the disc).
    r = run_cli(*args, "--metering", "spot")
    assert r.returncode == 0, r.stderr
    ev = float(r.stdout.split("exposure EV100 ")[1].split()[0])
    assert ev == pytest.approx(math.log2(11.0**2 * 100.0), abs=0.5)
    # The default (eye) in a magnified view (a 1 deg field, under NARROW_FIELD_DEG): the
    # observer at the telescope adapts to what fills it, the centre: the check with
    # the default, and the same exposure as centre-weighted metering (the Moon is > 1.25
    # cd/m^2, where the eye's key is the average's 0.18). The whole frame's average would
    # burn the Moon (its median > 240), as it did before.
    r = run_cli(*args)
    assert r.returncode == 0, r.stderr
    median_default = float(np.median(np.asarray(Image.open(png)).astype(float)[moon].mean(-1)))
    assert 150.0 <= median_default <= 230.0, median_default
    assert median_default == pytest.approx(median, abs=3.0)
    r = run_cli(*args, "--metering", "average")
    assert np.median(np.asarray(Image.open(png))[moon].mean(-1)) > 240.0


def test_cli_refuses_a_bad_metering(tmp_path):
    r = run_cli("render", "--sun-elevation", "20", "--metering", "matrix", "-o",
                str(tmp_path / "x.png"))  # fmt: skip
    assert r.returncode == 2
    assert "--metering" in r.stderr and "matrix" in r.stderr
    assert not (tmp_path / "x.png").exists()


def test_the_eye_meters_a_magnified_views_centre():
    from skydome.display.exposure import NARROW_FIELD_DEG, metering_weighting

    assert NARROW_FIELD_DEG == 5.0
    assert metering_weighting("eye", 1.0) == "center"
    assert metering_weighting("eye", 5.0) == "eye" and metering_weighting("eye", None) == "eye"
    assert metering_weighting("spot", 1.0) == "spot"
    assert metering_weighting("average", 1.0) == "average"


@pytest.mark.gl
def test_grid_mean_is_the_mean_of_every_sample(ctx):
    """GridMean (post/grid_mean.glsl, two passes) against NumPy's float64 mean of the same
    grid: float32 sums of 256 and 128 values, so within a few 1e-7 of the mean's scale."""
    rng = np.random.default_rng(7)
    grid = rng.normal(3.0, 2.0, size=(128, 256, 4)).astype(np.float32)
    grid[..., 2] = rng.random((128, 256)) > 0.3  # a weight channel of ones and zeros
    tex = ctx.texture((256, 128), 4, grid.tobytes(), dtype="f4")
    mean = GridMean(ctx)
    try:
        mean.average(tex)
        got = mean.read()
    finally:
        mean.release()
        tex.release()
    want = grid.reshape(-1, 4).astype(np.float64).mean(axis=0)
    np.testing.assert_allclose(got, want, rtol=0, atol=2e-6 * np.abs(grid).max())
    with pytest.raises(ParameterError, match="blocks"):
        GridMean(ctx, (250, 128))
