"""The lights of a sky for an instant, from the astronomy or from a Sun's angles alone.

:func:`state_at` and :func:`state_series` make a :class:`~skydome.core.lights.SkyState`
from an observer and a time (vectorized: a 24-hour time-lapse at 1-minute steps costs one
astronomy call); :func:`abstract_state` from a Sun elevation and azimuth alone (no place,
time or Moon). Layers read the state (``skydome.core.lights``); nothing in it depends on a
camera.
"""

from __future__ import annotations

import math

import numpy as np

from skydome.astro import frames, libration, photometry
from skydome.astro.moon import MOON_RADIUS_KM
from skydome.astro.sun import SUN_RADIUS_KM
from skydome.astro.time import Time, to_time
from skydome.celestial.moon_albedo import moon_spectral_albedo
from skydome.core.lights import Light, MoonView, SkyState
from skydome.errors import ParameterError, check_range
from skydome.physics.constants import AU_KM, STANDARD_PRESSURE_HPA, STANDARD_TEMPERATURE_C
from skydome.scene.eclipses import lunar_eclipse_view, solar_eclipse_view

#: Wavelengths (nm) of the umbra's refracted light in a lunar eclipse's state.
UMBRA_WAVELENGTHS_NM = np.arange(380.0, 781.0, 10.0)

__all__ = ["Light", "MoonView", "SkyState", "abstract_state", "state_at", "state_series"]


def abstract_state(
    sun_elevation_deg: float,
    sun_azimuth_deg: float = 180.0,
    *,
    sun_distance_au: float = 1.0,
    pressure_hPa: float = STANDARD_PRESSURE_HPA,
    temperature_C: float = STANDARD_TEMPERATURE_C,
) -> SkyState:
    """A Sun at an apparent elevation and azimuth (deg), no Moon, no place or time.

    With the standard weather (default) the disk is flattened near the horizon as a real
    Sun at that apparent elevation would be, and the air is lit from its airless direction;
    ``pressure_hPa=0`` bends no light (the apparent and airless directions are one).
    """
    el = check_range("sun elevation", sun_elevation_deg, -90.0, 90.0, "deg")
    az = check_range("sun azimuth", sun_azimuth_deg, -360.0, 360.0, "deg")
    d_au = check_range("sun distance", sun_distance_au, 0.01, 100.0, "au")
    pressure = check_range("pressure", pressure_hPa, 0.0, 2000.0, "hPa")
    temperature = check_range("temperature", temperature_C, -100.0, 100.0, "deg C")
    r_arcmin = float(frames.refraction_bennett(el, pressure, temperature))
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
    return SkyState(sun=sun, pressure_hPa=pressure, temperature_C=temperature)


def state_at(observer, time) -> SkyState:
    """The Sun and the Moon seen by ``observer`` (an ``skydome.astro.Observer``) at one
    ``time`` (anything ``skydome.astro.to_time`` accepts, a single instant)."""
    t = to_time(time)
    if t.shape != ():
        raise ParameterError(f"a sky is for one instant; got {t.shape} times")
    # The Time itself, as a 1-sequence: its UT1 and TT kept (a Time made with a delta_t of
    # its own keeps it; the tables are not read a second time).
    one = Time(t.jd_utc.reshape(1), t.jd_ut1.reshape(1), t.jd_tt.reshape(1))
    return state_series(observer, one)[0]


def state_series(observer, times) -> list[SkyState]:
    """One state per time (a 1-D sequence), the astronomy computed once for all of them."""
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
    earth_km = _earth_centre_enu_km(observer)
    out = []
    for i in range(t.shape[0]):
        sun = _light("sun", s.enu[i], s.enu_unrefracted[i], s.distance_km[i], s.illuminance_lux[i])
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
            frame=libration.moon_frame_enu(moon.direction_true, pole, l, b, p),
            libration_rad=(l, b, p),
            earthshine_lux=photometry.earthshine_lux(
                sun.illuminance_lux, earth_phase, moon.distance_km
            ),
        )
        out.append(
            SkyState(
                sun=sun,
                moon=moon,
                moon_view=view,
                solar_eclipse=solar_eclipse_view(sun, moon),
                lunar_eclipse=lunar_eclipse_view(sun, moon, earth_km, UMBRA_WAVELENGTHS_NM),
                time=Time(t.jd_utc[i], t.jd_ut1[i], t.jd_tt[i]),
                observer=observer,
                pressure_hPa=float(observer.pressure_hPa),
                temperature_C=float(observer.temperature_C),
            )
        )
    return out


def _earth_centre_enu_km(observer) -> np.ndarray:
    """The Earth's centre seen from the observer: ENU components, km (WGS84)."""
    lat, lon = math.radians(float(observer.latitude)), math.radians(float(observer.longitude))
    r = frames.geodetic_to_geocentric_km(lat, lon, float(observer.elevation_m))
    e = np.array([-math.sin(lon), math.cos(lon), 0.0])
    n = np.array([-math.sin(lat) * math.cos(lon), -math.sin(lat) * math.sin(lon), math.cos(lat)])
    u = np.array([math.cos(lat) * math.cos(lon), math.cos(lat) * math.sin(lon), math.sin(lat)])
    return -np.array([r @ e, r @ n, r @ u])


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
        # The Moon's light: sunlight times its spectral albedo (Velikodsky et al. 2011).
        moon_spectral_albedo if name == "moon" else None,
    )
