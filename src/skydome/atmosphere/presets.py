"""Atmosphere presets: ``earth``, ``earth_nishita``, ``hazy`` and ``mars``."""

from __future__ import annotations

import math

import numpy as np

from skydome.atmosphere.params import (
    DOBSON_UNIT_PER_M2,
    AtmosphereParams,
    DensityProfile,
    Spectrum,
)
from skydome.errors import ParameterError
from skydome.spectra.tables import solar_irradiance

#: Spectra of the presets are tabulated every 5 nm (the tables hold 10 nm bin means at the
#: bin centres, 365, 375, ... nm, which this grid contains).
_GRID_NM = np.arange(360.0, 831.0, 5.0)

#: Rayleigh scattering of air at sea level, beta(λ) = K / λ_µm^4 with K = 1.24062e-6 m^-1
#: (Bruneton 2017 demo; gives 5.802e-6, 13.558e-6, 33.1e-6 m^-1 at 680, 550, 440 nm,
#: the values of seed 001 appendix B / Hillaire 2020).
EARTH_RAYLEIGH_K = 1.24062e-6
#: Ozone: 300 Dobson units spread over a tent profile of 15 km equivalent thickness
#: (Bruneton 2017): peak number density = 300 · 2.687e20 m^-2 / 15 000 m.
OZONE_PEAK_NUMBER_DENSITY = 300.0 * DOBSON_UNIT_PER_M2 / 15000.0
#: Angular radius of the Sun seen from Earth at 1 AU (0.2666 deg, 959.6 arcsec).
SUN_ANGULAR_RADIUS_1AU = math.radians(959.63 / 3600.0)


def _lambda_power(k_at_1um: float, exponent: float) -> Spectrum:
    return Spectrum.sampled(_GRID_NM, k_at_1um * (_GRID_NM / 1000.0) ** (-exponent))


def _sun(scale: float = 1.0) -> Spectrum:
    return Spectrum.sampled(_GRID_NM, scale * solar_irradiance(_GRID_NM))


def earth() -> AtmosphereParams:
    """Earth, clear sky, with ozone: seed 001 appendix B (Hillaire 2020 / Bruneton 2017)."""
    return AtmosphereParams(
        name="earth",
        bottom_radius_m=6_360_000.0,
        top_radius_m=6_460_000.0,
        rayleigh_scattering=_lambda_power(EARTH_RAYLEIGH_K, 4.0),
        rayleigh_density=DensityProfile.exponential(8000.0),
        mie_scattering=Spectrum.constant(3.996e-6),
        mie_extinction=Spectrum.constant(4.440e-6),
        mie_g=0.8,
        mie_density=DensityProfile.exponential(1200.0),
        absorption_extinction=Spectrum.constant(0.0),  # 300 DU of ozone, set below
        absorption_density=DensityProfile.tent(25_000.0, 15_000.0),
        ground_albedo=Spectrum.constant(0.3),
        sun_angular_radius_rad=SUN_ANGULAR_RADIUS_1AU,
        solar_irradiance=_sun(),
        description="Earth, clear sky with ozone (seed 001 appendix B)",
    ).with_ozone(300.0)


def earth_nishita() -> AtmosphereParams:
    """The atmosphere of seed 002 (Nishita 1993 as in the tutorial): no ozone, HR 7994 m.

    Sea-level Rayleigh 5.8e-6, 13.5e-6, 33.1e-6 m^-1 at 680, 550, 440 nm (a λ^-4 law through
    13.5e-6 at 550 nm reproduces all three within 1%), Mie 21e-6 m^-1 with extinction 1.1x,
    HM 1200 m, g 0.76, radii 6360 / 6420 km.
    """
    return AtmosphereParams(
        name="earth_nishita",
        bottom_radius_m=6_360_000.0,
        top_radius_m=6_420_000.0,
        rayleigh_scattering=_lambda_power(13.5e-6 * 0.55**4, 4.0),
        rayleigh_density=DensityProfile.exponential(7994.0),
        mie_scattering=Spectrum.constant(21e-6),
        mie_extinction=Spectrum.constant(21e-6 * 1.1),
        mie_g=0.76,
        mie_density=DensityProfile.exponential(1200.0),
        absorption_extinction=Spectrum.constant(0.0),
        absorption_density=DensityProfile.exponential(8000.0),
        ground_albedo=Spectrum.constant(0.1),
        sun_angular_radius_rad=SUN_ANGULAR_RADIUS_1AU,
        solar_irradiance=_sun(),
        description="Nishita single-scattering atmosphere of seed 002",
    )


#: The knob settings of the ``hazy`` preset (``earth`` with them): aerosol optical depth
#: 0.272 at 550 nm, Ångström exponent 1.3 (continental haze), single-scattering albedo
#: 150/170 ≈ 0.88, boundary layer of scale height 1600 m, asymmetry g = 0.7.
HAZY_AEROSOL = {
    "aod_550": 0.272,
    "angstrom": 1.3,
    "ssa": 150.0 / 170.0,
    "scale_height_m": 1600.0,
    "mie_g": 0.7,
}


def hazy() -> AtmosphereParams:
    """Earth with a hazy boundary layer: aerosol optical depth 0.272 at 550 nm.

    ``earth().with_aerosol(**HAZY_AEROSOL)``: Mie extinction 170e-6 m^-1 and scattering
    150e-6 m^-1 at 550 nm at the ground (τ / H = 0.272 / 1600 m; single-scattering albedo
    0.88; with the air's Rayleigh, visibility 3.912/β ≈ 21 km), scale height 1600 m, Ångström exponent 1.3, g = 0.7.
    """
    return (
        earth()
        .with_aerosol(**HAZY_AEROSOL)
        .with_(name="hazy", description="Earth with hazy boundary layer (AOD 0.27 at 550 nm)")
    )


def mars() -> AtmosphereParams:
    """Mars with a moderately dusty sky (dust optical depth ~0.5, typical of clear seasons).

    Radius 3389.5 km; CO2 Rayleigh scattering scaled from air by number density (610 Pa,
    210 K: 1/120 of Earth's sea level) and by CO2's ~2.5x larger cross-section; dust with
    scale height 11.1 km, extinction 4.5e-5 m^-1 at the ground, single scattering albedo
    rising from 0.62 at 440 nm to 0.97 at 700 nm (absorbing in the blue, Wolff et al. 2009),
    g = 0.63; Sun at 1.524 AU (irradiance / 1.524^2, angular radius / 1.524).
    """
    dust_ext = 4.5e-5
    ssa = np.interp(_GRID_NM, [440.0, 550.0, 700.0], [0.62, 0.90, 0.97])
    return AtmosphereParams(
        name="mars",
        bottom_radius_m=3_389_500.0,
        top_radius_m=3_389_500.0 + 120_000.0,
        rayleigh_scattering=_lambda_power(EARTH_RAYLEIGH_K * 2.5 / 120.0, 4.0),
        rayleigh_density=DensityProfile.exponential(11_100.0),
        mie_scattering=Spectrum.sampled(_GRID_NM, dust_ext * ssa),
        mie_extinction=Spectrum.constant(dust_ext),
        mie_g=0.63,
        mie_density=DensityProfile.exponential(11_100.0),
        absorption_extinction=Spectrum.constant(0.0),
        absorption_density=DensityProfile.exponential(11_100.0),
        ground_albedo=Spectrum.sampled([450.0, 550.0, 650.0], [0.10, 0.22, 0.35]),
        sun_angular_radius_rad=SUN_ANGULAR_RADIUS_1AU / 1.524,
        solar_irradiance=_sun(1.0 / 1.524**2),
        description="Mars, moderately dusty (dust optical depth ~0.5)",
    )


PRESETS = {"earth": earth, "earth_nishita": earth_nishita, "hazy": hazy, "mars": mars}


def preset(
    name: str,
    *,
    albedo: float | Spectrum | None = None,
    aod_550: float | None = None,
    angstrom: float | None = None,
    ozone_du: float | None = None,
    ssa: float | None = None,
) -> AtmosphereParams:
    """The named preset, with any knobs set (``AtmosphereParams.with_knobs``; None keeps the
    preset's own value); raises ParameterError listing the valid names or naming a knob's
    valid range. E.g. ``preset("earth", aod_550=0.1, angstrom=1.3, ozone_du=300)``."""
    try:
        params = PRESETS[name]()
    except KeyError:
        raise ParameterError(
            f"unknown atmosphere preset {name!r}; choose one of {', '.join(PRESETS)}"
        ) from None
    return params.with_knobs(
        albedo=albedo, aod_550=aod_550, angstrom=angstrom, ozone_du=ozone_du, ssa=ssa
    )
