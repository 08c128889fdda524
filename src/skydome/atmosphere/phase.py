"""Aerosol phase functions given per wavelength: a mixture of Henyey-Greenstein lobes.

The Cornette-Shanks function with one asymmetry ``mie_g`` (``AtmosphereParams.mie_g``) suits
aerosols whose phase function changes little across the visible. Mineral dust of micron size
does not: its forward diffraction peak is about twice as high, and narrower, in the blue as in
the red (the peak's height grows as x^2 and its width as 1/x, x = 2 pi r / lambda), which is
what makes the Martian sky blue around the Sun. :class:`MiePhaseLobes` holds such a phase
function as non-negative weights w_j(lambda) of lobes HG(g_j) with fixed asymmetries g_j
(fitted to Mie theory by ``skydome.atmosphere.mie.fit_hg_lobes``):

    P(nu, lambda) = sum_j w_j(lambda) HG(nu, g_j),   sum_j w_j = 1,

evaluated by ``shaders/common/mie_phase.glsl`` for every wavelength, and for each output
channel (R, G, B, scotopic) with the weights averaged over the channel's spectral response
(the sum is linear in the weights).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from skydome.errors import ParameterError
from skydome.physics.phase import MAX_LOBES, henyey_greenstein

__all__ = ["MAX_LOBES", "MiePhaseLobes", "henyey_greenstein"]


@dataclass(frozen=True)
class MiePhaseLobes:
    """An aerosol phase function per wavelength: lobe asymmetries ``lobe_g`` (each in
    (-1, 1)), and for each of the increasing ``wavelengths_nm`` the lobes' non-negative
    ``weights`` (one row per wavelength, summing to 1). Linear in wavelength between rows,
    the end rows held outside."""

    lobe_g: tuple[float, ...]
    wavelengths_nm: tuple[float, ...]
    weights: tuple[tuple[float, ...], ...]

    def __post_init__(self):
        g = tuple(float(v) for v in self.lobe_g)
        wl = tuple(float(v) for v in self.wavelengths_nm)
        w = np.asarray(self.weights, float)
        if not 1 <= len(g) <= MAX_LOBES or not all(-1.0 < v < 1.0 for v in g):
            raise ParameterError(f"1 to {MAX_LOBES} lobes with asymmetries in (-1, 1), got {g}")
        if not wl or any(b <= a for a, b in zip(wl, wl[1:], strict=False)):
            raise ParameterError("phase-function wavelengths must increase")
        if w.shape != (len(wl), len(g)) or not np.all(np.isfinite(w)) or np.any(w < 0.0):
            raise ParameterError(
                f"phase-function weights: one row of {len(g)} non-negative values per wavelength"
            )
        if np.any(np.abs(w.sum(axis=1) - 1.0) > 1e-6):
            raise ParameterError("each wavelength's lobe weights must sum to 1")
        object.__setattr__(self, "lobe_g", g)
        object.__setattr__(self, "wavelengths_nm", wl)
        object.__setattr__(self, "weights", tuple(tuple(row) for row in w.tolist()))

    def weights_at(self, wavelengths_nm) -> np.ndarray:
        """Lobe weights (N, lobes) at the given wavelengths (nm)."""
        wl = np.atleast_1d(np.asarray(wavelengths_nm, float))
        w = np.asarray(self.weights)
        return np.stack([np.interp(wl, self.wavelengths_nm, w[:, j]) for j in range(w.shape[1])], 1)

    def asymmetry(self, wavelengths_nm) -> np.ndarray:
        """Mean cosine of the phase function at the wavelengths (nm): sum_j w_j g_j."""
        return self.weights_at(wavelengths_nm) @ np.asarray(self.lobe_g)

    def phase(self, cos_theta, wavelengths_nm) -> np.ndarray:
        """P (sr^-1), shape (cosines..., wavelengths)."""
        mu = np.asarray(cos_theta, float)[..., None, None]
        lobes = henyey_greenstein(mu, np.asarray(self.lobe_g))  # (..., 1, lobes)
        return np.sum(lobes * self.weights_at(wavelengths_nm), axis=-1)
