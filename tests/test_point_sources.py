"""The point-source pass: light conserved at every resolution and camera model (tiles, the
equirect seam, cube faces), the PSF's pixel integrals against float64 erf, centroids at the
projected position, the seeing's width, occluding disks, and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from skydome import Sky
from skydome.celestial.point_sources import FWHM_PER_SIGMA, PSF_EXTENT_SIGMA, PointSources
from skydome.core.cameras import (
    CubemapCamera,
    DirectionsCamera,
    EquirectCamera,
    FisheyeCamera,
    PerspectiveCamera,
    direction_from_angles,
)
from skydome.core.layer import Layer
from skydome.errors import ParameterError

VALLETTA = (35.8989, 14.5146, 56.0)


class SourcesLayer(Layer):
    """Chosen sources through the pass, nothing else."""

    name = "sources"
    stage = "space"

    def __init__(self, directions, channels, **kwargs):
        super().__init__()
        self.directions = np.asarray(directions, float)
        self.channels = np.asarray(channels, float)
        self.kwargs = kwargs
        self.points = None

    def draw(self, frame):
        if self.points is None:
            self.points = PointSources(frame.ctx)
        self.points.draw(frame, self.directions, self.channels, **self.kwargs)

    def release(self):
        super().release()
        if self.points is not None:
            self.points.release()


def render(camera, w, h, directions, channels=None, **kwargs):
    """A frame (top row first) of the sources alone, its pixel directions and solid angles."""
    directions = np.atleast_2d(directions)
    if channels is None:
        channels = np.tile([1.0, 2.0, 3.0, 4.0], (len(directions), 1))
    sky = Sky(VALLETTA, "2018-03-01T23:00Z", layers=[SourcesLayer(directions, channels, **kwargs)])
    data = sky.render(camera, w, h, exposure=None).data.astype(np.float64)
    sky.graph.release()
    fw, fh = camera.frame_size(w, h)
    rows, cols = np.mgrid[0:fh, 0:fw]
    gx, gy = cols + 0.5, (fh - 1 - rows) + 0.5  # GL pixel centres of the top-first rows
    dirs, sees = camera.directions(gx, gy, fw, fh)
    omega = camera.solid_angle(dirs, fw, fh)
    return data, dirs, omega, sees, (gx, gy)


def fluxes(data, dirs, omega, sources, radius_deg):
    """Flux (radiance x pixel solid angle, summed) within radius_deg of each source."""
    flux = data * omega[..., None]
    cos_r = math.cos(math.radians(radius_deg))
    return np.array([flux[(dirs @ np.asarray(s)) > cos_r].sum(axis=0) for s in sources])


# Sources at awkward places: on the equirect seam (both sides), on the border of the two
# 2048-pixel tiles of a 4096-wide frame (azimuth 180), near the zenith, near the horizon.
AWKWARD = [
    direction_from_angles(30.0, 0.01),
    direction_from_angles(12.0, 359.99),
    direction_from_angles(45.0, 180.0),
    direction_from_angles(-20.0, 180.04),
    direction_from_angles(80.0, 90.0),
    direction_from_angles(2.0, 270.0),
]


@pytest.mark.parametrize("w", [256, 1024, 4096])
def test_equirect_flux_is_the_illuminance_at_any_resolution(w):
    # The weights of a source sum to 1 and the radiance is weight / the pixel's solid angle:
    # the flux is the illuminance up to float32 rounding (1e-5), whole on the seam and on
    # the tile border (4096 x 2048 is two tiles).
    data, dirs, omega, _, _ = render(EquirectCamera(), w, w // 2, AWKWARD)
    got = fluxes(data, dirs, omega, AWKWARD, radius_deg=max(3.0, 8 * 360.0 / w))
    np.testing.assert_allclose(got, np.tile([1.0, 2.0, 3.0, 4.0], (len(AWKWARD), 1)), rtol=1e-4)


@pytest.mark.parametrize(
    "camera,w,h",
    [
        (PerspectiveCamera(fov_deg=40, yaw_deg=90, pitch_deg=30), 320, 200),
        (PerspectiveCamera(fov_deg=100, yaw_deg=90, pitch_deg=30), 1280, 720),
        (FisheyeCamera(), 600, 600),
    ],
)
def test_flux_in_other_camera_models(camera, w, h):
    # Sources inside the field (one in a perspective frame's corner, where pixels are
    # smallest in solid angle: cos^3 of the off-axis angle).
    inside = [direction_from_angles(30.0, 90.0), direction_from_angles(40.0, 100.0)]
    if isinstance(camera, PerspectiveCamera):
        fw, fh = camera.frame_size(w, h)
        corner, _ = camera.directions(0.9 * fw, 0.85 * fh, fw, fh)
        inside.append(corner)
    data, dirs, omega, _, _ = render(camera, w, h, inside)
    got = fluxes(data, dirs, omega, inside, radius_deg=2.0)
    np.testing.assert_allclose(got[:, 1], 2.0, rtol=1e-4)


def test_cubemap_flux_across_a_face_edge():
    # Each face draws the source on its own extended plane and writes its own pixels: a
    # source on the +X / +Y edge loses nothing measurable (the two planes' pixel grids meet
    # at the edge with the same scale). At a corner (three faces, 270 degrees of pixel plane
    # around a point) a quarter is lost: documented, not tested.
    cam = CubemapCamera()
    sources = [direction_from_angles(20.0, 45.0), direction_from_angles(44.9, 0.0)]
    data, dirs, omega, _, _ = render(cam, 6 * 512, 512, sources)
    got = fluxes(data, dirs, omega, sources, radius_deg=2.0)
    np.testing.assert_allclose(got[:, 1], 2.0, rtol=2e-3)


def axis_weights(c: float, sigma: float):
    """Float64 (math.erf) shares of a Gaussian centred at frame position c (pixels) on the
    whole pixels of its quad along one axis: the pixels' first edges and the shares."""
    half = math.ceil(PSF_EXTENT_SIGMA * sigma)

    def cdf(u):
        return 0.5 * (1.0 + math.erf(u / (sigma * math.sqrt(2.0))))

    lo, hi = math.floor(c) - half, math.floor(c) + 1 + half
    edges = np.arange(lo, hi + 1)
    return edges[:-1], np.diff([cdf(e - c) for e in edges]) / (cdf(hi - c) - cdf(lo - c))


@pytest.mark.parametrize(
    "sigma,azimuth_deg,w",
    [
        (1.7, 123.4, 720),  # a quad wider than 8 px: erf per pixel
        (0.8, 123.4, 720),  # 7 x 7: weights per column and row, a point sprite
        (0.8, 0.05, 720),  # on the seam: the copy one frame width over
        (0.8, 180.02, 4096),  # on the border of the two 2048-pixel tiles: quads
    ],
)
def test_pixel_weights_are_the_gaussian_integrals(sigma, azimuth_deg, w):
    # The shader's erf is Abramowitz & Stegun 7.1.26 (|error| <= 1.5e-7): each pixel's share
    # of the light equals the float64 integral of the Gaussian over the pixel divided by its
    # integral over the quad (math.erf), within 2e-6 of the total. The quad: whole pixels
    # from the source's pixel out to ceil(3 sigma) (PSF_EXTENT_SIGMA), and nothing beyond.
    assert PSF_EXTENT_SIGMA == 3.0
    h = w // 2
    source = direction_from_angles(0.3, azimuth_deg)  # near the equator: square pixels
    cam = EquirectCamera()
    data, _, omega, _, (gx, gy) = render(cam, w, h, source, [[0, 1.0, 0, 0]], psf_sigma_px=sigma)
    share = data[..., 1] * omega
    x, y, _ = cam.project(source, w, h)
    ex, wx = axis_weights(float(x), sigma)
    ey, wy = axis_weights(float(y), sigma)
    expected = np.zeros_like(share)
    for i, a in zip(ex, wx, strict=True):
        for j, b in zip(ey, wy, strict=True):
            expected[(gx == i % w + 0.5) & (gy == j + 0.5)] = a * b
    assert share.sum() == pytest.approx(1.0, abs=1e-5)
    np.testing.assert_allclose(share, expected, atol=2e-6)


def test_sources_just_off_the_frame_light_the_pixels_they_reach():
    # Sources 0.6 and 1.9 px beyond the left edge, 0.4 px beyond the right one and 0.9 px
    # above the top of a perspective frame (culled on the CPU by their quads, not their
    # centres): the flux inside the frame is the illuminance times the float64 share of the
    # PSF on the frame's pixels (axis_weights), 1e-4 (float32; shares from 0.8 % up).
    cam, w, h = PerspectiveCamera(fov_deg=60, yaw_deg=100, pitch_deg=20), 320, 200
    positions = [(-0.6, 100.3), (320.4, 50.7), (150.2, 200.9), (-1.9, 20.2)]
    sources = [cam.directions(px, py, w, h)[0] for px, py in positions]
    data, dirs, omega, _, _ = render(cam, w, h, sources)
    got = fluxes(data, dirs, omega, sources, radius_deg=2.0)[:, 1]
    for k, (px, py) in enumerate(positions):
        inside = 1.0
        for c, n in ((px, w), (py, h)):
            edges, share = axis_weights(c, 0.8)
            inside *= share[(edges >= 0) & (edges < n)].sum()
        assert 0.001 < inside < 0.9
        assert got[k] == pytest.approx(2.0 * inside, rel=1e-4), (px, py)


def test_centroid_is_the_projected_position():
    # A pixel-integrated Gaussian's centroid is its centre (the discretization bias of a
    # sigma = 0.8 px Gaussian, ~exp(-2 pi^2 sigma^2) = 3e-6 px, and the truncation at the
    # quad's edges, 3.75-5 sigma out, are far below 0.01 px); the position is the CPU's
    # float64 placement, held to projection.project.
    cams = [
        (EquirectCamera(), 2048, 1024),
        (PerspectiveCamera(fov_deg=60, yaw_deg=100, pitch_deg=35), 640, 480),
        (FisheyeCamera(), 512, 512),
    ]
    sources = [direction_from_angles(37.3, 95.1), direction_from_angles(23.9, 111.7)]
    for cam, w, h in cams:
        data, dirs, omega, _, (gx, gy) = render(cam, w, h, sources)
        fw, fh = cam.frame_size(w, h)
        x, y, _ = cam.project(np.array(sources), fw, fh)
        for k, s in enumerate(sources):
            near = (dirs @ s) > math.cos(math.radians(3.0))
            f = data[..., 1] * near
            cx, cy = (f * gx).sum() / f.sum(), (f * gy).sum() / f.sum()
            assert abs(cx - x[k]) < 0.01 and abs(cy - y[k]) < 0.01, (cam.name, cx - x[k], cy - y[k])


def test_seeing_adds_in_quadrature():
    # The image's variance along x and y is that of the Gaussian of sigma^2 = sigma_psf^2 +
    # (the seeing's sigma in pixels)^2, integrated over whole pixels (which adds ~1/12) and
    # truncated to the quad (ceil(3 sigma) pixels beyond the source's pixel: 1 % less
    # variance here), computed here in float64 with math.erf: 0.05 % (the radiance, not the
    # flux, is weighted: cos(elevation) changes by 1e-4 across the disk at the equator; the
    # seeing's scale comes from finite differences of the projection).
    w, h = 4096, 2048
    px_rad = 2 * math.pi / w
    seeing_arcsec = 3.0 * px_rad * 648000 / math.pi * FWHM_PER_SIGMA  # 3 px sigma
    source = direction_from_angles(0.0, 77.0)
    data, _, _, _, (gx, gy) = render(
        EquirectCamera(), w, h, source, psf_sigma_px=0.8, seeing_fwhm_arcsec=seeing_arcsec
    )
    x, y, _ = EquirectCamera().project(source, w, h)
    s = math.hypot(0.8, 3.0)
    half = math.ceil(PSF_EXTENT_SIGMA * s)
    f = data[..., 1]
    box = f > 0
    f, gx, gy = f[box], gx[box], gy[box]
    for g, c in ((gx, float(x)), (gy, float(y))):
        edges = np.arange(math.floor(c) - half, math.floor(c) + half + 2, dtype=float)
        cdf = np.array([0.5 * math.erfc(-(e - c) / (s * math.sqrt(2.0))) for e in edges])
        p = np.diff(cdf) / (cdf[-1] - cdf[0])
        centres = edges[:-1] + 0.5
        expected = (p * (centres - (p * centres).sum()) ** 2).sum()
        assert expected == pytest.approx(s**2 + 1.0 / 12.0, rel=0.03)  # nearly untruncated
        assert np.ptp(g) == 2 * half  # the quad, and nothing beyond
        mean = (f * g).sum() / f.sum()
        var = (f * (g - mean) ** 2).sum() / f.sum()
        assert var == pytest.approx(expected, rel=5e-4)  # measured: 2e-5


def test_occluders_hide_the_pixels_behind_them():
    moon = direction_from_angles(40.0, 200.0)
    radius = math.radians(0.26)
    behind = moon
    beside = direction_from_angles(40.0 + 1.0, 200.0)
    cam = PerspectiveCamera(fov_deg=5, yaw_deg=200, pitch_deg=40.5)
    data, dirs, omega, _, _ = render(cam, 400, 400, [behind, beside], occluder=[(moon, radius)])
    got = fluxes(data, dirs, omega, [behind, beside], radius_deg=0.2)
    assert np.all(got[0] == 0.0)
    np.testing.assert_allclose(got[1], [1.0, 2.0, 3.0, 4.0], rtol=1e-4)


def test_a_directions_camera_draws_nothing():
    cam = DirectionsCamera(np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]))
    sky = Sky(VALLETTA, "2018-03-01T23:00Z", layers=[SourcesLayer([[0, 0, 1.0]], [[1.0] * 4])])
    assert np.all(sky.render(cam, 0, 0, exposure=None).data == 0.0)


def test_bad_input_is_refused(ctx):
    points = PointSources(ctx)
    frame = None  # checked before the frame is used
    with pytest.raises(ParameterError, match="psf_sigma_px"):
        points.draw(frame, [[0, 0, 1.0]], [[1.0] * 4], psf_sigma_px=0.0)
    with pytest.raises(ParameterError, match="seeing"):
        points.draw(frame, [[0, 0, 1.0]], [[1.0] * 4], seeing_fwhm_arcsec=-1.0)
    with pytest.raises(ParameterError, match=r"\(N, 3\)"):
        points.draw(frame, [[0, 0, 1.0]], [[1.0] * 3])
    with pytest.raises(ParameterError, match="finite"):
        points.draw(frame, [[0, 0, np.nan]], [[1.0] * 4])
    with pytest.raises(ParameterError, match="occluder"):
        points.draw(frame, [[0, 0, 1.0]], [[1.0] * 4], occluder=[((0, 0, 0), 0.1)])
    points.release()
