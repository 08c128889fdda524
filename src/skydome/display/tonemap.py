"""Tone mapping: exposed linear sRGB -> display-linear sRGB in [0, 1] -> sRGB-encoded uint8.

Operators take **exposed** linear RGB (``exposure_scale * frame[..., :3]``, see
``skydome.display.exposure``; 1.0 = sensor saturation, 0.18 = middle grey under automatic
exposure) and return display-linear RGB in [0, 1] (float64). Negative components (out-of-gamut
spectral colours) are clipped to 0 first; results above 1 are clipped to 1. Then
:func:`~skydome.display.srgb.srgb_encode` and :func:`~skydome.display.srgb.quantize8` give
the 8-bit image.

These NumPy float64 functions are the reference; the production GPU path is
``shaders/post/tonemap.glsl`` (driven by ``skydome.display.gpu_tonemap``), which implements the same
formulas and agrees to within one 8-bit code value.

Operators (``TONEMAPS``):

- ``linear``: clip at 1 (a camera with no tone curve; EV alone decides).
- ``exponential``: 1 - exp(-k c) per channel (seed 000 eq. 4.14).
- ``reinhard``: extended Reinhard on luminance with white point L_white, colours scaled by
  L_d / L (seed 001 eqs. 5.2-5.4; Reinhard et al. 2002 eq. 4).
- ``hvs``: the bi-logarithmic "HVS" curve of seed 003 eq. 7 on luminance.
- ``filmic``: Narkowicz's fit of the ACES RRT+ODT curve on max(R, G, B), hue preserved,
  with highlights desaturated towards white over three stops above saturation.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from skydome.display.srgb import quantize8, srgb_decode, srgb_encode
from skydome.errors import ParameterError, check_range
from skydome.spectra import SRGB_LUMINANCE

_LN10 = math.log(10.0)
#: Valid range of I_max in seed 003 eq. 7 (see :func:`hvs_coefficients`): [2 sqrt(10) - 2, 9].
HVS_I_MAX_RANGE = (2.0 * math.sqrt(10.0) - 2.0, 9.0)


def _rgb(rgb: np.ndarray) -> np.ndarray:
    """Exposed linear RGB as float64 with negative components clipped to 0."""
    a = np.asarray(rgb, dtype=np.float64)
    if a.shape[-1:] != (3,):
        raise ParameterError(f"expected linear RGB of shape (..., 3), got shape {a.shape}")
    return np.maximum(a, 0.0)


def _scale_by_luminance(rgb: np.ndarray, lum: np.ndarray, lum_display: np.ndarray) -> np.ndarray:
    """C_d = (C / L) * L_d (seed 001 eq. 5.4); black where L = 0.

    C / L is bounded (by 1 / min weight, about 14) for non-negative C, so the order of the
    operations cannot overflow.
    """
    positive = lum > 0.0
    chroma = rgb / np.where(positive, lum, 1.0)[..., None]  # C / L, bounded for C >= 0
    return np.clip(chroma * np.where(positive, lum_display, 0.0)[..., None], 0.0, 1.0)


def linear(rgb: np.ndarray) -> np.ndarray:
    """Clip exposed linear RGB to [0, 1]: no tone curve (dimensionless in and out)."""
    return np.clip(_rgb(rgb), 0.0, 1.0)


def exponential(rgb: np.ndarray, k: float = 1.0) -> np.ndarray:
    """Exponential tone curve per channel: ``T(c) = 1 - exp(-k c)`` (seed 000 eq. 4.14).

    The seed uses T_s = 4 on its own (unnormalized) radiometric units; here ``c`` is already
    exposed, so k = 1 maps saturation (c = 1) to 0.63 and middle grey (0.18) to 0.165.
    Per channel, so very bright colours desaturate towards white.

    Args:
        rgb: exposed linear RGB (..., 3), dimensionless.
        k: the scale T_s of eq. 4.14 (> 0).
    Returns: display-linear RGB in [0, 1].
    """
    c = _rgb(rgb)
    return np.clip(-np.expm1(-k * c), 0.0, 1.0)  # 1 - exp(-k c), accurate near 0


def reinhard_luminance(lum: np.ndarray, l_white: float = 4.0) -> np.ndarray:
    """Extended Reinhard curve on luminance (seed 001 eq. 5.2; Reinhard et al. 2002 eq. 4).

    ``L_d = L (1 + L / L_white^2) / (1 + L)``, computed as ``(L + L*L/(L_white*L_white)) /
    (1 + L)`` so that ``L_white`` maps to exactly 1.0. ``l_white = inf`` gives the simple
    curve L / (1 + L) (eq. 5.1). Not clipped (values above L_white exceed 1).
    """
    L = np.maximum(np.asarray(lum, dtype=np.float64), 0.0)
    lw = float(l_white)
    burn = (L * L) / (lw * lw) if math.isfinite(lw) else 0.0
    return (L + burn) / (1.0 + L)


def reinhard(rgb: np.ndarray, l_white: float = 4.0) -> np.ndarray:
    """Extended Reinhard operator on luminance, colours scaled (seed 001 eqs. 5.2-5.4).

    L = 0.2126 R + 0.7152 G + 0.0722 B (eq. 5.3, our ``SRGB_LUMINANCE``), L_d from eq. 5.2
    (:func:`reinhard_luminance`), C_d = C L_d / L (eq. 5.4): chromaticity is preserved until a
    channel clips at 1. Exposed luminances at or above ``l_white`` burn to white.

    Args:
        rgb: exposed linear RGB (..., 3), dimensionless.
        l_white: exposed luminance mapped to display white (> 0; inf for eq. 5.1). The
            default 4 keeps two stops above the EV saturation point before burning.
    Returns: display-linear RGB in [0, 1].
    """
    c = _rgb(rgb)
    lum = c @ SRGB_LUMINANCE
    return _scale_by_luminance(c, lum, reinhard_luminance(lum, l_white))


def hvs_coefficients(i_max: float) -> tuple[float, float]:
    """Parameters (a, b) of seed 003 eq. 7 for a maximum intensity I_max.

    The constraints ``10^b = a + 2`` and ``10^(1-b) = I_max - a`` give, with t = 10^b,
    ``t + 10 / t = I_max + 2``, i.e. ``t^2 - (I_max + 2) t + 10 = 0``. Real roots need
    I_max >= 2 sqrt(10) - 2 (about 4.325); the curve maps [0, I_max] onto [0, 1] with its
    junction (inflection) x = a + 1 inside [0, I_max] only while I_max <= 9. The two roots
    give point-mirrored curves; we take the smaller, ``t = ((I_max+2) - sqrt((I_max+2)^2 -
    40)) / 2``, whose junction lies in the lower part of the range so that highlights are
    compressed (at I_max = 9 it is a = -1, b = 0: f(x) = log10(1 + x)).

    Raises ParameterError for I_max outside [2 sqrt(10) - 2, 9].
    """
    i = check_range("hvs i_max", i_max, *HVS_I_MAX_RANGE)
    s = i + 2.0
    t = 0.5 * (s - math.sqrt(max(s * s - 40.0, 0.0)))
    return t - 2.0, math.log10(t)


def hvs_curve(x: np.ndarray, i_max: float = 9.0) -> np.ndarray:
    """Seed 003 eq. 7 divided by 255: intensity x in [0, I_max] -> display value in [0, 1].

    ``f(x) = log10(x - a) + b`` for x >= a + 1 and ``-log10(a + 2 - x) + b`` for x < a + 1,
    with (a, b) from :func:`hvs_coefficients`. f(0) = 0, f(I_max) = 1, and f is C1 with its
    inflection at x = a + 1. Not clipped (x > I_max gives f > 1; x < 0 is treated as 0).
    """
    a, b = hvs_coefficients(i_max)
    xv = np.maximum(np.asarray(x, dtype=np.float64), 0.0)
    upper = xv >= a + 1.0
    arg = np.where(upper, xv - a, a + 2.0 - xv)  # >= 1 on both branches
    return np.where(upper, np.log10(arg) + b, -np.log10(arg) + b)


def hvs(rgb: np.ndarray, i_max: float = 9.0, white: float = 1.0) -> np.ndarray:
    """The bi-logarithmic HVS transform of seed 003 eq. 7, on luminance.

    Eq. 7 maps an intensity x in [0, I_max] to an 8-bit display value 255 f(x); it is only a
    tone curve (f(0) = 0, f(I_max) = 1) once intensities are normalised to [0, I_max], so the
    adaptation level enters through the exposure: the exposed luminance ``white`` (default
    1.0, i.e. the saturation luminance 1.2 * 2^EV100 cd/m^2 of the EV convention, or with
    automatic exposure ``white / key`` times the log-average luminance) maps to I_max:

        x = I_max * L / white,    L = exposed luminance (eq. 5.3 weights).

    The paper's output is a display code value, so f(x) is taken as the sRGB-encoded
    display luminance: L_d = srgb_decode(f(x)), and colours are scaled by L_d / L as in
    seed 001 eq. 5.4. A grey pixel therefore gets exactly the code value 255 f(x) of eq. 7.
    With the default I_max = 9, f(x) = log10(1 + x), which keeps middle grey near middle
    grey (0.18 -> code 107) and compresses highlights; exposed luminances above ``white``
    clip.

    Args:
        rgb: exposed linear RGB (..., 3), dimensionless.
        i_max: I_max of eq. 7, in [2 sqrt(10) - 2, 9] (see :func:`hvs_coefficients`).
        white: exposed luminance mapped to I_max (> 0).
    Returns: display-linear RGB in [0, 1].
    """
    c = _rgb(rgb)
    lum = c @ SRGB_LUMINANCE
    x = (float(i_max) / float(white)) * lum
    lum_display = srgb_decode(np.clip(hvs_curve(x, i_max), 0.0, 1.0))
    return _scale_by_luminance(c, lum, lum_display)


#: Narkowicz's fit reaches display 1 at x = (0.56 + sqrt(0.3584)) / 0.16 = 7.24; inputs are
#: capped here before the fit (no change after clipping, and no float32 overflow of x^2).
FILMIC_INPUT_CAP = 64.0
#: Highlight desaturation runs over this many stops above x = 1 (the EV saturation point).
FILMIC_DESATURATION_STOPS = 3.0


def aces_narkowicz(x: np.ndarray) -> np.ndarray:
    """Narkowicz's ACES fit ``f(x) = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)``.

    K. Narkowicz, "ACES Filmic Tone Mapping Curve", blog post, 2016-01-06: a fit of the ACES
    RRT + sRGB ODT with the display gamma removed, pre-exposed so that 1 maps to about 0.80.
    Monotonic for x >= 0 (the numerator of f' has only positive coefficients); f(0) = 0,
    f(7.24) = 1, f -> 2.51 / 2.43 as x -> inf. Not clipped. Dimensionless in and out.

    GLSL twin: ``aces_narkowicz``.
    """
    x = np.asarray(x, dtype=np.float64)
    return (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)


def filmic(rgb: np.ndarray, pre_scale: float = 1.0) -> np.ndarray:
    """Narkowicz's ACES filmic curve on the max channel, hue preserved, highlights to white.

    Applying the curve to each channel separately (as Narkowicz's snippet does) compresses
    the bright channels more than the dim ones, so hue shifts, and a channel that is 0
    stays 0: a very bright orange, out of gamut with blue <= 0, ends at pure yellow
    (1, 1, 0). Instead, with x = pre_scale * c (negative components clipped to 0):

    1. Tone curve on a norm, hue preserved. n = max(x_R, x_G, x_B) goes through the curve
       (:func:`aces_narkowicz`, capped at 1) and the colour is scaled by f(n) / n: channel
       ratios are kept exactly, so are hue and saturation, and grey gets f exactly as
       before (0.18 -> 0.267, 1 -> 0.804). The max-RGB norm never lets a channel exceed
       the curve (a luminance norm would push saturated blues far above 1). This is the
       max-RGB norm of darktable's filmic rgb module ("preserve chrominance: max RGB") and
       of T. Lottes, "Advanced Techniques and Optimization of HDR Color Pipelines", GDC
       2016, which tone-maps max(R, G, B), scales the colour, then desaturates it
       ("crosstalk") towards white in the highlights, as step 2 does.
    2. Path to white. Above the EV saturation point (n > 1) the colour is blended with the
       grey of the same display value f(n): channel i becomes
       f(n) (r_i + t (1 - r_i)), r_i = x_i / n, with t = smoothstep(log2(n) / 3) rising
       from 0 at n = 1 to 1 at n = 8 (three stops, over which f goes from 0.80 to 1), as
       on film. The mix with white (in linear RGB) keeps the
       dominant wavelength, so a bright orange goes orange -> pale orange -> white, never
       to yellow; every channel is non-decreasing in exposure because f(n) and t are.

    Args:
        rgb: exposed linear RGB (..., 3), dimensionless.
        pre_scale: multiplies the input before the curve (> 0); 0.6 matches the original
            (not pre-exposed) ACES curve.
    Returns: display-linear RGB in [0, 1].
    """
    x = _rgb(rgb) * float(pre_scale)
    n = np.maximum(np.maximum(x[..., 0], x[..., 1]), x[..., 2])[..., None]
    n_display = np.clip(aces_narkowicz(np.minimum(n, FILMIC_INPUT_CAP)), 0.0, 1.0)
    u = np.clip(np.log2(np.maximum(n, 1.0)) / FILMIC_DESATURATION_STOPS, 0.0, 1.0)
    t = u * u * (3.0 - 2.0 * u)  # smoothstep: C1 at both ends
    # f(n) (r + t (1 - r)) = x (1 - t) f(n) / n + t f(n): two full-size operations.
    white = t * n_display
    gain = (n_display - white) / np.where(n > 0.0, n, 1.0)  # 0 for black (f(0) = 0)
    out = x * gain
    out += white
    return np.clip(out, 0.0, 1.0, out=out)


@dataclass(frozen=True)
class ToneMapOperator:
    """A tone-mapping operator: its NumPy reference, its id in ``post/tonemap.glsl``, and its
    parameters with defaults and valid ranges."""

    name: str
    function: Callable[..., np.ndarray]
    gl_id: int
    defaults: Mapping[str, float] = field(default_factory=dict)
    ranges: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    summary: str = ""

    def check_params(self, params: Mapping[str, object]) -> dict[str, float]:
        """Defaults completed with ``params``; unknown names or bad values -> ParameterError."""
        unknown = sorted(set(params) - set(self.defaults))
        if unknown:
            valid = ", ".join(sorted(self.defaults)) or "none"
            raise ParameterError(
                f"tone map {self.name!r} has no parameter {unknown[0]!r} (valid: {valid})"
            )
        out = dict(self.defaults)
        for key, value in params.items():
            out[key] = check_range(f"{self.name} {key}", value, *self.ranges[key])
        return out

    def gl_uniforms(self, params: Mapping[str, float]) -> dict[str, float]:
        """Uniforms of ``post/tonemap.glsl`` for checked parameters (see :meth:`check_params`)."""
        u: dict[str, float] = {}
        if self.name == "exponential":
            u["u_exp_k"] = params["k"]
        elif self.name == "reinhard":
            lw = params["l_white"]
            u["u_inv_white_sq"] = 1.0 / (lw * lw) if math.isfinite(lw) else 0.0
        elif self.name == "hvs":
            a, b = hvs_coefficients(params["i_max"])
            u.update(u_hvs_a=a, u_hvs_b=b, u_hvs_x_scale=params["i_max"] / params["white"])
        elif self.name == "filmic":
            u["u_filmic_pre_scale"] = params["pre_scale"]
        return u


_POSITIVE = (1e-9, 1e9)

#: Registry of tone-mapping operators by name; ``gl_id`` selects the branch in post/tonemap.glsl.
TONEMAPS: dict[str, ToneMapOperator] = {
    op.name: op
    for op in (
        ToneMapOperator(name="linear", function=linear, gl_id=0, summary="clip at 1, no curve"),
        ToneMapOperator(
            name="exponential",
            function=exponential,
            gl_id=1,
            defaults={"k": 1.0},
            ranges={"k": _POSITIVE},
            summary="1 - exp(-k c) per channel (seed 000 eq. 4.14)",
        ),
        ToneMapOperator(
            name="reinhard",
            function=reinhard,
            gl_id=2,
            defaults={"l_white": 4.0},
            ranges={"l_white": (1e-9, math.inf)},
            summary="extended Reinhard on luminance (seed 001 eqs. 5.2-5.4)",
        ),
        ToneMapOperator(
            name="hvs",
            function=hvs,
            gl_id=3,
            defaults={"i_max": 9.0, "white": 1.0},
            ranges={"i_max": HVS_I_MAX_RANGE, "white": _POSITIVE},
            summary="bi-logarithmic HVS curve on luminance (seed 003 eq. 7)",
        ),
        ToneMapOperator(
            name="filmic",
            function=filmic,
            gl_id=4,
            defaults={"pre_scale": 1.0},
            ranges={"pre_scale": _POSITIVE},
            summary="ACES filmic fit (Narkowicz 2016) on max RGB, hue-preserving, path to white",
        ),
    )
}
#: Operator used when none is named.
DEFAULT_TONEMAP = "filmic"


def get_operator(name: str) -> ToneMapOperator:
    """The operator called ``name``; ParameterError listing the valid names otherwise."""
    op = TONEMAPS.get(str(name).lower()) if isinstance(name, str) else None
    if op is None:
        raise ParameterError(f"unknown tone map {name!r} (valid: {', '.join(sorted(TONEMAPS))})")
    return op


def as_array(frame) -> np.ndarray:
    """The pixel array of a frame: an array as is, or the ``.data`` of a Frame object."""
    if not isinstance(frame, np.ndarray) and isinstance(getattr(frame, "data", None), np.ndarray):
        return frame.data
    return np.asarray(frame)


def check_frame(frame: np.ndarray) -> np.ndarray:
    """Validate a frame (H, W, 4) or (H, W, 3): numeric and finite (DESIGN rule 8).

    Returns it as an array; raises ParameterError naming the first non-finite pixel.
    """
    a = as_array(frame)
    if a.ndim != 3 or a.shape[-1] not in (3, 4) or 0 in a.shape or a.dtype.kind not in "fiu":
        raise ParameterError(
            f"frame must be a non-empty numeric (H, W, 4) or (H, W, 3) array, got "
            f"shape {a.shape} dtype {a.dtype}"
        )
    if a.dtype.kind == "f":
        bad = ~np.isfinite(a[..., :3])
        if bad.any():
            r, c, ch = (int(i) for i in np.argwhere(bad)[0])
            raise ParameterError(
                f"frame has {int(bad.sum())} non-finite values (first at row {r}, column {c}, "
                f"channel {ch}: {a[r, c, ch]}); frames must be finite"
            )
    return a


def check_exposure_scale(exposure_scale: float) -> float:
    """Validate an exposure scale (m^2/cd): finite and positive."""
    try:
        s = float(exposure_scale)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(f"exposure scale must be a number, got {exposure_scale!r}") from None
    if not (math.isfinite(s) and s > 0.0):
        raise ParameterError(f"exposure scale = {exposure_scale!r} must be finite and > 0")
    return s


def tonemap_linear(
    frame: np.ndarray, name: str, exposure_scale: float, **params: float
) -> np.ndarray:
    """Display-linear RGB (H, W, 3) float64 in [0, 1]: exposure then operator ``name``.
    GLSL twin: ``tonemap_display_linear``."""
    op = get_operator(name)
    checked = op.check_params(params)
    a = check_frame(frame)
    s = check_exposure_scale(exposure_scale)
    return op.function(a[..., :3].astype(np.float64) * s, **checked)


def tonemap(frame: np.ndarray, name: str, exposure_scale: float, **params: float) -> np.ndarray:
    """Tone-map a frame in absolute units to an 8-bit sRGB image.

    Args:
        frame: (H, W, 4) float frame (linear sRGB in cd/m^2, channel 3 scotopic and ignored
            here), row 0 at the top; (H, W, 3) also accepted, and any object with a
            ``.data`` array (``skydome.core.frame.Frame``). Must be finite.
        name: an operator of ``TONEMAPS`` (ParameterError listing them otherwise).
        exposure_scale: m^2/cd, from ``ev100_to_scale`` or ``auto_exposure``.
        **params: operator parameters (see each operator; unknown names -> ParameterError).
    Returns: uint8 (H, W, 3), sRGB-encoded (IEC 61966-2-1), row 0 at the top.
    """
    return quantize8(srgb_encode(tonemap_linear(frame, name, exposure_scale, **params)))
