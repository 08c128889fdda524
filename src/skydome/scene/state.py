"""SkyState: the lights and the place of a sky at one instant, computed once per time.

Layers read a SkyState in their update stage (light directions, irradiances, the Moon's
phase and orientation); nothing in it depends on a camera. It is made either from the
astronomy (:meth:`SkyState.at_place`) or from a Sun elevation and azimuth alone
(:meth:`SkyState.abstract`, the mode of ``render_sky``).

Units: directions are unit ENU vectors (x east, y north, z up); angles in radians unless a
name says ``_deg``; illuminances in lux outside the atmosphere on a surface facing the
light; distances in km.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from skydome.astro import frames, photometry
from skydome.astro.moon import MOON_RADIUS_KM
from skydome.astro.sun import SUN_RADIUS_KM
from skydome.errors import ParameterError, check_range

#: Mean Earth-Sun distance (km), for the abstract mode's Sun at 1 au.
AU_KM = frames.AU_KM
#: Standard weather for refraction when none is given (Meeus ch. 16's reference values).
STANDARD_PRESSURE_HPA = 1010.0
STANDARD_TEMPERATURE_C = 10.0
#: Equatorial radius of the Earth (km), for the earthshine on the Moon (IERS 2010).
EARTH_RADIUS_KM = 6378.137
#: Mean Earth radius (m; IUGG mean radius R1 = 6371.0088 km), for the horizon's dip.
EARTH_MEAN_RADIUS_M = 6_371_008.8


@dataclass(frozen=True)
class Light:
    """A source beyond the atmosphere as the observer sees it at one instant.

    ``direction`` is the apparent (refracted) one, where the disk's centre is seen and from
    where its light reaches the air; ``direction_true`` the airless one. ``illuminance_lux``
    is outside the atmosphere, normal incidence.
    """

    name: str
    direction: np.ndarray
    direction_true: np.ndarray
    distance_km: float
    angular_radius_rad: float
    illuminance_lux: float

    @property
    def elevation_deg(self) -> float:
        """Apparent elevation above the horizon, degrees."""
        return math.degrees(math.asin(float(np.clip(self.direction[2], -1.0, 1.0))))

    @property
    def azimuth_deg(self) -> float:
        """Azimuth from north through east, degrees in [0, 360)."""
        x, y = float(self.direction[0]), float(self.direction[1])
        return math.degrees(math.atan2(x, y)) % 360.0


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
class SkyState:
    """The lights of a sky at one instant: the Sun, the Moon (or None) and the weather that
    bends their light (refraction)."""

    sun: Light
    moon: Light | None = None
    moon_view: MoonView | None = None
    time: Any = None
    observer: Any = None
    pressure_hPa: float = STANDARD_PRESSURE_HPA
    temperature_C: float = STANDARD_TEMPERATURE_C

    # ------------------------------------------------------------------ abstract mode

    @classmethod
    def abstract(
        cls,
        sun_elevation_deg: float,
        sun_azimuth_deg: float = 180.0,
        *,
        sun_distance_au: float = 1.0,
        refraction: bool = True,
    ) -> SkyState:
        """A Sun at an apparent elevation and azimuth (deg), no Moon, standard weather.

        With ``refraction`` (default) the disk is flattened near the horizon as a real Sun
        at that apparent elevation would be; without, the air does not bend light.
        """
        el = check_range("sun elevation", sun_elevation_deg, -90.0, 90.0, "deg")
        az = check_range("sun azimuth", sun_azimuth_deg, -360.0, 360.0, "deg")
        d_au = check_range("sun distance", sun_distance_au, 0.01, 100.0, "au")
        pressure = STANDARD_PRESSURE_HPA if refraction else 0.0
        r_arcmin = float(frames.refraction_bennett(el, pressure, STANDARD_TEMPERATURE_C))
        apparent = frames.horizontal_to_enu(math.radians(el), math.radians(az))
        true = frames.horizontal_to_enu(math.radians(el - r_arcmin / 60.0), math.radians(az))
        d_km = d_au * AU_KM
        sun = Light(
            "sun",
            apparent,
            true,
            d_km,
            math.asin(SUN_RADIUS_KM / d_km),
            float(photometry.sun_illuminance_lux(d_au)),
        )
        return cls(sun=sun, pressure_hPa=pressure)

    # ------------------------------------------------------------------ a place and a time

    @classmethod
    def at_place(cls, observer, time) -> SkyState:
        """The Sun and the Moon seen by ``observer`` (an ``skydome.astro.Observer``) at one
        ``time`` (anything ``skydome.astro.to_time`` accepts, a single instant)."""
        from skydome.astro.time import to_time

        t = to_time(time)
        if t.shape != ():
            raise ParameterError(f"a sky is for one instant; got {t.shape} times")
        return cls.series(observer, t.jd_utc.reshape(1))[0]

    @classmethod
    def series(cls, observer, times) -> list[SkyState]:
        """One state per time (a 1-D sequence), the astronomy computed once for all of them
        (vectorized: a 24-hour time-lapse at 1-minute steps costs one call)."""
        from skydome.astro import libration
        from skydome.astro.time import Time, to_time

        t = to_time(times)
        if len(t.shape) != 1:
            raise ParameterError(f"times must be a 1-D sequence, got shape {t.shape}")
        sky = observer.sky(t, bodies=("sun", "moon"))
        s, m = sky["sun"], sky["moon"]
        lat = math.radians(float(observer.latitude))
        lib = libration.moon_topocentric_libration(
            t, lat, math.radians(float(observer.longitude)), float(observer.elevation_m)
        )
        pole = np.array([0.0, math.cos(lat), math.sin(lat)])  # the true pole of date in ENU
        out = []
        for i in range(t.shape[0]):
            sun = _light(
                "sun", s.enu[i], s.enu_unrefracted[i], s.distance_km[i], s.illuminance_lux[i]
            )
            moon = _light(
                "moon", m.enu[i], m.enu_unrefracted[i], m.distance_km[i], m.illuminance_lux[i]
            )
            sun_km = sun.direction_true * sun.distance_km
            moon_km = moon.direction_true * moon.distance_km
            to_sun = (sun_km - moon_km) / np.linalg.norm(sun_km - moon_km)
            l, b, p = (float(lib[k][i]) for k in ("l", "b", "P"))
            earth_phase = float(m.earth_phase_angle[i])
            view = MoonView(
                phase_angle_rad=float(m.phase_angle[i]),
                illuminated_fraction=float(m.illuminated_fraction[i]),
                bright_limb_angle_rad=float(m.bright_limb_angle[i]),
                earth_phase_angle_rad=earth_phase,
                to_sun=to_sun,
                frame=moon_frame_enu(moon.direction_true, pole, l, b, p),
                libration_rad=(l, b, p),
                earthshine_lux=earthshine_lux(sun.illuminance_lux, earth_phase, moon.distance_km),
            )
            out.append(
                cls(
                    sun=sun,
                    moon=moon,
                    moon_view=view,
                    time=Time(t.jd_utc[i], t.jd_ut1[i], t.jd_tt[i]),
                    observer=observer,
                    pressure_hPa=float(observer.pressure_hPa),
                    temperature_C=float(observer.temperature_C),
                )
            )
        return out

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


def _light(name: str, enu, enu_true, distance_km, illuminance_lux) -> Light:
    d_km = float(distance_km)
    radius_km = SUN_RADIUS_KM if name == "sun" else MOON_RADIUS_KM
    return Light(
        name,
        np.asarray(enu, dtype=np.float64),
        np.asarray(enu_true, dtype=np.float64),
        d_km,
        math.asin(min(radius_km / d_km, 1.0)),
        float(illuminance_lux),
    )


def moon_frame_enu(
    moon_true: np.ndarray, pole_enu: np.ndarray, l_rad: float, b_rad: float, p_rad: float
) -> np.ndarray:
    """Moon-fixed axes (columns x, y, z) in ENU from the libration and the axis angle.

    ``moon_true``: unit ENU vector from the observer to the Moon (airless); ``pole_enu``: the
    celestial north pole in ENU; ``l_rad``, ``b_rad``: selenographic longitude and latitude
    of the sub-observer point; ``p_rad``: position angle of the Moon's axis from the north
    point of the disk through east (Meeus ch. 53).
    """
    u = moon_true / np.linalg.norm(moon_true)
    w = -u  # from the Moon towards the observer
    north = pole_enu - np.dot(pole_enu, u) * u
    north /= np.linalg.norm(north)
    east = np.cross(pole_enu, u)  # towards increasing right ascension on the sky
    east /= np.linalg.norm(east)
    axis_on_sky = math.cos(p_rad) * north + math.sin(p_rad) * east
    # The pole leans towards the observer by the libration in latitude b.
    pole = math.cos(b_rad) * axis_on_sky + math.sin(b_rad) * w
    q = w - math.sin(b_rad) * pole
    q /= np.linalg.norm(q)  # the sub-observer meridian on the Moon's equator: longitude l
    x = math.cos(l_rad) * q - math.sin(l_rad) * np.cross(pole, q)
    y = np.cross(pole, x)
    return np.stack([x, y, pole], axis=1)


def earthshine_lux(sun_illuminance_lux: float, earth_phase_angle_rad: float, moon_km: float):
    """Illuminance (lx) of the earthlit Moon: the Earth as a Lambert sphere of Bond albedo
    0.30 (Goode et al. 2001, GRL 28, 1671: earthshine albedo 0.297) seen at its phase angle
    from the Moon. A Lambert sphere's geometric albedo is 2/3 of its Bond albedo and its phase
    law (sin a + (pi - a) cos a) / pi (Russell 1916)."""
    a = float(earth_phase_angle_rad)
    phase_law = (math.sin(a) + (math.pi - a) * math.cos(a)) / math.pi
    geometric_albedo = 2.0 / 3.0 * 0.30
    return sun_illuminance_lux * geometric_albedo * phase_law * (EARTH_RADIUS_KM / moon_km) ** 2


def horizon_dip_sin(observer_height_m) -> float:
    """sin of the dip of the ground's horizon below the horizontal for an observer at
    ``observer_height_m`` above a spherical Earth: a ray with elevation below -dip hits it."""
    r = EARTH_MEAN_RADIUS_M + max(float(observer_height_m), 0.0)
    return math.sqrt(max(1.0 - (EARTH_MEAN_RADIUS_M / r) ** 2, 0.0))


def refraction_scale(state: SkyState) -> float:
    """The factor (P / 1010 hPa)(283 K / (273 K + T)) of the refraction laws for the
    state's weather (0 when the pressure is 0: no refraction), as in skydome.astro.frames."""
    return (state.pressure_hPa / 1010.0) * (283.0 / (273.0 + state.temperature_C))
