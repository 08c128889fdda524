"""The lights of a sky at one instant, as typed objects: what every layer reads.

A :class:`SkyState` holds the Sun, the Moon (or None) and the weather that bends their
light; the scene makes it from the astronomy (``skydome.scene.state``) or from a Sun
elevation alone. Nothing in it depends on a camera.

Units: directions are unit ENU vectors (x east, y north, z up); angles in radians unless a
name says ``_deg``; illuminances in lux outside the atmosphere on a surface facing the
light; distances in km.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from skydome.physics.constants import AU_KM, STANDARD_PRESSURE_HPA, STANDARD_TEMPERATURE_C
from skydome.physics.geometry import azimuth_deg, elevation_deg
from skydome.physics.refraction import refraction_scale


@dataclass(frozen=True)
class Light:
    """A source beyond the atmosphere as the observer sees it at one instant.

    ``direction`` is the apparent (refracted) one, where the disk's centre is seen;
    ``direction_true`` the airless one, from where its light reaches the air.
    ``illuminance_lux`` is outside the atmosphere, at normal incidence.
    ``relative_spectrum``: the light's spectrum over the solar one as a function of
    wavelength (nm), any scale (the Moon's: its spectral albedo); None for sunlight.
    """

    name: str
    direction: np.ndarray
    direction_true: np.ndarray
    distance_km: float
    angular_radius_rad: float
    illuminance_lux: float
    relative_spectrum: Callable[[np.ndarray], np.ndarray] | None = None

    @property
    def elevation_deg(self) -> float:
        """Apparent elevation above the horizon, degrees."""
        return elevation_deg(self.direction)

    @property
    def azimuth_deg(self) -> float:
        """Azimuth from north through east, degrees in [0, 360)."""
        return azimuth_deg(self.direction)

    @property
    def distance_au(self) -> float:
        return self.distance_km / AU_KM


@dataclass(frozen=True)
class MoonView:
    """How the Moon is lit and turned at one instant (its disk is drawn from this).

    ``to_sun``: unit ENU vector from the Moon towards the Sun; ``frame``: 3x3 matrix whose
    columns are the Moon-fixed axes in ENU (x towards selenographic longitude 0, latitude 0;
    y towards longitude 90 E; z the north pole), from the libration and the axis position
    angle (Meeus ch. 53). ``earthshine_lux``: the Earth's illuminance at the Moon, from the
    Earth's phase seen from the Moon.
    """

    phase_angle_rad: float
    illuminated_fraction: float
    bright_limb_angle_rad: float
    earth_phase_angle_rad: float
    to_sun: np.ndarray
    frame: np.ndarray
    libration_rad: tuple[float, float, float]  # (l, b, P)
    earthshine_lux: float


@dataclass(frozen=True)
class SolarEclipseView:
    """The Moon in front of the Sun at one instant (``skydome.astro.eclipses``).

    ``hidden_fraction``: the fraction of the Sun's limb-darkened luminous flux the Moon hides
    from the observer (0..1); the air, the clouds and the ground get the rest.
    ``moon_km``: the Moon's centre from the observer (ENU, km, airless direction), and
    ``moon_radius_km`` its radius: the sky's light per direction (the umbra and penumbra
    cones) and the disks' occultation follow from them.
    """

    hidden_fraction: float
    moon_km: np.ndarray
    moon_radius_km: float

    @property
    def visible_fraction(self) -> float:
        return 1.0 - self.hidden_fraction


@dataclass(frozen=True)
class LunarEclipseView:
    """The Earth's shadow on the Moon at one instant.

    ``sun_km`` and ``earth_km``: the Sun's and the Earth's centres from the observer (ENU,
    km); ``earth_radius_km``: the shadow-casting radius (the Earth's, enlarged by 1/85 for
    its atmosphere, Danjon). ``umbra_light``: sunlight refracted into the shadow by the
    Earth's atmosphere, (distances from the shadow's axis in km, factors (N, W) of the
    direct sunlight at ``wavelengths_nm``). ``moon_light_factor``: the eclipsed Moon's
    brightness over the uneclipsed one's (luminance, disk averaged; for the moonlit sky).
    """

    sun_km: np.ndarray
    earth_km: np.ndarray
    earth_radius_km: float
    umbra_distances_km: np.ndarray
    umbra_light: np.ndarray
    wavelengths_nm: np.ndarray
    moon_light_factor: float


@dataclass(frozen=True)
class SkyState:
    """The lights of a sky at one instant: the Sun, the Moon (or None) and the weather that
    bends their light (refraction). ``time`` (a ``skydome.astro.Time``) and ``observer``
    (a ``skydome.astro.Observer``) are None for a Sun alone (the abstract mode)."""

    sun: Light
    moon: Light | None = None
    moon_view: MoonView | None = None
    time: Any = None
    observer: Any = None
    pressure_hPa: float = STANDARD_PRESSURE_HPA
    temperature_C: float = STANDARD_TEMPERATURE_C
    #: A solar eclipse (the Moon over the Sun's disk) or a lunar one (the Moon in the
    #: Earth's penumbra), None otherwise.
    solar_eclipse: SolarEclipseView | None = None
    lunar_eclipse: LunarEclipseView | None = None

    @property
    def refraction_scale(self) -> float:
        """The weather's factor on the refraction laws (0 without refraction)."""
        return float(refraction_scale(self.pressure_hPa, self.temperature_C))

    @property
    def ground_m(self) -> float:
        """Height (m) of the place's ground above sea level (0 in the abstract mode or below
        sea level): cloud bases and the camera's default height count from it."""
        return 0.0 if self.observer is None else max(float(self.observer.elevation_m), 0.0)

    @property
    def julian_day_utc(self) -> float | None:
        """The instant as a Julian Date (UTC), None in the abstract mode."""
        t = self.time
        if t is None or not hasattr(t, "jd_utc"):
            return None
        return float(np.ravel(t.jd_utc)[0])

    def summary(self) -> dict[str, Any]:
        """Where the lights are, for reports: degrees, lux."""
        out: dict[str, Any] = {
            "sun_elevation_deg": self.sun.elevation_deg,
            "sun_azimuth_deg": self.sun.azimuth_deg,
            "sun_illuminance_lux": self.sun.illuminance_lux,
        }
        if self.moon is not None and self.moon_view is not None:
            out.update(
                moon_elevation_deg=self.moon.elevation_deg,
                moon_azimuth_deg=self.moon.azimuth_deg,
                moon_illuminated_fraction=self.moon_view.illuminated_fraction,
                moon_illuminance_lux=self.moon.illuminance_lux,
            )
        return out
