"""Falling rain and snow near the camera (skydome.weather.particles), through Sky.

The streaks are checked against what a camera records: over one exposure a pixel's mean
covered share is the particles' projected area per unit area of the view (the time-averaged
overlap of a disk crossing a square is its area over the square's, whatever its path), i.e.
the geometric optical depth of the drawn particles, n <pi D^2 / 4> (far - near), with n and
<D^2> from the drop size distribution (Marshall-Palmer above 0.5 mm) or the flakes'
(Gunn-Marshall, a flake 2.15 times its melted drop); the streaks slant with the wind as
atan(wind / fall speed) and lengthen with the shutter time.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from skydome.weather import Weather
from skydome.weather.particles import particle_density
from skydome.weather.snow import flake_size_ratio

pytestmark = pytest.mark.gl

W, H = 480, 270


def particle_images(weather: Weather, *, shutter_s: float = 1 / 60, seed: int | None = None,
                    time_shift: bool = False):  # fmt: skip
    """(covered share (H/2, W) of the ground rows, the layer's info) of ``weather`` seen
    south, 25 deg down, 60 deg wide."""
    from skydome import Sky

    with Sky(sun_elevation_deg=30, weather=weather, shutter_s=shutter_s) as sky:
        camera = sky.camera("south", fov_deg=60, pitch_deg=-25)
        layer = next(la for la in sky.graph.layers if la.name == "precipitation")
        if seed is not None:
            layer.seed = seed
        frame = sky.render(camera, W, H, exposure=None)
        if time_shift:
            sky.graph.update(sky.state)  # the same instant: unchanged
        radiance = layer.particle_radiance()[1]
        layer.enabled = False
        behind = sky.render(camera, W, H, exposure=None).data[H // 2 :, :, 1]
    share = (frame.data[H // 2 :, :, 1] - behind) / (radiance - behind)
    return share, frame.info


def expected_share(weather: Weather, far_m: float) -> float:
    n, slope, smallest, kind = particle_density(weather)
    mean_d2 = (smallest + 1 / slope) ** 2 + 1 / slope**2  # exponential above the smallest
    if kind == "snow":
        mean_d2 *= flake_size_ratio() ** 2
    return n * math.pi / 4 * mean_d2 * 1e-6 * (far_m - 0.3)  # near: 0.3 m


@pytest.mark.parametrize(
    "weather",
    [
        Weather("rain", rain_mm_h=8, wind_m_s=(0.0, 0.0)),
        Weather("rain", rain_mm_h=8, wind_m_s=(4.0, 0.0)),
        Weather("heavy-rain", rain_mm_h=30, wind_m_s=(0.0, 0.0)),
        Weather("snow", snow_mm_h=2, wind_m_s=(1.0, 0.0)),
    ],
    ids=["rain", "rain-wind", "downpour", "snow"],
)
def test_particles_cover_their_projected_area(weather):
    """Measured 0.90-0.96 of it (the lattice's cubes miss the few streaks that began beyond
    the MAX_CUBES they look back through, and a seeded sample of a few thousand particles
    scatters by a few per cent): within 25 %."""
    share, info = particle_images(weather)
    ratio = share.mean() / expected_share(weather, info["particles_far_m"])
    assert 0.75 < ratio < 1.25, ratio


def streak_angle_deg(share: np.ndarray) -> float:
    """The streaks' direction in the image (deg from the vertical, positive leaning right at
    the bottom) from the structure tensor of the covered share."""
    gy, gx = np.gradient(share.astype(np.float64))
    jxx, jyy, jxy = (gx * gx).sum(), (gy * gy).sum(), (gx * gy).sum()
    # the gradients run across the streaks: the streaks along the tensor's weaker axis
    theta = 0.5 * math.atan2(2 * jxy, jxx - jyy)  # the gradients' main direction from x
    return math.degrees(theta)


def test_streaks_slant_with_the_wind():
    """Looking south, a wind towards the east (the image's left) carries the drops left as
    they fall: the streaks lean by about atan(4 / v) ~ 35-45 deg for the 1-2 mm drops that
    make most of the covered share (v = 4-6.5 m/s); without wind they hang vertical."""
    calm, _ = particle_images(Weather("rain", rain_mm_h=8, wind_m_s=(0.0, 0.0)))
    windy, _ = particle_images(Weather("rain", rain_mm_h=8, wind_m_s=(4.0, 0.0)))
    assert abs(streak_angle_deg(calm)) < 8.0
    angle = streak_angle_deg(windy)
    assert 20.0 < abs(angle) < 60.0, angle
    assert np.sign(angle) != 0


def test_streaks_lengthen_with_the_shutter():
    """A drop falls v t in an exposure t: at 1/30 s a 1 mm drop 1-2 m away draws a streak
    tens of pixels long here, at 1/500 s a few: the covered share stays correlated over 8
    pixels down the image at the long shutter (measured 0.29), hardly at the short one
    (0.05)."""

    def correlation(share, lag=8):
        a, b = share[:-lag], share[lag:]
        return float(((a - a.mean()) * (b - b.mean())).mean() / share.var())

    weather = Weather("rain", rain_mm_h=8, wind_m_s=(0.0, 0.0))
    long_exposure, _ = particle_images(weather, shutter_s=1 / 30)
    short_exposure, _ = particle_images(weather, shutter_s=1 / 500)
    assert correlation(long_exposure) > 0.2
    assert correlation(long_exposure) > 3 * correlation(short_exposure)


def test_particles_are_seeded():
    weather = Weather("rain", rain_mm_h=8)
    a, _ = particle_images(weather, seed=3)
    b, _ = particle_images(weather, seed=3)
    c, _ = particle_images(weather, seed=4)
    assert np.array_equal(a, b)
    assert not np.allclose(a, c)
