"""Spectra and colour: wavelength grids, CIE tables, solar spectrum, ozone, XYZ/sRGB."""

from skydome.spectra.colour import (
    LINEAR_SRGB_TO_XYZ,
    LUMINOUS_SOLAR_CONSTANT_LX,
    PHOTOPIC_EFFICACY_LM_PER_W,
    SCOTOPIC_EFFICACY_LM_PER_W,
    SRGB_LUMINANCE,
    XYZ_TO_LINEAR_SRGB,
    conversion_matrix,
    linear_srgb_to_xyz,
    luminance,
    solar_luminance,
    spectral_to_rgbs_matrix,
    xyz_to_linear_srgb,
)
from skydome.spectra.grids import ACCURATE_NM, FAST_NM, wavelengths
from skydome.spectra.tables import (
    SURFACES,
    cmf_xyz,
    ozone_cross_section,
    photopic_efficiency,
    scotopic_efficiency,
    solar_irradiance,
    surface_albedo,
)

__all__ = [
    "ACCURATE_NM",
    "FAST_NM",
    "LINEAR_SRGB_TO_XYZ",
    "LUMINOUS_SOLAR_CONSTANT_LX",
    "PHOTOPIC_EFFICACY_LM_PER_W",
    "SCOTOPIC_EFFICACY_LM_PER_W",
    "SRGB_LUMINANCE",
    "SURFACES",
    "XYZ_TO_LINEAR_SRGB",
    "cmf_xyz",
    "conversion_matrix",
    "linear_srgb_to_xyz",
    "luminance",
    "ozone_cross_section",
    "photopic_efficiency",
    "scotopic_efficiency",
    "solar_luminance",
    "solar_irradiance",
    "spectral_to_rgbs_matrix",
    "surface_albedo",
    "wavelengths",
    "xyz_to_linear_srgb",
]
