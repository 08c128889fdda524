"""Black-body spectra (Planck's law), for the colours of stars and of the Galaxy's light."""

from __future__ import annotations

import numpy as np

#: Second radiation constant c2 = h c / k (CODATA 2018), in nm K.
C2_NM_K = 1.438776877e7


def planck_relative(wavelengths_nm, temperature_k) -> np.ndarray:
    """Black-body spectral radiance up to a constant, lambda^-5 / (exp(c2 / lambda T) - 1),
    shape (len(wavelengths), len(temperatures)); c2 from CODATA 2018."""
    wl = np.asarray(wavelengths_nm, dtype=np.float64).reshape(-1)[:, None]
    t = np.asarray(temperature_k, dtype=np.float64).reshape(-1)[None, :]
    return wl**-5.0 / np.expm1(C2_NM_K / (wl * t))
