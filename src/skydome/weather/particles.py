"""Falling rain and snow near the camera: a layer of particles (``weather/precipitation.glsl``).

What a camera records in one exposure: each drop or flake a streak as long as it falls (and
drifts with the wind) in the exposure, covering each pixel on its path for the share of the
exposure it spends there (Garg & Nayar 2004, "Photometric model of a rain drop", and their
2007 streak model), with the radiance of the light around it: a drop refracts the sky and the
ground over nearly a hemisphere towards the eye (about 94 % of their mean radiance, Garg &
Nayar 2004), a flake scatters them (its albedo, 0.9). The light around them is the sky that is
drawn (the cloud layer's probe, a ``SkyLightService``).

Particles: Marshall-Palmer drops of 0.5 mm and more (the ones a camera resolves near it), or
Gunn-Marshall flakes of 0.2 mm of melted water and more; their number per m^3 from the
distributions; seeded, deterministic, falling with the time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from skydome.core.cameras import CameraInputs
from skydome.core.layer import BehindInputs, DrawContext, Layer
from skydome.core.services import SkyLightService
from skydome.errors import ParameterError, check_range
from skydome.gpu.inputs import ShaderInputs
from skydome.physics.constants import J2000_JD
from skydome.weather.params import Weather
from skydome.weather.rain import MP_N0, marshall_palmer_slope_per_mm
from skydome.weather.snow import FLAKE_DENSITY_KG_M3, flake_size_ratio, gunn_marshall_parameters

#: The smallest drop (mm) and flake (mm of melted water) drawn.
SMALLEST_DROP_MM = 0.5
SMALLEST_FLAKE_MM = 0.2
#: A drop's radiance over the mean radiance around it (Garg & Nayar 2004); a flake's albedo.
DROP_RADIANCE_RATIO = 0.94
FLAKE_ALBEDO = 0.9
#: Exposure times (s) a camera may have.
EXPOSURE_RANGE_S = (1e-5, 1.0)


@dataclass(frozen=True)
class PrecipitationInputs(ShaderInputs):
    """``weather/precipitation.glsl``'s uniforms (its comments say what each holds)."""

    u_particles: tuple[float, float, float, float]
    u_motion: tuple[float, float, float, float]
    u_particle_radiance: tuple[float, float, float, float]
    u_particle_scale: tuple[float, float]
    u_pixel_rad: float
    u_seed: float
    u_far_m: float


def particle_density(weather: Weather) -> tuple[float, float, float, str]:
    """(particles per m^3 drawn, the slope of their sizes 1/mm, the smallest mm, kind) of a
    weather's precipitation: its snow if it snows, else its rain."""
    if weather.snow_mm_h > 0:
        n0, lam = (float(v) for v in gunn_marshall_parameters(weather.snow_mm_h))
        smallest, kind = SMALLEST_FLAKE_MM, "snow"
    else:
        n0 = MP_N0
        lam = float(marshall_palmer_slope_per_mm(max(weather.rain_mm_h, 1e-9)))
        smallest, kind = SMALLEST_DROP_MM, "rain"
    # an exponential distribution has N0 / Lambda exp(-Lambda D) particles above D
    return n0 / lam * math.exp(-lam * smallest), lam, smallest, kind


def resolved_distance_m(pixel_rad: float, smallest_mm: float) -> float:
    """How far (m) particles are drawn: where a typical one (three times the smallest) fills
    a third of a pixel, within 2-20 m. Farther, the particles are the rain volume's haze."""
    return min(max(3.0 * smallest_mm * 1e-3 / (pixel_rad / 3.0), 2.0), 20.0)


class PrecipitationLayer(Layer):
    """Rain streaks or falling snow near the camera (volume stage, after the clouds): the
    ``weather``'s rate, its wind, a camera's ``exposure_s`` (s), a ``seed``."""

    name = "precipitation"
    stage = "volume"

    def __init__(self, weather: Weather, *, exposure_s: float = 1.0 / 60.0, seed: int = 1,
                 enabled: bool = True):  # fmt: skip
        super().__init__(enabled=enabled)
        if not isinstance(weather, Weather):
            raise ParameterError(f"weather must be a Weather, got {weather!r}")
        if not weather.precipitates:
            raise ParameterError("a precipitation layer needs rain or snow in its weather")
        self.weather = weather
        self.exposure_s = check_range("exposure_s", exposure_s, *EXPOSURE_RANGE_S, "s")
        if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
            raise ParameterError(f"seed must be a non-negative integer, got {seed!r}")
        self.seed = seed
        self.time_s = 0.0
        self._far_m = None

    def update(self, state) -> None:
        jd = state.julian_day_utc
        # an hour's cycle keeps float32 its milliseconds (the pattern repeats hourly)
        self.time_s = 0.0 if jd is None else ((jd - J2000_JD) * 86400.0) % 3600.0

    def particle_radiance(self) -> tuple[float, float, float, float]:
        """A particle's radiance (cd/m^2 per channel): the ratio of its kind times the mean
        radiance of the sky that is drawn around it (0 without a sky light service)."""
        service = self.graph.find_service(SkyLightService) if self.graph is not None else None
        if service is None:
            return (0.0, 0.0, 0.0, 0.0)
        ratio = FLAKE_ALBEDO if self.weather.snow_mm_h > 0 else DROP_RADIANCE_RATIO
        return tuple(ratio * v for v in service.ambient_radiance())

    def draw(self, frame: DrawContext) -> None:
        density, slope, smallest, kind = particle_density(self.weather)
        w, h = frame.frame_size
        fov = getattr(frame.camera, "fov_deg", None)
        pixel_rad = math.radians(fov) / w if fov is not None else math.pi / h
        wind = self.weather.wind_m_s
        scale = flake_size_ratio() if kind == "snow" else 1.0
        self._far_m = resolved_distance_m(pixel_rad, smallest * scale)
        inputs = PrecipitationInputs(
            u_particles=(density, slope, smallest, 1.0 if kind == "snow" else 0.0),
            u_motion=(wind[0], wind[1], self.exposure_s, self.time_s),
            u_particle_radiance=self.particle_radiance(),
            u_particle_scale=(flake_size_ratio(FLAKE_DENSITY_KG_M3), max(frame.altitude_m, 0.0)),
            u_pixel_rad=pixel_rad,
            u_seed=float(self.seed % 997),
            u_far_m=self._far_m,
        )
        fpass = self.full_screen_pass(
            frame.ctx, "weather/precipitation.glsl",
            (CameraInputs, BehindInputs, PrecipitationInputs), frame.camera,
        )  # fmt: skip
        fpass.draw(frame.fbo, frame.view, self.behind_inputs(frame), inputs)

    def info(self) -> dict:
        density, _, _, kind = particle_density(self.weather)
        return {
            "particles": kind,
            "particles_per_m3": density,
            "particles_far_m": self._far_m,
            "exposure_s": self.exposure_s,
        }
