"""Wavelength grids used for spectral rendering (nm).

The renderer carries wavelengths in groups of four (one vec4 per group in GLSL).
"""

from __future__ import annotations

import numpy as np

from skydome.errors import ParameterError

#: Fast mode: four wavelengths spanning the colour matching functions.
FAST_NM = (440.0, 510.0, 580.0, 650.0)
#: Default (accurate) mode: 16 wavelengths, 380-755 nm every 25 nm.
ACCURATE_NM = tuple(380.0 + 25.0 * i for i in range(16))

MODES = {"fast": FAST_NM, "accurate": ACCURATE_NM}


def wavelengths(mode: str | tuple | list = "accurate") -> np.ndarray:
    """Wavelengths (nm) of a spectral mode ('fast', 'accurate') or a custom sorted list.

    A custom list must have a multiple of 4 entries, sorted, inside 360-830 nm.
    """
    if isinstance(mode, str):
        if mode not in MODES:
            raise ParameterError(
                f"unknown spectral mode {mode!r}; choose one of {', '.join(sorted(MODES))}"
            )
        return np.array(MODES[mode])
    wl = np.asarray(mode, dtype=np.float64)
    if wl.ndim != 1 or len(wl) == 0 or len(wl) % 4 or np.any(np.diff(wl) <= 0):
        raise ParameterError(
            f"custom wavelengths must be a sorted list of 4, 8, 12, ... values, got {list(wl)}"
        )
    if wl[0] < 360 or wl[-1] > 830:
        raise ParameterError(f"wavelengths must lie in [360, 830] nm, got {list(wl)}")
    return wl
