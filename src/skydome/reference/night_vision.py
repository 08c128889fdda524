"""Float64 NumPy twin of the night-vision display pass (skydome.display.night_vision).

Step by step what the passes under ``shaders/post/`` (``night_log_luminance.glsl``,
``night_vision.glsl``, ``acuity_blur.glsl``, ``night_scotopic_blur.glsl``,
``night_downsample.glsl``, ``night_noise.glsl``) compute, in float64, on a NumPy frame
(H, W, 4), row 0 at the top (as ``Frame.data``): the S/P ratio of the frame on the exposure
grid, the CIE 191:2010 coefficient m, the mesopic blend, the separable Gaussian blur (same
taps, same truncation, clamped edges; on the same level of the same pyramid for a wide blur,
:func:`skydome.display.night_vision.blur_plan`) and the hashed noise (the same PCG hash on
uint32, so the noise pattern is the shader's). :func:`gaussian_blur` is the exact blur the
pyramid stands for. For tests only.
"""

from __future__ import annotations

import math

import numpy as np

from skydome.display.exposure import DEFAULT_DELTA
from skydome.display.night_vision import (
    BLUE_GREY,
    DOWNSAMPLE_WEIGHTS,
    GRID,
    MIN_SIGMA_PX,
    blur_plan,
    blur_sigma_deg,
    gaussian_weights,
    mesopic_coefficient,
    noise_amplitude,
    photopic_share,
)
from skydome.spectra import SRGB_LUMINANCE


def frame_sp_ratio(frame: np.ndarray, *, delta: float = DEFAULT_DELTA) -> float:
    """S/P ratio of a frame (H, W, 4), row 0 at the top: the ratio of the log-average
    scotopic and photopic luminances (each exp(mean ln(delta + L)) - delta, as
    skydome.display.exposure) over the lit pixels of the 256 x 128 sample grid of
    ``post/night_log_luminance.glsl`` (the sampling of ``post/log_luminance.glsl``)."""
    gl = np.asarray(frame, dtype=np.float64)[::-1]  # GL rows: row 0 at the bottom
    h, w = gl.shape[:2]
    gw, gh = GRID
    cols = np.minimum(((np.arange(gw) + 0.5) * w / gw).astype(int), w - 1)
    rows = np.minimum(((np.arange(gh) + 0.5) * h / gh).astype(int), h - 1)
    s = gl[np.ix_(rows, cols)]
    lp = s[..., :3] @ SRGB_LUMINANCE
    ls = s[..., 3]
    lit = (lp > 0.0) | (ls > 0.0)
    if not lit.any():
        return 1.0
    avg_p = math.exp(float(np.mean(np.log(delta + np.maximum(lp[lit], 0.0))))) - delta
    avg_s = math.exp(float(np.mean(np.log(delta + np.maximum(ls[lit], 0.0))))) - delta
    return max(avg_s, delta) / max(avg_p, delta)


def mesopic_blend(frame: np.ndarray, m: float) -> np.ndarray:
    """Step 1: ``w_p RGB + (1 - w_p) L_s C_b`` per pixel (channel 3 kept); m = 1: the frame."""
    a = np.asarray(frame, dtype=np.float64)
    if m >= 1.0:
        return a.copy()
    wp = photopic_share(m)
    out = a.copy()
    out[..., :3] = wp * a[..., :3] + (1.0 - wp) * a[..., 3:4] * BLUE_GREY
    return out


def gaussian_taps(sigma_px: float) -> np.ndarray:
    """Normalised weights of taps -r..r, r = min(ceil(3 sigma), MAX_BLUR_RADIUS)."""
    half = gaussian_weights(sigma_px)
    return np.concatenate([half[:0:-1], half])


def _blur_axis(a: np.ndarray, w: np.ndarray, axis: int) -> np.ndarray:
    r = (len(w) - 1) // 2
    n = a.shape[axis]
    idx = np.arange(n)
    out = np.zeros_like(a)
    for k, wk in zip(range(-r, r + 1), w, strict=True):
        out += wk * np.take(a, np.clip(idx + k, 0, n - 1), axis=axis)
    return out


def gaussian_blur(frame: np.ndarray, sigma_px: float, radius: int | None = None) -> np.ndarray:
    """The separable Gaussian blur of ``sigma_px`` at full resolution, taps to ``radius``
    (default 3 sigma, uncapped), weights normalised, edges clamped."""
    a = np.asarray(frame, dtype=np.float64)
    r = math.ceil(3.0 * sigma_px) if radius is None else int(radius)
    i = np.arange(-r, r + 1, dtype=np.float64)
    w = np.exp(-0.5 * i * i / (sigma_px * sigma_px))
    w /= w.sum()
    return _blur_axis(_blur_axis(a, w, 1), w, 0)


def downsample(gl: np.ndarray) -> np.ndarray:
    """One halving of ``post/night_downsample.glsl`` on GL rows (row 0 at the bottom): texel j
    from texels 2j - 1 .. 2j + 2 by [1, 3, 3, 1] / 8 per axis, edges clamped."""
    a = np.asarray(gl, dtype=np.float64)
    for axis in (0, 1):
        n = a.shape[axis]
        m = -(-n // 2)
        j = np.arange(m)
        out = 0.0
        for off, wk in zip(range(-1, 3), DOWNSAMPLE_WEIGHTS, strict=True):
            out = out + wk * np.take(a, np.clip(2 * j + off, 0, n - 1), axis=axis)
        a = out
    return a


def upsample(gl: np.ndarray, level: int, shape: tuple[int, int]) -> np.ndarray:
    """The bilinear look-up of ``post/night_vision.glsl`` (source 2) on GL rows: full-frame
    pixel x reads the level at texel coordinate (x + 0.5) / 2^k - 0.5, edges clamped."""
    a = np.asarray(gl, dtype=np.float64)
    f = 2.0**level
    for axis, n in enumerate(shape):
        m = a.shape[axis]
        t = (np.arange(n) + 0.5) / f - 0.5
        j0 = np.floor(t).astype(int)
        fr = t - j0
        lo = np.take(a, np.clip(j0, 0, m - 1), axis=axis)
        hi = np.take(a, np.clip(j0 + 1, 0, m - 1), axis=axis)
        wshape = [1] * a.ndim
        wshape[axis] = n
        fr = fr.reshape(wshape)
        a = (1.0 - fr) * lo + fr * hi
    return a


def acuity_blur(frame: np.ndarray, sigma_px: float) -> np.ndarray:
    """Step 2: the acuity blur as the pass runs it (no blur below MIN_SIGMA_PX): a separable
    Gaussian, edges clamped, at full resolution or on the level of the pyramid that
    :func:`skydome.display.night_vision.blur_plan` chooses (halved, blurred, enlarged)."""
    a = np.asarray(frame, dtype=np.float64)
    if not sigma_px >= MIN_SIGMA_PX:
        return a.copy()
    h, w = a.shape[:2]
    level, s = blur_plan(sigma_px, (w, h))
    taps = gaussian_taps(s)
    if level == 0:
        return _blur_axis(_blur_axis(a, taps, 1), taps, 0)
    gl = a[::-1]
    for _ in range(level):
        gl = downsample(gl)
    gl = _blur_axis(_blur_axis(gl, taps, 1), taps, 0)
    return upsample(gl, level, (h, w))[::-1].copy()


def _pcg(v: np.ndarray) -> np.ndarray:
    """PCG hash (O'Neill 2014, the RXS-M-XS output of a one-step LCG) on uint32, as GLSL."""
    v = np.asarray(v, dtype=np.uint32)
    state = v * np.uint32(747796405) + np.uint32(2891336453)
    shift = (state >> np.uint32(28)) + np.uint32(4)
    word = ((state >> shift) ^ state) * np.uint32(277803737)
    return (word >> np.uint32(22)) ^ word


def noise_field(shape: tuple[int, int], seed: int, time_s: float) -> np.ndarray:
    """The unit-variance noise n (H, W), row 0 at the top, of ``post/night_noise.glsl``."""
    h, w = shape
    tbits = np.array([np.float32(time_s)]).view(np.uint32)
    base = _pcg(_pcg(np.array([seed], dtype=np.uint32)) ^ tbits)
    y = np.arange(h, dtype=np.uint32)[:, None]  # GL row index
    x = np.arange(w, dtype=np.uint32)[None, :]
    hrow = _pcg(base + y)
    h1 = _pcg(hrow + x)
    h2 = _pcg(h1 ^ np.uint32(0x9E3779B9))
    k = (h1 >> np.uint32(8)).astype(np.int64) + (h2 >> np.uint32(8)).astype(np.int64) - (1 << 24)
    n = k.astype(np.float64) * (math.sqrt(6.0) / 16777216.0)
    return n[::-1]  # back to row 0 at the top


def add_noise(frame: np.ndarray, m: float, seed: int, time_s: float) -> np.ndarray:
    """Step 3: ``RGB (1 + a n)``, a = noise_amplitude(L_s, m); m = 1: the frame."""
    a = np.asarray(frame, dtype=np.float64)
    if m >= 1.0:
        return a.copy()
    amp = noise_amplitude(a[..., 3], m)
    n = noise_field(a.shape[:2], seed, time_s)
    out = a.copy()
    out[..., :3] *= (1.0 + amp * n)[..., None]
    return out


def night_vision_reference(
    frame: np.ndarray,
    *,
    pixel_angle_rad: float,
    adaptation: float,
    seed: int = 0,
    time_s: float = 0.0,
    noise: bool = True,
    acuity: bool = True,
) -> tuple[np.ndarray, dict[str, float]]:
    """The whole pass in float64 on a frame (H, W, 4), row 0 at the top.

    Args:
        adaptation: the photopic adaptation luminance, cd/m^2 (for a GpuExposure, pass the
            log-average luminance it measured).

    Returns:
        (out, state): the displayed frame, and the adaptation state: L_p, S/P, L_s, m,
        L_mes, the blur width (px).
    """
    a = np.asarray(frame, dtype=np.float64)
    sp = frame_sp_ratio(a)
    lp = float(adaptation)
    ls = lp * sp
    m, lmes = mesopic_coefficient(lp, ls)
    sigma = 0.0 if m >= 1.0 else blur_sigma_deg(lp) / math.degrees(pixel_angle_rad)
    out = mesopic_blend(a, m)
    if acuity:
        out = acuity_blur(out, sigma)
    if noise:
        out = add_noise(out, m, seed, time_s)
    state = {"lp": lp, "sp": sp, "ls": ls, "m": m, "lmes": lmes, "sigma_px": sigma}
    return out, state
