"""Exposure: from absolute luminance (cd/m^2) to "exposed" relative units.

Every function here returns a scalar **exposure scale** ``s`` (unit m^2/cd): exposed value =
``s * frame`` (photopic channels). Tone-mapping operators (``skydome.display.tonemap``) take
exposed values, where 1.0 is the sensor's saturation point.

**EV100 convention** (saturation-based sensor, ISO 12232; as in Lagarde & de Rousiers,
"Moving Frostbite to Physically Based Rendering", SIGGRAPH 2014 course notes, sec. 5.1):
a camera of speed S, aperture N and shutter time t saturates at

    L_max = (78 / (q S)) * N^2 / t   cd/m^2,     q = 0.65 (lens and vignetting factor),

so at ISO 100, with EV100 = log2(N^2 / t):

    L_max = 1.2 * 2^EV100 cd/m^2,        s = 1 / L_max = 1 / (1.2 * 2^EV100).

EV 0 maps 1.2 cd/m^2 to 1.0; each +1 EV halves the scale. With automatic exposure (key 0.18)
EV100 = log2(L_avg / (1.2 * 0.18)): a clear noon sky (L_avg 5000-10000 cd/m^2) is EV 14.5-15.5,
an overcast day (~2000) EV 13, a sunset sky (~500) EV 11, a full-moon sky (~0.03) EV -3, a
moonless night sky (~2e-4) EV -10. Exposure compensation (in EV) multiplies the scale by 2^compensation (+1 EV =
twice as bright an image), as on a camera.

**Automatic exposure** uses the log-average luminance of Reinhard et al., "Photographic tone
reproduction for digital images", SIGGRAPH 2002, eq. 1, mapped to a key value (eq. 2):
``s = key / L_avg``. A uniform frame of any luminance therefore becomes exactly ``key``.
"""

from __future__ import annotations

import math

import numpy as np

from skydome.errors import ParameterError, check_range
from skydome.spectra import SRGB_LUMINANCE

#: L_max / 2^EV100 for a saturation-based ISO 100 sensor: 78 / (0.65 * 100) = 1.2 cd/m^2.
SATURATION_LUMINANCE_EV0 = 78.0 / (0.65 * 100.0)
#: Default key value (Reinhard 2002: 0.18, "middle grey").
DEFAULT_KEY = 0.18
#: Default delta of Reinhard 2002 eq. 1 (cd/m^2): far below the darkest natural night sky
#: (~2e-4 cd/m^2), so it only guards log(0) for black pixels.
DEFAULT_DELTA = 1e-6
#: Range of EV100 accepted: from deep space (-20) to staring at the Sun (+40).
EV_RANGE = (-20.0, 40.0)
#: Range of exposure compensation accepted, in EV.
COMPENSATION_RANGE = (-20.0, 20.0)


def ev100_to_scale(ev100: float, compensation_ev: float = 0.0) -> float:
    """Exposure scale (m^2/cd) for an exposure value EV100 and a compensation (EV).

    ``s = 2^compensation / (1.2 * 2^EV100)``: the luminance ``1.2 * 2^(EV100 - compensation)``
    cd/m^2 maps to 1.0. Raises ParameterError outside EV [-20, 40] or compensation [-20, 20].
    """
    ev = check_range("exposure", ev100, *EV_RANGE, "EV")
    comp = check_range("exposure compensation", compensation_ev, *COMPENSATION_RANGE, "EV")
    return 2.0 ** (comp - ev) / SATURATION_LUMINANCE_EV0


def scale_to_ev100(scale: float) -> float:
    """The EV100 whose exposure scale (m^2/cd, no compensation) is ``scale``; inverse of
    :func:`ev100_to_scale`. Useful to report what automatic exposure chose."""
    s = float(scale)
    if not (math.isfinite(s) and s > 0.0):
        raise ParameterError(f"exposure scale = {scale!r} must be a finite positive number")
    return -math.log2(s * SATURATION_LUMINANCE_EV0)


def _is_frame_object(frame) -> bool:
    return not isinstance(frame, np.ndarray) and isinstance(
        getattr(frame, "data", None), np.ndarray
    )


def _photopic_luminance(frame: np.ndarray) -> np.ndarray:
    """Luminance (cd/m^2) of a frame (H, W, 4) / (H, W, 3), or the array itself if 2-D."""
    a = np.asarray(frame.data if _is_frame_object(frame) else frame)
    if a.ndim == 3 and a.shape[-1] in (3, 4):
        return a[..., :3].astype(np.float64) @ SRGB_LUMINANCE
    if a.ndim == 2:
        return a.astype(np.float64)
    raise ParameterError(
        f"frame of shape {a.shape} is not a (H, W, 4) or (H, W, 3) frame or an (H, W) "
        "luminance image"
    )


#: Frames larger than this are averaged over a regular subgrid of about this many pixels.
AVERAGE_MAX_PIXELS = 1 << 22


def log_average_luminance(
    frame: np.ndarray, *, delta: float = DEFAULT_DELTA, clip_percentile: float | None = None
) -> float:
    """Log-average luminance (cd/m^2), Reinhard et al. 2002 eq. 1, unbiased by delta.

    ``L_avg = exp(mean(log(delta + L))) - delta`` over the finite, lit pixels (NaN and +-Inf
    are ignored, and so are pixels with L <= 0: pixels outside a fisheye's circle, empty
    space, unlit ground, which carry no light for the eye to adapt to). Subtracting delta again removes eq. 1's bias,
    so a uniform frame of luminance L gives exactly L; for L >> delta it changes nothing.
    The result is at least ``delta`` (an all-black frame gives delta).

    Args:
        frame: (H, W, 4) or (H, W, 3) frame in cd/m^2, or an (H, W) luminance image.
        delta: guard against log(0) for black pixels, cd/m^2 (> 0).
        clip_percentile: if given (in (0, 100]), luminances above this percentile are clipped
            to it first, so that a few very bright pixels (the Sun's disc, 1e9 cd/m^2) do not
            darken the rest of the image. E.g. 99.5.
    """
    d = check_range("delta", delta, 1e-30, 1e30, "cd/m^2")
    a = np.asarray(frame.data if _is_frame_object(frame) else frame)
    if a.ndim >= 2 and a.shape[0] * a.shape[1] > AVERAGE_MAX_PIXELS:
        # A regular grid of about every k-th row and column (at most AVERAGE_MAX_PIXELS
        # pixels) for large frames: the log-average of 4 million evenly spread samples of a smooth sky
        # is within 0.1 % of the full one (tested), at a fraction of the memory.
        # Rows and columns spread symmetrically over the frame, edges included, so a gradient
        # across the frame averages as it does over every pixel.
        k = math.sqrt(a.shape[0] * a.shape[1] / AVERAGE_MAX_PIXELS)
        rows, cols = (
            np.linspace(0, n - 1, max(2, int(n / k))).round().astype(int) for n in a.shape[:2]
        )
        a = a[np.ix_(rows, cols)]
    lum = _photopic_luminance(a).ravel()
    lum = lum[np.isfinite(lum)]
    if lum.size == 0:
        raise ParameterError("cannot expose a frame with no finite pixels")
    lum = lum[lum > 0.0]
    if lum.size == 0:
        return d
    if clip_percentile is not None:
        p = check_range("clip percentile", clip_percentile, 1e-9, 100.0, "%")
        lum = np.minimum(lum, np.percentile(lum, p))
    avg = math.exp(float(np.mean(np.log(d + lum)))) - d  # Reinhard 2002 eq. 1
    return max(avg, d)


def auto_exposure(
    frame: np.ndarray,
    *,
    key: float = DEFAULT_KEY,
    compensation_ev: float = 0.0,
    clip_percentile: float | None = None,
    delta: float = DEFAULT_DELTA,
) -> float:
    """Exposure scale (m^2/cd) that maps the frame's log-average luminance to ``key``.

    ``s = 2^compensation * key / L_avg`` (Reinhard 2002 eq. 2 with eq. 1 for ``L_avg``, see
    :func:`log_average_luminance` for ``delta`` and ``clip_percentile``). NaN pixels are
    ignored. A uniform frame of any luminance is mapped exactly to ``key`` (up to float64
    rounding). Use :func:`scale_to_ev100` to report the equivalent EV100.

    Args:
        frame: (H, W, 4) frame in cd/m^2 (or (H, W, 3), or an (H, W) luminance image).
        key: exposed value of the log-average luminance, in (0, 1]; 0.18 is middle grey.
        compensation_ev: exposure compensation, EV (+1 = twice as bright).
        clip_percentile: clip luminances above this percentile before averaging (excludes
            the Sun), e.g. 99.5; None uses every pixel.
        delta: guard of eq. 1 against black pixels, cd/m^2.
    """
    k = check_range("key", key, 1e-6, 1.0)
    comp = check_range("exposure compensation", compensation_ev, *COMPENSATION_RANGE, "EV")
    avg = log_average_luminance(frame, delta=delta, clip_percentile=clip_percentile)
    return 2.0**comp * k / avg
