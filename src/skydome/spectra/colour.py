"""Colour: XYZ <-> linear sRGB and the conversion of sampled spectra to luminance.

Frames are linear sRGB (Rec. 709 primaries, D65 white) scaled so that Y is the photopic
luminance in cd/m^2; a fourth channel carries the scotopic luminance in scotopic cd/m^2.
"""

from __future__ import annotations

import functools

import numpy as np

from skydome.errors import ParameterError
from skydome.spectra.tables import (
    WAVELENGTH_MAX_NM,
    WAVELENGTH_MIN_NM,
    cmf_xyz,
    scotopic_efficiency,
    solar_irradiance,
)

#: Maximum photopic luminous efficacy, lm/W (CIE; defines the candela at 555 nm).
PHOTOPIC_EFFICACY_LM_PER_W = 683.0
#: Maximum scotopic luminous efficacy, lm/W (CIE 1951, at 507 nm).
SCOTOPIC_EFFICACY_LM_PER_W = 1700.0

#: Luminous solar constant, lx: the Sun's illuminance at 1 au outside the atmosphere, on a
#: surface facing it. Darula, Kittler & Gueymard (2005), "Reference luminous solar constant
#: and solar luminance for illuminance calculations", LEUKOS 1(3), 25-44: 133 334 lx, from
#: Gueymard's extraterrestrial spectrum (the one ASTM G-173 tabulates, 1366.1 W/m^2) weighted
#: with the CIE V(lambda) and 683 lm/W at full resolution. skydome's single value of it: the
#: astronomy layer (``skydome.astro.photometry.SOLAR_ILLUMINANCE_1AU_LX``) uses it, and the
#: renderer's Sun, which is the packaged ASTM G-173 table integrated the same way
#: (``spectral_to_rgbs_matrix``), is tested against it. That integral is 133 177 lx, 0.12 %
#: lower: the package holds the spectrum as 10 nm bin means, interpolated linearly between
#: bin centres, which smooths the product E(lambda) V(lambda) over each bin (the 360-830 nm
#: range loses < 1e-5 of V). The total solar irradiance 1361 W/m^2 (Kopp & Lean 2011) is on
#: a radiometric scale 0.37 % lower than the spectrum's 1366.1 W/m^2; the luminous constant
#: is kept on the spectrum's scale so that the Sun of the astronomy layer and the Sun of
#: the renderer agree.
LUMINOUS_SOLAR_CONSTANT_LX = 133_334.0

#: XYZ -> linear sRGB (IEC 61966-2-1, D65).
XYZ_TO_LINEAR_SRGB = np.array(
    [
        [3.2404542, -1.5371385, -0.4985314],
        [-0.9692660, 1.8760108, 0.0415560],
        [0.0556434, -0.2040259, 1.0572252],
    ]
)
LINEAR_SRGB_TO_XYZ = np.linalg.inv(XYZ_TO_LINEAR_SRGB)
#: Luminance weights of linear sRGB (the Y row of LINEAR_SRGB_TO_XYZ).
SRGB_LUMINANCE = LINEAR_SRGB_TO_XYZ[1]


def xyz_to_linear_srgb(xyz: np.ndarray) -> np.ndarray:
    """Convert XYZ (..., 3) to linear sRGB (..., 3); Y is preserved as luminance."""
    return np.asarray(xyz) @ XYZ_TO_LINEAR_SRGB.T


def linear_srgb_to_xyz(rgb: np.ndarray) -> np.ndarray:
    """Convert linear sRGB (..., 3) to XYZ (..., 3)."""
    return np.asarray(rgb) @ LINEAR_SRGB_TO_XYZ.T


def luminance(rgb: np.ndarray) -> np.ndarray:
    """Photopic luminance Y of linear sRGB values (same units as the input)."""
    return np.asarray(rgb)[..., :3] @ SRGB_LUMINANCE


_FINE_STEP_NM = 1.0


def _hat_weights(fine: np.ndarray, samples: np.ndarray) -> np.ndarray:
    """Weights (len(fine), len(samples)) of piecewise-linear interpolation, flat at the ends."""
    eye = np.eye(len(samples))
    return np.stack([np.interp(fine, samples, eye[i]) for i in range(len(samples))], axis=-1)


def spectral_to_rgbs_matrix(wavelengths_nm, illuminant: str = "sun") -> np.ndarray:
    """Matrix (4, N) from N spectral samples to (R, G, B, scotopic) luminance.

    With ``illuminant="sun"`` the samples are a *transfer* spectrum f(λ): radiance per unit
    solar spectral irradiance (sr^-1). The radiance is taken to be f(λ)·E_sun(λ) with f
    interpolated linearly between the samples (f is smooth: it holds the atmosphere's
    scattering and extinction) and E_sun at full resolution, so the structure of the solar
    spectrum is not lost between samples. The result, with E_sun in W m^-2 nm^-1, is in
    cd/m^2 (linear sRGB with Y = luminance; 4th row scotopic cd/m^2).

    With ``illuminant="none"`` the samples are spectral radiance in W m^-2 sr^-1 nm^-1,
    interpolated linearly.
    """
    wl = np.sort(np.asarray(wavelengths_nm, dtype=np.float64))
    if not np.array_equal(wl, np.asarray(wavelengths_nm, dtype=np.float64)):
        raise ParameterError("wavelengths must be sorted in increasing order")
    fine = np.arange(WAVELENGTH_MIN_NM, WAVELENGTH_MAX_NM + 0.5 * _FINE_STEP_NM, _FINE_STEP_NM)
    weights = _hat_weights(fine, wl)  # (F, N)
    if illuminant == "sun":
        weights = weights * solar_irradiance(fine)[:, None]
    elif illuminant != "none":
        raise ParameterError(f"illuminant must be 'sun' or 'none', got {illuminant!r}")
    # Trapezoid rule on the 1 nm grid.
    dl = np.full(fine.shape, _FINE_STEP_NM)
    dl[0] = dl[-1] = 0.5 * _FINE_STEP_NM
    xyz = PHOTOPIC_EFFICACY_LM_PER_W * (cmf_xyz(fine) * dl[:, None]).T @ weights  # (3, N)
    rgb = XYZ_TO_LINEAR_SRGB @ xyz
    scot = SCOTOPIC_EFFICACY_LM_PER_W * (scotopic_efficiency(fine) * dl) @ weights  # (N,)
    return np.vstack([rgb, scot[None, :]])


#: The output channels a spectral conversion can give: (R, G, B, scotopic) luminance, or the
#: 4 wavelengths themselves (a debugging mode of the tables).
OUTPUTS = ("rgbs", "spectral")


def conversion_matrix(wavelengths_nm, output: str = "rgbs") -> np.ndarray:
    """(4, N) matrix from N transfer values (per unit solar irradiance) to output channels.

    ``"rgbs"``: (R, G, B, scotopic) luminance in cd/m^2 for the tabulated solar spectrum
    (:func:`spectral_to_rgbs_matrix`); ``"spectral"``: the identity (exactly 4 wavelengths).
    """
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    if output == "spectral":
        if len(wl) != 4:
            raise ParameterError("spectral output needs exactly 4 wavelengths")
        return np.eye(4)
    if output != "rgbs":
        raise ParameterError(f"output {output!r} must be one of {', '.join(OUTPUTS)}")
    return _rgbs_matrix_of(tuple(wl.tolist())).copy()


@functools.lru_cache(maxsize=32)
def _rgbs_matrix_of(wavelengths_nm: tuple[float, ...]) -> np.ndarray:
    """spectral_to_rgbs_matrix of a few wavelength sets, kept (0.3 ms each: every layer of
    every ``Sky.at`` asks for its basis's)."""
    return spectral_to_rgbs_matrix(np.asarray(wavelengths_nm))


def solar_luminance(wavelengths_nm) -> float:
    """Photopic luminance (cd/m^2) of transfer values of 1 at every wavelength (the
    tabulated solar spectrum at 1 au, 1 sr^-1), as the RGBS conversion of these wavelengths
    sees it."""
    rgbs = conversion_matrix(wavelengths_nm, "rgbs") @ np.ones(len(wavelengths_nm))
    return float(SRGB_LUMINANCE @ rgbs[:3])
