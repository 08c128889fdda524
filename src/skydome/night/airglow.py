"""Natural airglow: its zenith brightness, spectrum, the van Rhijn brightening towards the
horizon and the solar-cycle factor; and the surface-brightness units of the night sky.

Float64 NumPy functions: the layer (``skydome.night.glow_layer.AirglowLayer``) draws the
same formulas in ``shaders/night/airglow.glsl``, and the tests check the frame against them.

Units (skydome.astro.photometry). 1 S10 is the light of one V = 10 star spread over a square degree: 10 + 2.5 log10(3600^2)
= 27.78 V mag/arcsec^2. A V surface brightness m (mag/arcsec^2) is a luminance
L = 10.8e4 * 10^(-0.4 m) cd/m^2 (the conversion the night-sky work uses throughout; e.g.
220 S10 = 21.93 mag/arcsec^2 = 1.83e-4 cd/m^2).
"""

from __future__ import annotations

import numpy as np

from skydome.astro.photometry import (  # noqa: F401 (the night sky's units, re-exported)
    MAG0_LUMINANCE_CD_M2,
    S10_MAG_ARCSEC2,
    luminance_to_mag,
    mag_to_luminance,
    s10_to_luminance,
    s10_to_mag,
)
from skydome.errors import ParameterError, check_range
from skydome.physics.constants import EARTH_MEAN_RADIUS_M as EARTH_RADIUS_M
from skydome.physics.refraction import horizon_dip_sin
from skydome.spectra.tables import WAVELENGTH_MAX_NM, WAVELENGTH_MIN_NM, solar_irradiance

# ---------------------------------------------------------------------- geometry

#: Height of the emitting layer (m): the OI 557.7 nm and OH emissions peak at 87-97 km
#: (Leinert et al. 1998, A&AS 127, 1, sec. 11); 90 km is the conventional value.
AIRGLOW_HEIGHT_M = 90_000.0


def van_rhijn(zenith_rad, layer_height_m: float = AIRGLOW_HEIGHT_M, observer_height_m=0.0):
    """The van Rhijn factor: brightness of a thin emitting shell at ``layer_height_m`` seen at
    zenith angle ``zenith_rad``, relative to its zenith brightness (van Rhijn 1921; Leinert et
    al. 1998 sec. 11, eq. for the van Rhijn function):

        V(z) = 1 / sqrt(1 - (R / (R + h))^2 sin^2 z),   R = the observer's distance from the
        Earth's centre, h = the shell's height above it.

    It is the shell's slant thickness over its vertical thickness. Examples (h = 90 km, observer
    at sea level): V(60 deg) = 1.94, V(80 deg) = 4.19, V(85 deg) = 5.34, V(90 deg) = 6.01.
    Rays that cannot reach the shell (observer above it) get 0.

    GLSL twin: ``van_rhijn``.
    """
    z = np.asarray(zenith_rad, dtype=np.float64)
    r_obs = EARTH_RADIUS_M + np.asarray(observer_height_m, dtype=np.float64)
    r_layer = EARTH_RADIUS_M + float(layer_height_m)
    if np.any(r_obs >= r_layer):
        return np.zeros(np.broadcast(z, r_obs).shape)
    q = (r_obs / r_layer) ** 2 * np.sin(z) ** 2
    return 1.0 / np.sqrt(1.0 - q)


# ---------------------------------------------------------------------- brightness

#: Zenith airglow at solar minimum in S10 (V): the 145 S10 of the natural dark-sky budget
#: (airglow 145 + zodiacal light 60 at high ecliptic latitude + faint stars ~15 = 220 S10 =
#: 21.9 mag/arcsec^2; Leinert et al. 1998, sec. 11 and their summary of the night-sky
#: components; the same 21.9 V is measured at La Palma at sunspot minimum by Benn & Ellison
#: 1998, La Palma Technical Note 115).
AIRGLOW_ZENITH_S10 = 145.0
#: 10.7 cm solar radio flux (sfu = 1e-22 W m^-2 Hz^-1) at solar minimum: 0.8 MJy = 80 sfu,
#: the lower end of the relation below.
SOLAR_MINIMUM_SFU = 80.0
SOLAR_FLUX_RANGE_SFU = (50.0, 400.0)


def solar_cycle_factor(solar_flux_sfu) -> np.ndarray:
    """Airglow brightness relative to solar minimum for a 10.7 cm solar flux (sfu).

    The zenith airglow in S10 (V) is I = 145 + 130 (S - 0.8) / 1.2 with S the 10.7 cm flux in
    MJy (= 100 sfu), which runs from 0.8 to 2.0 over the 11-year cycle: ~275 S10 at solar
    maximum, 0.7 mag brighter. The relation is the one given with the 145 S10 night-sky budget
    in the standard summaries (e.g. Wikipedia, "Sky brightness", relative contributions, after
    Roach & Gordon 1973 and Leinert et al. 1998); its size agrees with Walker 1988 (PASP 100,
    496: the V sky ~0.5 mag brighter at solar maximum) and Benn & Ellison 1998 (0.4 mag).
    brighter. Returns I(S) / I(0.8 MJy); linear outside 0.8-2.0 MJy within 50-400 sfu.
    """
    s = np.asarray(solar_flux_sfu, dtype=np.float64)
    lo, hi = SOLAR_FLUX_RANGE_SFU
    if np.any(~((s >= lo) & (s <= hi))):
        raise ParameterError(f"solar_flux_sfu = {solar_flux_sfu} is outside [{lo}, {hi}] sfu")
    mjy = s / 100.0
    return (145.0 + 130.0 * (mjy - 0.8) / 1.2) / 145.0


def airglow_zenith_s10(zenith_s10: float = AIRGLOW_ZENITH_S10, solar_flux_sfu=SOLAR_MINIMUM_SFU):
    """Zenith airglow (S10, V) for a solar-minimum zenith brightness and a solar flux (sfu)."""
    return float(zenith_s10) * float(solar_cycle_factor(solar_flux_sfu))


def airglow_luminance(
    zenith_rad,
    zenith_s10: float = AIRGLOW_ZENITH_S10,
    solar_flux_sfu=SOLAR_MINIMUM_SFU,
    layer_height_m: float = AIRGLOW_HEIGHT_M,
    observer_height_m: float = 0.0,
) -> np.ndarray:
    """Airglow luminance (cd/m^2) above the air at zenith angle ``zenith_rad`` (rad): the
    zenith value times the van Rhijn factor. The atmosphere's extinction is not included (the
    scene's atmosphere layer applies each ray's transmittance); 0 where the ray meets the
    ground (zenith angle beyond the horizon's dip for ``observer_height_m``)."""
    z = np.asarray(zenith_rad, dtype=np.float64)
    lum = s10_to_luminance(airglow_zenith_s10(zenith_s10, solar_flux_sfu))
    v = van_rhijn(z, layer_height_m, observer_height_m)
    return np.where(np.cos(z) >= -horizon_dip_sin(observer_height_m), lum * v, 0.0)


# ---------------------------------------------------------------------- spectrum

#: Emission lines of the night airglow, (wavelength nm, zenith intensity in rayleigh):
#: OI 557.7 and 630.0 nm from a mid-latitude spectroscopic survey 300-920 nm (Jones 1992,
#: PhD thesis, 1992PhDT.........8J: 320 R and 160 R); OI 636.4 nm from 630.0 nm by the ratio of
#: their transition probabilities, A(630.0) / A(636.4) = 5.63e-3 / 1.82e-3 s^-1 = 3.1 (NIST
#: atomic spectra database; Wiese et al. 1996); Na D1 589.6 nm 20 R, the 4-year Keck HIRES
#: mean (Slanger et al. 2005, JGR 110, D23302), with D2 589.0 nm taken equal to it.
AIRGLOW_LINES_R = (
    (557.73, 320.0),
    (630.03, 160.0),
    (636.38, 160.0 / 3.1),
    (588.99, 20.0),
    (589.59, 20.0),
)
#: OH Meinel bands (v', v'') with their intensities (R) from Jones 1992; each is spread
#: evenly over 8 nm starting at its band origin (the P branch lies to the red of it).
OH_BANDS_R = {(9, 4): 450.0, (8, 3): 450.0, (7, 2): 90.0, (7, 3): 1620.0, (6, 2): 970.0,
              (5, 1): 680.0, (4, 0): 190.0}  # fmt: skip
#: O2 band systems, (first nm, last nm, intensity R) from Jones 1992: Herzberg I 230 R over
#: 300-400 nm; Chamberlain 80 R and Herzberg II 80 R over 350-450 nm (spread evenly); the
#: atmospheric (0-1) band at 864.5 nm, 350 R.
O2_BANDS_R = ((300.0, 400.0, 230.0), (350.0, 450.0, 160.0), (862.0, 868.0, 350.0))
#: Airglow continuum (R/nm) at (672 nm, 870 nm): zenith-equivalent 22.5 and 22.0 mag/arcsec^2
#: (AB) measured between the OH lines at La Palma (Viuho, Fynbo & Andersen 2025, arXiv
#: 2506.02102), converted to photon radiance; linear between, constant outside.
CONTINUUM_R_PER_NM = ((672.0, 4.36), (870.0, 5.33))


def oh_band_origin_nm(v_upper: int, v_lower: int) -> float:
    """Vacuum wavelength (nm) of an OH X 2Pi (v', v'') band origin from the vibrational term
    values G(v) = we (v+1/2) - wexe (v+1/2)^2 + weye (v+1/2)^3 with we = 3737.76, wexe = 84.881,
    weye = 0.5409 cm^-1 (Huber & Herzberg 1979): e.g. (8-3) 728 nm, (6-2) 833 nm."""

    def g(v):
        x = v + 0.5
        return 3737.76 * x - 84.881 * x**2 + 0.5409 * x**3

    return 1e7 / (g(v_upper) - g(v_lower))


def airglow_spectrum(wavelengths_nm, step_nm: float = 1.0):
    """The airglow's photon spectrum on a fine grid: returns (grid_nm, R/nm) on
    ``step_nm`` bins covering ``wavelengths_nm``'s span, the lines put into their bins."""
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    grid = np.arange(np.floor(wl.min()), np.ceil(wl.max()) + step_nm, step_nm)
    (w0, c0), (w1, c1) = CONTINUUM_R_PER_NM
    photons = np.interp(grid, [w0, w1], [c0, c1])  # R/nm

    def add_band(first, last, intensity):
        inside = (grid >= first) & (grid < last)
        if np.any(inside):
            photons[inside] += intensity / (last - first)

    for (vu, vl), intensity in OH_BANDS_R.items():
        origin = oh_band_origin_nm(vu, vl)
        add_band(origin, origin + 8.0, intensity)
    for first, last, intensity in O2_BANDS_R:
        add_band(first, last, intensity)
    for line_nm, intensity in AIRGLOW_LINES_R:
        k = int(np.floor((line_nm - grid[0]) / step_nm + 0.5))
        if 0 <= k < len(grid):
            photons[k] += intensity / step_nm
    return grid, photons


def bin_relative_to_sun(grid_nm, radiance, wavelengths_nm) -> np.ndarray:
    """A spectral radiance on a fine grid (any energy units), as transfer values relative to
    the solar spectrum at ``wavelengths_nm`` (what SpectralBasis.colour takes): the radiance and
    the solar spectrum are both averaged with the hat weights of linear interpolation between
    the samples (flat beyond the ends, as spectral_to_rgbs_matrix interpolates), and divided.
    A spectrum of the solar shape gives exactly 1 at every sample."""

    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    g = np.asarray(grid_nm, dtype=np.float64)
    keep = (g >= WAVELENGTH_MIN_NM) & (g <= WAVELENGTH_MAX_NM)
    g, r = g[keep], np.asarray(radiance, dtype=np.float64)[keep]
    eye = np.eye(len(wl))
    hats = np.stack([np.interp(g, wl, eye[i]) for i in range(len(wl))])  # (N, F)
    sun = solar_irradiance(g)
    return (hats @ r) / (hats @ sun)


def airglow_relative_spectrum(wavelengths_nm) -> np.ndarray:
    """The airglow's spectrum binned onto ``wavelengths_nm`` relative to the solar spectrum
    (energy units: photons times hc / lambda), for SpectralBasis.colour."""
    grid, photons = airglow_spectrum(wavelengths_nm)
    return bin_relative_to_sun(grid, photons / grid, wavelengths_nm)


def check_airglow_parameters(zenith_s10: float, solar_flux_sfu: float) -> tuple[float, float]:
    """Validated (zenith S10, solar flux sfu)."""
    s10 = check_range("airglow zenith_s10", zenith_s10, 0.0, 10_000.0, "S10")
    sfu = check_range("solar_flux_sfu", solar_flux_sfu, *SOLAR_FLUX_RANGE_SFU, "sfu")
    return s10, sfu
