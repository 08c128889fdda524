"""Hygroscopic growth: aerosols take up water as the air nears saturation and scatter more.

Kasten's (1969, Tellus 21, 631) form of Hanel's growth law (Hanel 1976, Adv. Geophys. 19,
73): the extinction of a continental aerosol grows as (1 - RH)^-gamma, gamma = 0.25. The aerosol types
of ``skydome.atmosphere.aerosols`` are OPAC's at 80 % relative humidity, so the factor is
taken from there: f(RH) = ((1 - RH) / (1 - 0.8))^-gamma, 0.67 in dry air (RH 0) and 1.61 at
97 %. Past 97 % the aerosol becomes droplets (activation: mist and fog), which the weather's
droplet layer holds instead; the factor is held at its 97 % value.

The growth also whitens the aerosol: the particles grow towards the wavelength and their
extinction flattens across the spectrum. OPAC's water-soluble component (the continental
types' hygroscopic part) has an Angstrom exponent (450/650 nm) of 1.48 dry, 1.37 at 80 % and
0.99 at 99 %, from its component files' extinction at each humidity (Hess, Koepke & Schult
1998, Bull. Amer. Meteor. Soc. 79, 831; the files waso00-waso99 as shipped with AeroMix, Raj &
Sinha 2023). The aerosol's spectrum is tilted by the change from 80 % (its types' humidity),
keeping its own shape; past activation (97 %) the droplets whiten the mist and the fog.
"""

from __future__ import annotations

import numpy as np

from skydome.errors import check_range

#: Kasten / Hanel's exponent for continental aerosol.
GROWTH_EXPONENT = 0.25
#: The relative humidity (fraction) of the aerosol types' spectra (OPAC's 80 %).
REFERENCE_HUMIDITY = 0.8
#: Where growth becomes activation: the factor is held above this humidity (fraction).
ACTIVATION_HUMIDITY = 0.97


def growth_factor(relative_humidity_pct: float) -> float:
    """The aerosol's extinction at ``relative_humidity_pct`` (%) over its extinction at
    OPAC's 80 %."""
    rh = check_range("relative humidity", relative_humidity_pct, 0.0, 100.0, "%") / 100.0
    rh = min(rh, ACTIVATION_HUMIDITY)
    return ((1.0 - rh) / (1.0 - REFERENCE_HUMIDITY)) ** (-GROWTH_EXPONENT)


#: Relative humidities (%) of OPAC's water-soluble component files, and its Angstrom exponent
#: between 450 and 650 nm there (from the files' extinction coefficients, e.g. 5.180e-6 and
#: 3.003e-6 /km per particle per cm^3 at 0 %).
OPAC_HUMIDITY_PCT = (0.0, 50.0, 70.0, 80.0, 90.0, 95.0, 98.0, 99.0)
WATER_SOLUBLE_ANGSTROM = (1.483, 1.434, 1.402, 1.368, 1.297, 1.207, 1.076, 0.985)


def angstrom_change(relative_humidity_pct: float) -> float:
    """The change of the aerosol's Angstrom exponent at ``relative_humidity_pct`` (%) from
    OPAC's 80 % (negative: whiter), held at its value at activation (97 %)."""
    rh = check_range("relative humidity", relative_humidity_pct, 0.0, 100.0, "%")
    rh = min(rh, 100.0 * ACTIVATION_HUMIDITY)
    alpha = np.interp(rh, OPAC_HUMIDITY_PCT, WATER_SOLUBLE_ANGSTROM)
    return float(alpha - WATER_SOLUBLE_ANGSTROM[OPAC_HUMIDITY_PCT.index(80.0)])
