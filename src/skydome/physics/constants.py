"""Physical and astronomical constants used across the package: one home each."""

from __future__ import annotations

import math

#: Julian Date of the epoch J2000.0 (2000-01-01 12:00 TT); the origin of the series of the
#: astronomy (TT) and of the clouds' time (UTC seconds since it).
J2000_JD = 2451545.0
#: Days in a Julian century.
JULIAN_CENTURY_DAYS = 36525.0
#: The astronomical unit (km), IAU 2012 resolution B2.
AU_KM = 149_597_870.700
#: The Earth's equatorial radius (km): WGS84's semi-major axis (IERS 2010 conventions).
EARTH_EQUATORIAL_RADIUS_KM = 6378.137
#: The Earth's mean radius (m): IUGG mean radius R1 = 6371.0088 km (Moritz 2000). The
#: horizon's dip and the airglow layer's geometry use it; the atmospheres' own ground radius
#: is their parameter (``AtmosphereParams.bottom_radius_m``, 6360 km for Bruneton's Earth).
EARTH_MEAN_RADIUS_M = 6_371_008.8
#: Radians per arcsecond and per arcminute.
ARCSEC_RAD = math.pi / 648000.0
ARCMIN_RAD = math.pi / 10800.0
#: Metres per kilometre: Python works in metres, the shaders in km (float32 precision).
M_PER_KM = 1000.0
#: The standard weather of the refraction laws (Meeus ch. 16): pressure (hPa) and
#: temperature (deg C) at which Bennett's and Saemundsson's formulas hold as written.
STANDARD_PRESSURE_HPA = 1010.0
STANDARD_TEMPERATURE_C = 10.0
#: 0 deg C in kelvin.
ZERO_CELSIUS_K = 273.0
