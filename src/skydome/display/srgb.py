"""sRGB transfer function (IEC 61966-2-1:1999) and 8-bit quantization.

The encoding maps linear display values in [0, 1] to non-linear code values in [0, 1]:

    V = 12.92 L                     for L <= 0.0031308
    V = 1.055 L^(1/2.4) - 0.055     otherwise

and the decoding is its inverse (breakpoint 0.04045 = 12.92 * 0.0031308 in code values).
The GLSL twin is ``shaders/common/srgb.glsl``.
"""

from __future__ import annotations

import numpy as np

#: Linear-side breakpoint of the sRGB curve (IEC 61966-2-1).
SRGB_LINEAR_BREAK = 0.0031308
#: Encoded-side breakpoint of the sRGB curve (IEC 61966-2-1).
SRGB_ENCODED_BREAK = 0.04045


def srgb_encode(linear: np.ndarray | float) -> np.ndarray:
    """Encode linear display values (dimensionless, [0, 1]) with the sRGB curve.

    Inputs are clipped to [0, 1] first; returns float64 code values in [0, 1].

    GLSL twin: ``srgb_encode``.
    """
    v = np.clip(np.asarray(linear, dtype=np.float64), 0.0, 1.0)
    return np.where(
        v <= SRGB_LINEAR_BREAK,
        12.92 * v,
        1.055 * np.power(np.maximum(v, SRGB_LINEAR_BREAK), 1.0 / 2.4) - 0.055,
    )


def srgb_decode(encoded: np.ndarray | float) -> np.ndarray:
    """Decode sRGB code values (dimensionless, [0, 1]) to linear display values.

    Inputs are clipped to [0, 1] first; returns float64 linear values in [0, 1].

    GLSL twin: ``srgb_decode``.
    """
    v = np.clip(np.asarray(encoded, dtype=np.float64), 0.0, 1.0)
    return np.where(
        v <= SRGB_ENCODED_BREAK,
        v / 12.92,
        np.power((np.maximum(v, SRGB_ENCODED_BREAK) + 0.055) / 1.055, 2.4),
    )


def quantize8(encoded: np.ndarray) -> np.ndarray:
    """Quantize code values in [0, 1] to uint8 by rounding to nearest (half up).

    ``round(v * 255)``: 0.5/255 steps round up, values outside [0, 1] are clipped.
    """
    v = np.clip(np.asarray(encoded, dtype=np.float64), 0.0, 1.0)
    return np.floor(v * 255.0 + 0.5).astype(np.uint8)
