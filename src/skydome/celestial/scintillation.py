"""Twinkling: the intensity scintillation of stars seen by the naked eye, float64 NumPy.

Amplitude
---------
Young (1967, AJ 72, 747; the form quoted by Dravins et al. 1997, PASP 109, 173)
gives the relative standard deviation of a star's intensity through an aperture of
diameter D (cm) integrated over t (s), at air mass X, for an observer at altitude h (m):

    sigma_I = 0.09 D^(-2/3) X^1.75 exp(-h / 8000 m) (2 t)^(-1/2).

For the naked eye we take a dark-adapted pupil D = 0.7 cm and the eye's integration time
t = 0.1 s: sigma_I = 0.255 at the zenith at sea level. Young's law is a weak-scintillation
result for apertures larger than the Fresnel zone (~5 cm); for a small aperture at large
air masses the scintillation saturates (Dravins et al. 1997 describe this regime: the
intensity statistics approach those of fully developed speckle, whose relative standard
deviation is 1). Young's value therefore grows without bound towards the horizon
(X^1.75: 17x at X = 5) while the real one levels off; we cap it smoothly at
``SATURATED_SIGMA`` = 1, sigma = s / sqrt(1 + (s / 1)^2), which keeps the amplitude
increasing with air mass (zenith < horizon) and equal to Young's where it is small
(within 3 % below s = 0.25).

The air mass is Kasten & Young's (1989, Applied Optics 28, 4735) formula of the apparent
altitude, finite at the horizon (X = 38).

Time dependence
---------------
Each star's log-intensity is a smooth, seeded random function of time: a sum of K
sinusoids with random frequencies in [0.5, 4] Hz (several changes a second, like the eye
sees) and random phases, of unit variance, so nearly Gaussian (central limit). The factor
is exp(s g(t)) / E[exp(s g)], with s^2 = ln(1 + sigma_I^2) (the lognormal whose relative
standard deviation is sigma_I) and E[exp(s g)] = prod_k I0(s a_k), the exact time mean of
the exponential of a sum of incommensurate sinusoids of amplitudes a_k: the mean factor
over time is 1, so twinkling conserves each star's light on average. The same seed and
time give the same factors. Numerics: the phases are float64 at the start of each
EPOCH_S = 1024 s stretch and float32 within it (g to < 0.01 of the float64 sum).
"""

from __future__ import annotations

import numpy as np

from skydome.errors import ParameterError
from skydome.physics.airmass import kasten_young_airmass

#: Dark-adapted pupil diameter, cm.
EYE_APERTURE_CM = 0.7
#: The eye's integration time, s.
EYE_INTEGRATION_S = 0.1
#: Relative standard deviation of fully saturated scintillation (exponential statistics).
SATURATED_SIGMA = 1.0
#: Sinusoids per star.
TERMS = 12
#: Frequencies of the sinusoids, Hz.
FREQUENCY_RANGE_HZ = (0.5, 4.0)
#: The phases are kept in float64 at the start of stretches this long (s), float32 within.
EPOCH_S = 1024.0


def airmass_kasten_young(apparent_altitude_rad) -> np.ndarray:
    """Relative air mass X at an apparent altitude (rad), Kasten & Young (1989):
    X = 1 / (sin h + 0.50572 (h_deg + 6.07995)^-1.6364); the horizon's value below it, and
    at least 1 (the fit gives 0.9997 at the zenith)."""
    h = np.maximum(np.asarray(apparent_altitude_rad, dtype=np.float64), 0.0)
    return np.maximum(kasten_young_airmass(0.5 * np.pi - h), 1.0)


def young_sigma(
    airmass,
    *,
    aperture_cm: float = EYE_APERTURE_CM,
    exposure_s: float = EYE_INTEGRATION_S,
    altitude_m: float = 0.0,
) -> np.ndarray:
    """Young's (1967) relative standard deviation of a star's intensity (uncapped)."""
    x = np.asarray(airmass, dtype=np.float64)
    if np.any(~(x >= 1.0)):
        raise ParameterError(f"air mass must be >= 1, got {np.min(x)!r}")
    if not aperture_cm > 0 or not exposure_s > 0:
        raise ParameterError(
            f"aperture ({aperture_cm!r} cm) and exposure ({exposure_s!r} s) must be positive"
        )
    return (
        0.09
        * aperture_cm ** (-2.0 / 3.0)
        * x**1.75
        * np.exp(-float(altitude_m) / 8000.0)
        * (2.0 * exposure_s) ** -0.5
    )


def scintillation_sigma(apparent_altitude_rad, altitude_m: float = 0.0) -> np.ndarray:
    """Naked-eye relative standard deviation of intensity at apparent altitudes (rad):
    Young's law for the eye, capped smoothly at SATURATED_SIGMA."""
    s = young_sigma(airmass_kasten_young(apparent_altitude_rad), altitude_m=altitude_m)
    return s / np.sqrt(1.0 + (s / SATURATED_SIGMA) ** 2)


def bessel_i0(x) -> np.ndarray:
    """Modified Bessel function I0 for |x| <= 3.75: Abramowitz & Stegun (1964) 9.8.1,
    relative error < 1.6e-7 (np.i0 is ~50x slower; here |x| <= 0.34)."""
    t2 = (np.asarray(x, dtype=np.float64) / 3.75) ** 2
    if np.any(t2 > 1.0):
        raise ParameterError("bessel_i0 is for |x| <= 3.75")
    return 1.0 + t2 * (
        3.5156229
        + t2 * (3.0899424 + t2 * (1.2067492 + t2 * (0.2659732 + t2 * (0.0360768 + t2 * 0.0045813))))
    )


class Scintillation:
    """Seeded twinkling factors for ``n`` stars (see the module docstring)."""

    def __init__(self, n: int, seed: int = 0):
        if int(n) < 0:
            raise ParameterError(f"number of stars must be >= 0, got {n!r}")
        rng = np.random.default_rng(int(seed))
        self.n = int(n)
        lo, hi = FREQUENCY_RANGE_HZ
        self.frequency_hz = rng.uniform(lo, hi, (self.n, TERMS))
        self.phase = rng.uniform(0.0, 2.0 * np.pi, (self.n, TERMS))
        self.amplitude = np.sqrt(2.0 / TERMS)  # unit variance of the sum
        self._frequency32 = self.frequency_hz.astype(np.float32)
        self._epoch: float | None = None
        self._cycles_at_epoch: np.ndarray | None = None  # float32, every star and term

    def _cycles(self, epoch_s: float) -> np.ndarray:
        """Each term's phase in cycles at ``epoch_s`` (float64 whole cycles dropped, then
        float32; recomputed when the epoch changes)."""
        if self._epoch != epoch_s:
            cycles = self.frequency_hz * epoch_s  # up to 1e10 cycles: float64
            cycles -= np.floor(cycles)
            cycles += self.phase / (2.0 * np.pi)
            self._cycles_at_epoch = cycles.astype(np.float32)
            self._epoch = epoch_s
        return self._cycles_at_epoch

    def gaussian(self, t_s: float, index=slice(None)) -> np.ndarray:
        """The unit-variance process g(t) of the stars ``index`` at time ``t_s`` (s)."""
        # From the phases at the start of the EPOCH_S-long stretch holding t_s (float64
        # once per stretch), the rest in float32: at most 4 Hz x 1024 s = 4096 cycles
        # further, so the phases keep ~3e-4 cycles (2e-3 rad: nothing one could see) and
        # depend on t_s alone. A third of the cost of float64 throughout.
        t = float(t_s)
        epoch = np.floor(t / EPOCH_S) * EPOCH_S
        arg = self._frequency32[index] * np.float32(t - epoch)
        arg += self._cycles(float(epoch))[index]
        arg -= np.floor(arg)
        arg *= np.float32(2.0 * np.pi)
        np.cos(arg, out=arg)
        return self.amplitude * arg.sum(axis=-1, dtype=np.float64)

    def factors(self, t_s: float, sigma, index=slice(None)) -> np.ndarray:
        """Intensity factors (time mean exactly 1) of the stars ``index`` at time ``t_s``
        (s, any origin) for relative standard deviations ``sigma`` (one per star)."""
        s2 = np.log1p(np.asarray(sigma, dtype=np.float64) ** 2)
        s = np.sqrt(s2)
        g = self.gaussian(t_s, index)
        log_mean = TERMS * np.log(bessel_i0(s * self.amplitude))
        return np.exp(s * g - log_mean)
