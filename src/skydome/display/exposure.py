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


# -- Metering -------------------------------------------------------------------------------
#: Metering modes: where in the frame the exposure is measured, and how the key is chosen.
#: ``average``: every lit pixel alike, key 0.18 (the automatic exposure before metering modes
#: existed). ``center``: centre-weighted (a Gaussian of CENTER_SIGMA_FRACTION of the frame's
#: height), key 0.18. ``spot``: a disc at the centre covering SPOT_AREA_FRACTION of the frame
#: (what the camera looks at), key 0.18. ``eye``: every pixel alike, with the key of a
#: dark-adapted observer, :func:`eye_key`, which falls with the adaptation luminance.
METERINGS = ("average", "center", "spot", "eye")
#: Metering used when none is named.
DEFAULT_METERING = "eye"
#: Shader ids of the weightings (``post/log_luminance.glsl`` METERING): eye weighs as average.
METERING_IDS = {"average": 0, "center": 1, "spot": 2, "eye": 0}
#: Centre-weighted metering: Gaussian weight of standard deviation this fraction of the frame's
#: height about its centre (about 60 % of the weight falls in the central quarter of the frame,
#: the "60/40" of cameras' centre-weighted meters).
CENTER_SIGMA_FRACTION = 0.25
#: Spot metering: a disc at the centre covering this fraction of the frame's area (cameras'
#: spot meters cover 1.5 to 5 % of the frame; 2.5 % is a 9 mm circle on a 36 x 24 mm frame).
SPOT_AREA_FRACTION = 0.025
#: Krawczyk et al. 2005, key-value function: key(L) = KEY_A - KEY_B / (KEY_B + log10(L + 1)).
KEY_A = 1.03
KEY_B = 2.0


def check_metering(metering: str) -> str:
    """The metering mode ``metering`` (one of METERINGS), or a ParameterError naming them."""
    if not isinstance(metering, str) or metering.lower() not in METERINGS:
        raise ParameterError(f"metering {metering!r} must be one of {', '.join(METERINGS)}")
    return metering.lower()


def eye_key(adaptation_cd_m2: float) -> float:
    """Key value (exposed value of the adaptation luminance) of a human observer adapted to
    ``adaptation_cd_m2`` (cd/m^2): Krawczyk, Myszkowski & Seidel 2005, "Perceptual effects
    in real-time tone mapping" (SCCG), sec. 3 (key value), ``key = 1.03 - 2 / (2 + log10(L + 1))``,
    capped at DEFAULT_KEY (0.18).

    The key falls from 0.18 at 1.25 cd/m^2 (where the formula reaches 0.18) to 0.161 at 1 cd/m^2,
    0.05 at 0.1 (a moonlit landscape) and 0.030 at a moonless sky's 2e-4: night images are
    shown dark, as a dark-adapted eye sees them. The cap keeps brighter scenes at middle grey
    (the formula would give 0.66 at a daylight sky's 5000 cd/m^2, +1.9 EV over every daylight
    image so far); it joins the formula without a jump, at 1.25 cd/m^2."""
    lum = check_range("adaptation luminance", adaptation_cd_m2, 0.0, math.inf, "cd/m^2")
    key = KEY_A - KEY_B / (KEY_B + math.log10(lum + 1.0))
    return min(key, DEFAULT_KEY)


def metering_weights(height: int, width: int, metering: str) -> np.ndarray:
    """Weights (H, W) of the pixels of a frame in the metered log-average, row 0 at the top:
    1 everywhere (average, eye), a Gaussian about the centre (center), a central disc (spot).
    Evaluated at pixel centres; the GLSL twin is ``post/log_luminance.glsl`` (METERING)."""
    mode = check_metering(metering)
    y = np.arange(height, dtype=np.float64) + 0.5 - 0.5 * height
    x = np.arange(width, dtype=np.float64) + 0.5 - 0.5 * width
    d2 = y[:, None] ** 2 + x[None, :] ** 2
    if METERING_IDS[mode] == 1:
        sigma = CENTER_SIGMA_FRACTION * height
        return np.exp(-d2 / (2.0 * sigma * sigma))
    if METERING_IDS[mode] == 2:
        return (d2 <= SPOT_AREA_FRACTION * width * height / math.pi).astype(np.float64)
    return np.ones((height, width))


#: A perspective field narrower than this (deg) is a magnified view (a telescope's, a long
#: lens's): the eye meters what it looks at, the frame's centre, not the whole frame.
NARROW_FIELD_DEG = 5.0


def metering_weighting(metering: str, field_deg: float | None) -> str:
    """The weights a metering mode measures a frame with: its own, but ``eye`` in a magnified
    view (a perspective field under NARROW_FIELD_DEG) weights the centre (``center``), as an
    observer at a telescope adapts to what fills it: a Moon close-up is exposed for the Moon.
    ``field_deg``: the camera's horizontal field, None for wide maps."""
    mode = check_metering(metering)
    if mode == "eye" and field_deg is not None and field_deg < NARROW_FIELD_DEG:
        return "center"
    return mode


def metered_luminance(frame: np.ndarray, metering: str, *, delta: float = DEFAULT_DELTA) -> float:
    """Weighted log-average luminance (cd/m^2) of a frame under a metering mode: Reinhard et
    al. 2002 eq. 1 with the weights of :func:`metering_weights` (unlit pixels ignored, delta
    subtracted again, as :func:`log_average_luminance`). ``average`` and ``eye`` give exactly
    :func:`log_average_luminance` (no clipping); delta when no weighted pixel is lit."""
    mode = check_metering(metering)
    lum = _photopic_luminance(frame)
    if METERING_IDS[mode] == 0:
        return log_average_luminance(lum, delta=delta)
    weights = metering_weights(*lum.shape, mode)
    keep = np.isfinite(lum) & (lum > 0.0) & (weights > 0.0)
    if not keep.any():
        return delta
    w = weights[keep]
    avg = math.exp(float(np.sum(w * np.log(delta + lum[keep])) / np.sum(w))) - delta
    return max(avg, delta)


def metered_exposure(
    frame: np.ndarray, metering: str = DEFAULT_METERING, *, compensation_ev: float = 0.0
) -> float:
    """Exposure scale (m^2/cd) a metering mode chooses for a frame: ``2^compensation * key /
    L``, L its :func:`metered_luminance`, the key 0.18 or, metering ``eye``, :func:`eye_key`
    of L. (The frame graph's ``eye`` also shows the mesopic colours below 5 cd/m^2 and
    divides by the mesopic luminance; this is the photopic part.)"""
    mode = check_metering(metering)
    comp = check_range("exposure compensation", compensation_ev, *COMPENSATION_RANGE, "EV")
    lum = metered_luminance(frame, mode)
    key = eye_key(lum) if mode == "eye" else DEFAULT_KEY
    return 2.0**comp * key / lum
