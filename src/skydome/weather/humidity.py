"""Hygroscopic growth: aerosols take up water as the air nears saturation and scatter more.

Kasten's (1969, Tellus 21, 631) form of Hanel's growth law (Hanel 1976, Adv. Geophys. 19,
73): the extinction of a continental aerosol grows as (1 - RH)^-gamma, gamma = 0.25. The aerosol types
of ``skydome.atmosphere.aerosols`` are OPAC's at 80 % relative humidity, so the factor is
taken from there: f(RH) = ((1 - RH) / (1 - 0.8))^-gamma, 0.67 in dry air (RH 0) and 1.61 at
97 %. Past 97 % the aerosol becomes droplets (activation: mist and fog), which the weather's
droplet layer holds instead; the factor is held at its 97 % value.

The growth changes the aerosol's amount, not its colour, here: its spectrum keeps its shape
(the water a particle takes up scales its radius, which moves its spectrum in wavelength
only, and the OPAC types' spectra are close to power laws over the visible). What whitens
mist and haze near saturation is the droplets.
"""

from __future__ import annotations

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
