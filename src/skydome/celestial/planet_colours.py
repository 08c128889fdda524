"""The planets' colours: a smooth geometric-albedo spectrum per planet, fitted to photometry.

What is known of each planet's colour here is its disk-integrated geometric albedo in three
broad bands, Johnson B and V and Cousins R, from Mallama, Krobusek & Pavlov (2017),
"Comprehensive wide-band magnitudes and albedos for the planets, with applications to
exo-planets and Planet Nine", Icarus 282, 19-33, Table 7 (arXiv:1609.05048 p. 16; the values
below were read from the transcription of that table in a public planet-photometry project,
whose review report lists B, V and Rc per planet). A band albedo is the solar-weighted mean
of the albedo spectrum through the band, so the ratios p_B / p_V and p_R / p_V are the
planet's colour indices relative to the Sun's:

    (B - V)_planet = (B - V)_sun - 2.5 log10(p_B / p_V).

Each planet's albedo spectrum is taken as the smooth curve

    ln p(lambda) = c0 + c1 x + c2 x^2,   x = (lambda - 550 nm) / 100 nm,

with (c1, c2) solved so that its band means give exactly the published p_B / p_V and
p_R / p_V, and c0 so that its V mean is p_V. Two colours fix two shape parameters; the curve
is a colour model (it has no methane bands: Jupiter's and Saturn's 619 and 727 nm bands and
the red absorption of Uranus and Neptune appear only as the curve's overall red slope).

Passbands: Bessell (1990), "UBVRI passbands", PASP 102, 1181, Table 2 (B and V at 10 nm, R
at 10 nm to 750 nm then 50 nm), the definitions of the Johnson-Cousins system used in
synthetic photometry, taken as energy response functions (band mean = integral of
F p S / integral of F S over wavelength; counting photons instead, F lambda, shifts the
colours here by under 0.005 mag). The solar spectrum is the package's ASTM G-173 table
(skydome.spectra.solar_irradiance), which ends at 830 nm: the R band's tail beyond it (1.4 %
of its weight) is left out of both integrals, which changes a band mean by under 1 % for
the reddest slope here (Uranus).

The Sun's own colour, for quoting planet colours as B - V: 0.653 +- 0.003 (Ramirez et al.
2012, ApJ 752, 5).
"""

from __future__ import annotations

from functools import cache

import numpy as np

from skydome.errors import ParameterError
from skydome.spectra.tables import WAVELENGTH_MAX_NM, WAVELENGTH_MIN_NM, solar_irradiance

__all__ = [
    "PLANET_BAND_ALBEDOS",
    "SUN_B_MINUS_V",
    "band_albedo",
    "planet_albedo",
    "planet_albedo_coefficients",
    "published_b_minus_v",
    "synthetic_b_minus_v",
]

#: Geometric albedos (B, V, Rc) of Mallama et al. (2017) Table 7. Saturn's is the globe and
#: rings at their standard geometry; several entries of the table are synthetic (computed by
#: the authors from published spectra: Mercury's B and Rc, Saturn's Rc, Mars's Rc).
PLANET_BAND_ALBEDOS: dict[str, tuple[float, float, float]] = {
    "mercury": (0.105, 0.142, 0.158),
    "venus": (0.658, 0.689, 0.658),
    "mars": (0.088, 0.170, 0.250),
    "jupiter": (0.443, 0.538, 0.513),
    "saturn": (0.339, 0.499, 0.646),
    "uranus": (0.561, 0.488, 0.264),
    "neptune": (0.562, 0.442, 0.226),
}

#: The Sun's B - V (Ramirez et al. 2012, ApJ 752, 5: 0.653 +- 0.003).
SUN_B_MINUS_V = 0.653

# Bessell (1990) Table 2, normalised responses: (first wavelength nm, step nm, values).
_BESSELL_B = (360.0, 10.0, (
    0.0, 0.030, 0.134, 0.567, 0.920, 0.978, 1.000, 0.978, 0.935, 0.853, 0.740, 0.640, 0.536,
    0.424, 0.325, 0.235, 0.150, 0.095, 0.043, 0.009, 0.0,
))  # fmt: skip
_BESSELL_V = (470.0, 10.0, (
    0.0, 0.030, 0.163, 0.458, 0.780, 0.967, 1.000, 0.973, 0.898, 0.792, 0.684, 0.574, 0.461,
    0.359, 0.270, 0.197, 0.135, 0.081, 0.045, 0.025, 0.017, 0.013, 0.009, 0.0,
))  # fmt: skip
_BESSELL_R_NM = np.concatenate([np.arange(550.0, 751.0, 10.0), [800.0, 850.0, 900.0]])
_BESSELL_R = (
    0.0, 0.23, 0.74, 0.91, 0.98, 1.0, 0.98, 0.96, 0.93, 0.90, 0.86, 0.81, 0.78, 0.72, 0.67,
    0.61, 0.56, 0.51, 0.46, 0.40, 0.35, 0.14, 0.03, 0.0,
)  # fmt: skip

BANDS = ("B", "V", "R")
#: The integration grid (nm): 1 nm over the solar table's range.
_GRID_NM = np.arange(WAVELENGTH_MIN_NM, WAVELENGTH_MAX_NM + 0.5, 1.0)


def _check_planet(planet: str) -> str:
    p = str(planet).lower()
    if p not in PLANET_BAND_ALBEDOS:
        raise ParameterError(f"planet = {planet!r} is not one of {', '.join(PLANET_BAND_ALBEDOS)}")
    return p


def passband(band: str, wavelengths_nm) -> np.ndarray:
    """Bessell (1990) response of ``band`` ("B", "V" or "R") at ``wavelengths_nm``, peak 1,
    linear between the tabulated points and 0 outside them."""
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    if band == "B" or band == "V":
        start, step, values = _BESSELL_B if band == "B" else _BESSELL_V
        nodes = start + step * np.arange(len(values))
    elif band == "R":
        nodes, values = _BESSELL_R_NM, _BESSELL_R
    else:
        raise ParameterError(f"band = {band!r} is not one of {', '.join(BANDS)}")
    return np.interp(wl, nodes, np.asarray(values), left=0.0, right=0.0)


@cache
def _weights() -> dict[str, np.ndarray]:
    """Per band, the normalised weights F_sun S_X on the 1 nm grid (sum 1)."""
    sun = solar_irradiance(_GRID_NM)
    out = {}
    for band in BANDS:
        w = sun * passband(band, _GRID_NM)
        out[band] = w / w.sum()
    return out


def band_albedo(band: str, wavelengths_nm, albedo) -> float:
    """Solar-weighted mean of an albedo spectrum (sampled at ``wavelengths_nm``, linear
    between samples, within 360-830 nm) through the Bessell (1990) ``band``."""
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    p = np.asarray(albedo, dtype=np.float64)
    if wl.shape != p.shape or wl.ndim != 1 or wl.size < 2:
        raise ParameterError("an albedo spectrum needs matching 1-D wavelengths and values")
    weights = _weights()
    if band not in weights:
        raise ParameterError(f"band = {band!r} is not one of {', '.join(BANDS)}")
    return float(weights[band] @ np.interp(_GRID_NM, wl, p))


def synthetic_b_minus_v(wavelengths_nm, albedo) -> float:
    """B - V of sunlight reflected with this albedo spectrum (mag): the Sun's plus
    -2.5 log10(p_B / p_V)."""
    ratio = band_albedo("B", wavelengths_nm, albedo) / band_albedo("V", wavelengths_nm, albedo)
    return SUN_B_MINUS_V - 2.5 * float(np.log10(ratio))


def published_b_minus_v(planet: str) -> float:
    """B - V of ``planet`` from Mallama et al. (2017)'s B and V albedos (mag)."""
    p_b, p_v, _ = PLANET_BAND_ALBEDOS[_check_planet(planet)]
    return SUN_B_MINUS_V - 2.5 * float(np.log10(p_b / p_v))


def _log_albedo(c: np.ndarray, wl: np.ndarray) -> np.ndarray:
    x = (wl - 550.0) / 100.0
    return c[0] + c[1] * x + c[2] * x * x


@cache
def planet_albedo_coefficients(planet: str) -> tuple[float, float, float]:
    """(c0, c1, c2) of ln p = c0 + c1 x + c2 x^2 (x = (lambda - 550 nm) / 100 nm) whose band
    means are Mallama et al. (2017)'s B, V and R albedos (Newton's method; converges to
    1e-12 in the ratios within 6 steps from a grey start)."""
    p = _check_planet(planet)
    p_b, p_v, p_r = PLANET_BAND_ALBEDOS[p]
    target = np.log([p_b / p_v, p_r / p_v])
    w = _weights()

    def residual(shape: np.ndarray) -> np.ndarray:
        a = np.exp(_log_albedo(np.array([0.0, *shape]), _GRID_NM))
        v = w["V"] @ a
        return np.log([(w["B"] @ a) / v, (w["R"] @ a) / v]) - target

    shape = np.zeros(2)
    for _ in range(50):
        r = residual(shape)
        if np.max(np.abs(r)) < 1e-12:
            break
        jac = np.empty((2, 2))
        for k in range(2):
            step = np.zeros(2)
            step[k] = 1e-6
            jac[:, k] = (residual(shape + step) - r) / 1e-6
        shape = shape - np.linalg.solve(jac, r)
    else:  # pragma: no cover - the fit is smooth and two-dimensional
        raise ParameterError(f"the colour fit of {p} did not converge")
    a = np.exp(_log_albedo(np.array([0.0, *shape]), _GRID_NM))
    c0 = float(np.log(p_v / (w["V"] @ a)))
    return c0, float(shape[0]), float(shape[1])


def planet_albedo(planet: str, wavelengths_nm) -> np.ndarray:
    """The fitted geometric albedo spectrum of ``planet`` at ``wavelengths_nm`` (nm): the
    planet's light relative to the Sun's, for ``SpectralBasis.colour``."""
    c = np.array(planet_albedo_coefficients(_check_planet(planet)))
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    if not np.all(np.isfinite(wl)) or np.any(wl <= 0.0):
        raise ParameterError(f"wavelengths must be positive nm, got {wavelengths_nm}")
    return np.exp(_log_albedo(c, wl))
