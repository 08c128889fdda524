"""Top-of-atmosphere irradiance and illuminance of the Sun, Moon, planets and stars.

Units: W/m^2 (irradiance), lux (illuminance, on a surface normal to the light), all
outside the atmosphere; the renderer applies extinction.

Sun
    Total solar irradiance 1361 W/m^2 at 1 au (Kopp & Lean 2011, GRL 38, L01706).
    Illuminance 133,334 lx at 1 au: the luminous solar constant of Darula, Kittler &
    Gueymard (2005, LEUKOS 1(3), 25-44), defined once in ``skydome.spectra``
    (``LUMINOUS_SOLAR_CONSTANT_LX``, whose comment explains why the renderer's integral of
    the packaged ASTM G-173 spectrum, 133,177 lx, is 0.12 % lower and why the value stays on
    the spectrum's 1366.1 W/m^2 scale rather than Kopp & Lean's). Both scale as 1/r^2.
Stars and planets
    E = 10^(-0.4 (m + 14.18)) lx for a V magnitude m (the conversion used across skydome;
    m = 0 gives 2.13e-6 lx). Note that with this constant the Sun's V = -26.74 would give
    106 klx rather than the 133 klx above: the magnitude zero point and the solar
    spectrum are independent calibrations that differ by 0.25 mag.
Moon
    V magnitude from Allen's phase law (Astrophysical Quantities, 3rd ed., 1973, sec. 66;
    the form used by the USNO): V = -12.73 + 0.026 |i| + 4e-9 i^4 (i in degrees) at mean
    distances (384,400 km, 1 au), plus 5 log10(Delta/384,400 km * r/1 au); valid for
    |i| < 150 deg. Converted to lux with the stellar constant (full Moon 0.26 lx).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from skydome.physics.constants import EARTH_EQUATORIAL_RADIUS_KM
from skydome.spectra.colour import LUMINOUS_SOLAR_CONSTANT_LX

__all__ = [
    "SOLAR_CONSTANT_W_M2",
    "SOLAR_ILLUMINANCE_1AU_LX",
    "MAGNITUDE_ZERO_POINT",
    "sun_irradiance_w_m2",
    "sun_illuminance_lux",
    "magnitude_to_lux",
    "lux_to_magnitude",
    "moon_magnitude",
    "moon_illuminance_lux",
    "MAG0_LUMINANCE_CD_M2",
    "S10_MAG_ARCSEC2",
    "mag_to_luminance",
    "luminance_to_mag",
    "s10_to_mag",
    "s10_to_luminance",
    "mag_to_s10",
    "mag_to_optical_depth",
]

SOLAR_CONSTANT_W_M2 = 1361.0
SOLAR_ILLUMINANCE_1AU_LX = LUMINOUS_SOLAR_CONSTANT_LX
MAGNITUDE_ZERO_POINT = 14.18  # E[lx] = 10^(-0.4 (m + 14.18))
MOON_MEAN_DISTANCE_KM = 384_400.0


def sun_irradiance_w_m2(distance_au: Any) -> np.ndarray:
    """Total solar irradiance (W/m^2) at ``distance_au`` from the Sun."""
    d = np.asarray(distance_au, dtype=float)
    return SOLAR_CONSTANT_W_M2 / (d * d)


def sun_illuminance_lux(distance_au: Any) -> np.ndarray:
    """Solar illuminance (lux) at ``distance_au`` from the Sun."""
    d = np.asarray(distance_au, dtype=float)
    return SOLAR_ILLUMINANCE_1AU_LX / (d * d)


def magnitude_to_lux(vmag: Any) -> np.ndarray:
    """Illuminance (lux) of a point source of V magnitude ``vmag``."""
    return 10.0 ** (-0.4 * (np.asarray(vmag, dtype=float) + MAGNITUDE_ZERO_POINT))


def lux_to_magnitude(lux: Any) -> np.ndarray:
    """V magnitude of a point source giving ``lux``."""
    return -2.5 * np.log10(np.asarray(lux, dtype=float)) - MAGNITUDE_ZERO_POINT


def moon_magnitude(
    phase_angle_rad: Any, distance_km: Any, sun_distance_au: Any = 1.0
) -> np.ndarray:
    """V magnitude of the Moon (Allen's phase law, see the module doc).

    ``phase_angle_rad``: Sun-Moon-observer angle; ``distance_km``: observer-Moon
    distance; ``sun_distance_au``: Sun-Moon distance. Beyond |i| = 150 deg (a crescent
    within 30 deg of the Sun, unseen in daylight) the law is extrapolated.
    """
    i = np.abs(np.degrees(np.asarray(phase_angle_rad, dtype=float)))
    d = np.asarray(distance_km, dtype=float) / MOON_MEAN_DISTANCE_KM
    r = np.asarray(sun_distance_au, dtype=float)
    return -12.73 + 0.026 * i + 4e-9 * i**4 + 5.0 * np.log10(d * r)


def moon_illuminance_lux(
    phase_angle_rad: Any, distance_km: Any, sun_distance_au: Any = 1.0
) -> np.ndarray:
    """Illuminance (lux) from the Moon outside the atmosphere (earthshine not included)."""
    return magnitude_to_lux(moon_magnitude(phase_angle_rad, distance_km, sun_distance_au))


# Surface brightness of the night sky. 1 S10 is the light of one V = 10 star spread over a
# square degree: 10 + 2.5 log10(3600^2) = 27.78 V mag/arcsec^2. A V surface brightness m is a
# luminance L = 10.8e4 10^(-0.4 m) cd/m^2 (the conversion of the night-sky issue; 220 S10 =
# 21.93 mag/arcsec^2 = 1.83e-4 cd/m^2). It is 0.19 mag from the stellar zero point above,
# as the published zero points are from each other.

#: cd/m^2 of a surface brightness of 0 V mag/arcsec^2 (L = 10.8e4 * 10^(-0.4 m)).
MAG0_LUMINANCE_CD_M2 = 10.8e4
#: V mag/arcsec^2 of 1 S10: a 10th-magnitude star per square degree (3600^2 arcsec^2).
S10_MAG_ARCSEC2 = 10.0 + 2.5 * math.log10(3600.0**2)


def mag_to_luminance(mag_arcsec2) -> np.ndarray:
    """Luminance (cd/m^2) of a V surface brightness (mag/arcsec^2)."""
    return MAG0_LUMINANCE_CD_M2 * 10.0 ** (-0.4 * np.asarray(mag_arcsec2, dtype=np.float64))


def luminance_to_mag(luminance_cd_m2) -> np.ndarray:
    """V surface brightness (mag/arcsec^2) of a luminance (cd/m^2); inf for 0."""
    lum = np.asarray(luminance_cd_m2, dtype=np.float64)
    with np.errstate(divide="ignore"):
        return -2.5 * np.log10(lum / MAG0_LUMINANCE_CD_M2)


def s10_to_mag(s10) -> np.ndarray:
    """V mag/arcsec^2 of a brightness in S10 units."""
    with np.errstate(divide="ignore"):
        return S10_MAG_ARCSEC2 - 2.5 * np.log10(np.asarray(s10, dtype=np.float64))


def mag_to_s10(mag_arcsec2) -> np.ndarray:
    """Brightness in S10 units of a V surface brightness (mag/arcsec^2): the inverse of
    :func:`s10_to_mag`."""
    return 10.0 ** (-0.4 * (np.asarray(mag_arcsec2, dtype=np.float64) - S10_MAG_ARCSEC2))


def mag_to_optical_depth(extinction_mag) -> np.ndarray:
    """Optical depth tau of an extinction in magnitudes: a loss of m mag is a factor
    10^(-0.4 m) = exp(-tau), so tau = m / (2.5 log10 e) = 0.921 m."""
    return np.asarray(extinction_mag, dtype=np.float64) / (2.5 * math.log10(math.e))


def s10_to_luminance(s10) -> np.ndarray:
    """Luminance (cd/m^2) of a brightness in S10 units."""
    return np.asarray(s10, dtype=np.float64) * float(mag_to_luminance(S10_MAG_ARCSEC2))


def earthshine_lux(sun_illuminance_lux: float, earth_phase_angle_rad: float, moon_km: float):
    """Illuminance (lx) of the earthlit Moon: the Earth as a Lambert sphere of Bond albedo
    0.30 (Goode et al. 2001, GRL 28, 1671: earthshine albedo 0.297) seen at its phase angle
    from the Moon. A Lambert sphere's geometric albedo is 2/3 of its Bond albedo and its phase
    law (sin a + (pi - a) cos a) / pi (Russell 1916)."""
    a = float(earth_phase_angle_rad)
    phase_law = (math.sin(a) + (math.pi - a) * math.cos(a)) / math.pi
    geometric_albedo = 2.0 / 3.0 * 0.30
    return (
        sun_illuminance_lux
        * geometric_albedo
        * phase_law
        * (EARTH_EQUATORIAL_RADIUS_KM / moon_km) ** 2
    )
