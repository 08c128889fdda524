"""Atmosphere presets.

The measured Earth (U.S. Standard Atmosphere 1976 air, Bodhaine Rayleigh, AFGL ozone at
300 DU, an OPAC aerosol type): ``earth`` (clean continental, AOD 0.1: a typical clear day),
``typical`` (average continental: the mean daylight of measured curves), ``hazy``, ``urban``,
``maritime``, ``desert``. The seeds' atmospheres, for comparison: ``earth_bruneton`` (seed 001
appendix B) and ``earth_nishita`` (seed 002). And ``mars``.
"""

from __future__ import annotations

import math

import numpy as np

from skydome.atmosphere import mars_atmosphere as m
from skydome.atmosphere.aerosols import with_aerosol_type
from skydome.atmosphere.ozone import ozone_density_profile
from skydome.atmosphere.params import (
    DOBSON_UNIT_PER_M2,
    AtmosphereParams,
    DensityProfile,
    Spectrum,
    surface_spectrum,
)
from skydome.atmosphere.rayleigh import rayleigh_scattering_per_m
from skydome.atmosphere.standard_atmosphere import air_density_profile, us_standard_1976
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


def earth_bruneton() -> AtmosphereParams:
    """The seeds' Earth (seed 001 appendix B, Hillaire 2020 / Bruneton 2017), kept for
    comparison: air as one 8 km exponential with Bruneton's Rayleigh coefficients, aerosol of
    optical depth 0.005 at 550 nm (1.2 km exponential, g = 0.8), 300 DU of ozone on a tent
    profile (25 km, 15 km half width)."""
    return AtmosphereParams(
        name="earth_bruneton",
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
        description="Earth of the seeds (seed 001 appendix B): 8 km exponential air",
    ).with_ozone(300.0)


def _standard_earth(
    name: str, description: str, aerosol: str, aod_550: float | None = None,
    surface: str = "grassland",
):  # fmt: skip
    """The measured Earth: U.S. Standard Atmosphere 1976 air (number density, tabulated every
    500 m to 100 km) with Rayleigh scattering from first principles (Bodhaine et al. 1999
    cross-section times the standard's sea-level number density: 1.149e-5 m^-1 at 550 nm, an
    optical depth of 0.0971), the AFGL 1986 U.S. Standard ozone profile scaled to 300 DU, an
    OPAC aerosol type (Hess et al. 1998) over the spectral albedo of a ``surface``
    (``params.surface_spectrum``: grassland, 0.04 in the blue, 0.13 in the green and red;
    a luminous albedo of 0.12 under the Sun, where a grey 0.3 drew a beige plane brighter
    than the horizon)."""

    sea_level_m3 = float(us_standard_1976().number_density_m3[0])
    base = AtmosphereParams(
        name=name,
        bottom_radius_m=6_360_000.0,
        top_radius_m=6_460_000.0,
        rayleigh_scattering=Spectrum.sampled(
            _GRID_NM, rayleigh_scattering_per_m(_GRID_NM, sea_level_m3)
        ),
        rayleigh_density=air_density_profile(),
        mie_scattering=Spectrum.constant(0.0),  # the aerosol type's, set below
        mie_extinction=Spectrum.constant(0.0),
        mie_g=0.7,
        mie_density=DensityProfile.exponential(1200.0),
        absorption_extinction=Spectrum.constant(0.0),  # 300 DU of ozone, set below
        absorption_density=ozone_density_profile(),
        ground_albedo=surface_spectrum(surface),
        sun_angular_radius_rad=SUN_ANGULAR_RADIUS_1AU,
        solar_irradiance=_sun(),
        description=description,
    ).with_ozone(300.0)
    return with_aerosol_type(base, aerosol, aod_550)


def earth() -> AtmosphereParams:
    """A typical clear day: the measured Earth (:func:`_standard_earth`) with clean
    continental aerosol of optical depth 0.1 at 550 nm."""
    return _standard_earth(
        "earth",
        "Earth, clear day: standard atmosphere, clean continental aerosol (AOD 0.1), 300 DU",
        "continental_clean",
        0.1,
    )


def typical() -> AtmosphereParams:
    """The mean turbidity that measured mean daylight curves describe: the measured Earth
    with OPAC's average continental aerosol (its standard column, AOD 0.151 at 550 nm)."""
    return _standard_earth(
        "typical",
        "Earth, average continental aerosol (AOD 0.151): the measured mean daylight",
        "continental_average",
    )


def urban() -> AtmosphereParams:
    """The measured Earth with OPAC's urban aerosol (AOD 0.643 at 550 nm, SSA 0.82)."""
    return _standard_earth("urban", "Earth, urban aerosol (AOD 0.643)", "urban", surface="urban")


def maritime() -> AtmosphereParams:
    """The measured Earth with OPAC's clean maritime aerosol (AOD 0.096, Ångström 0.1)."""
    return _standard_earth(
        "maritime", "Earth, clean maritime aerosol (AOD 0.096)", "maritime_clean",
        surface="ocean",
    )  # fmt: skip


def desert() -> AtmosphereParams:
    """The measured Earth with OPAC's desert aerosol (AOD 0.286, coarse mineral dust)."""
    return _standard_earth(
        "desert", "Earth, desert aerosol (AOD 0.286)", "desert", surface="desert"
    )


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
    """Mars in a clear season, from published profiles (``skydome.atmosphere.mars_atmosphere``).

    CO2 gas from a Mars-GRAM 2005 profile (Justus et al. 2005: 583 Pa and 0.0142 kg/m^3 at
    the areoid, radius 3389.5 km) with Rayleigh scattering 2.5 times air's per molecule; dust of
    optical depth 0.5 at 550 nm on Conrath's profile (nu = 0.01), with Mie optics for
    r_eff = 1.71 um (Markiewicz et al. 1999): single-scattering albedo 0.62 at 440 nm rising
    to 0.97 at 700 nm (absorbing in the blue: the butterscotch daytime sky) and a forward
    peak twice as high in the blue as in the red (the blue glow around the setting Sun);
    ground albedo 0.10-0.35 (450-650 nm); the Sun at 1.524 AU.
    """

    dust_density = m.mars_dust_density()
    top_m = m.TOP_M
    extinction, scattering = m.mars_dust_spectra(dust_density.column_m(top_m))
    phase = m.mars_dust_phase()
    return AtmosphereParams(
        name="mars",
        bottom_radius_m=m.MARS_RADIUS_M,
        top_radius_m=m.MARS_RADIUS_M + top_m,
        rayleigh_scattering=Spectrum.sampled(_GRID_NM, m.mars_rayleigh_scattering(_GRID_NM)),
        rayleigh_density=m.mars_gas_density(),
        mie_scattering=scattering,
        mie_extinction=extinction,
        mie_g=float(phase.asymmetry(550.0)[0]),
        mie_density=dust_density,
        absorption_extinction=Spectrum.constant(0.0),
        absorption_density=DensityProfile.exponential(11_100.0),
        ground_albedo=Spectrum.sampled([450.0, 550.0, 650.0], [0.10, 0.22, 0.35]),
        sun_angular_radius_rad=SUN_ANGULAR_RADIUS_1AU / 1.524,
        solar_irradiance=_sun(1.0 / 1.524**2),
        mie_phase=phase,
        description="Mars, clear season (dust optical depth 0.5), Mars-GRAM gas profile",
    )


PRESETS = {
    "earth": earth,
    "typical": typical,
    "hazy": hazy,
    "urban": urban,
    "maritime": maritime,
    "desert": desert,
    "earth_bruneton": earth_bruneton,
    "earth_nishita": earth_nishita,
    "mars": mars,
}


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
    if not isinstance(name, str) or name not in PRESETS:
        raise ParameterError(
            f"unknown atmosphere preset {name!r}; choose one of {', '.join(PRESETS)}"
        )
    params = PRESETS[name]()
    return params.with_knobs(
        albedo=albedo, aod_550=aod_550, angstrom=angstrom, ozone_du=ozone_du, ssa=ssa
    )
