"""Night vision: what a dark-adapted human eye sees, as a display pass before the tone map.

The pass reads the float frame (linear sRGB in cd/m^2, channel 3 the scotopic luminance) and
writes a frame in the same units, the photopic-equivalent luminance shown to a viewer whose
own eye is light adapted. It changes the displayed image only, never the frame's data, and
does nothing at all (the output equals the input bit for bit) in photopic vision. Off by
default; the frame graph's post stage runs it before the tone map.

1. **Mesopic blend**, CIE 191:2010 (recommended system for mesopic photometry, MES2). The
   adaptation coefficient m follows from the photopic and scotopic adaptation luminances by
   the standard's fixed-point iteration (:func:`mesopic_coefficient`):
   ``L_mes = (m L_p + (1 - m) L_s V'(555)) / (m + (1 - m) V'(555))``, ``V'(555) = 683/1699``,
   ``m = 0.7670 + 0.3334 log10(L_mes)`` clamped to [0, 1] (1 from L_mes = 5 cd/m^2 up, 0 from
   0.005 down), starting from m = 0.5. Each pixel is then shown with the mesopic luminance
   the standard gives it, ``w_p L_p + w_s L_s`` with ``w_p = m / (m + (1 - m) V'(555))``,
   the photopic share in the pixel's colour and the scotopic share in a desaturated blue grey
   (the blue shift of Thompson, Shirley & Ferwerda 2002, "A spatial post-processing algorithm
   for images of night scenes", JGT 7(1); seed 001 eqs. 5.7-5.8 blend the same two images).
2. **Purkinje shift**: falls out of 1, as the scotopic channel weighs blue light more than red.
3. **Loss of acuity**: a separable Gaussian blur whose width follows Ferwerda, Pattanaik,
   Shirley & Greenberg 1996 ("A model of visual adaptation for realistic image synthesis",
   SIGGRAPH 96, eq. 7, their fit of Shaler 1937): the highest resolvable spatial frequency
   ``R(L) = 17.25 atan(1.4 log10 L + 0.35) + 25.72`` cycles/deg (:func:`acuity_cycles_per_deg`).
4. **Temporal noise**, growing as the light falls (Thompson et al. 2002), mean preserving,
   from a hash of the pixel, the seed and the frame time.

The frame's adaptation field: its photopic log-average luminance (a number, or a
:class:`skydome.display.gpu_exposure.GpuExposure` that measured the frame), and its S/P ratio,
the ratio of the log-average scotopic and photopic luminances, measured by the pass on the GPU
from the frame itself (``post/night_log_luminance.glsl``). The two 1 x 1 mip levels are read
back (16 bytes each, once per frame) and m, the blur width and the passes to run are chosen
on the CPU in float64: nothing at m = 1, no blur under 0.5 px, no noise when it is off, the
scotopic channel alone at m = 0, a reduced-resolution copy for a blur of several pixels
(:func:`blur_plan`). The float64 twin of the whole pass is
:func:`skydome.reference.night_vision.night_vision_reference`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from skydome.display.exposure import DEFAULT_DELTA
from skydome.display.glare import GlareHalo
from skydome.display.gpu_exposure import GridMean, LogLuminanceInputs
from skydome.errors import ParameterError, check_range
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.textures import FloatTargets
from skydome.spectra import SRGB_LUMINANCE, XYZ_TO_LINEAR_SRGB

# -- CIE 191:2010, MES2 ---------------------------------------------------------------------
#: m = MES2_A + MES2_B log10(L_mes) (CIE 191:2010, sec. 6; a, b as the standard prints them).
MES2_A = 0.7670
MES2_B = 0.3334
#: V'(lambda_0) at lambda_0 = 555 nm, written 683/1699 in CIE 191:2010 (the ratio of the
#: photopic and scotopic maximum luminous efficacies; the frame's scotopic channel uses
#: 1700 lm/W, 0.06 % apart).
V_PRIME_555 = 683.0 / 1699.0
#: Edges of the mesopic range of CIE 191:2010 (cd/m^2): m = 1 above, 0 below.
PHOTOPIC_LIMIT_CD_M2 = 5.0
SCOTOPIC_LIMIT_CD_M2 = 0.005
#: Fixed-point iterations at most (the map converges in < 30 for S/P < 18: Li et al. 2018).
MES2_ITERATIONS = 64
#: Convergence tolerance on m (CIE 191 asks for iteration "until m converges").
MES2_TOLERANCE = 1e-12
#: At or above this photopic adaptation luminance (cd/m^2) MES2 gives m = 1 whatever the S/P
#: ratio: its first step from m = 0.5 gives L_mes >= L_p / (1 + V'(555)) = 0.713 L_p, at least
#: 5 cd/m^2 (m = 1) from L_p = 7.01 on. The S/P ratio (a grid pass, its mean and a
#: read-back a frame) is then not measured: by day the eye's colours cost nothing.
PHOTOPIC_ANY_SP_CD_M2 = 10.0


def leaves_frame(adaptation_cd_m2: float) -> bool:
    """Whether :meth:`NightVision.apply` at a photopic adaptation of ``adaptation_cd_m2``
    returns its frame as it is (m = 1 whatever the S/P ratio): then no pass reads it."""
    return float(adaptation_cd_m2) >= PHOTOPIC_ANY_SP_CD_M2


# -- Blue shift -----------------------------------------------------------------------------
#: CIE 1931 xy of the blue grey in which scotopic luminance is drawn: a bluish white near a
#: 10 000 K correlated colour temperature, u'v' distance 0.029 from D65. Thompson et al. 2002
#: (sec. 3) and Jensen et al. 2001 ("Night rendering", sec. 5) choose their blue shift by eye;
#: this one is as faint: a slightly blue grey, not a blue.
BLUE_GREY_XY = (0.28, 0.29)


def _xy_to_linear_srgb_unit_luminance(x: float, y: float) -> np.ndarray:
    xyz = np.array([x / y, 1.0, (1.0 - x - y) / y])
    return XYZ_TO_LINEAR_SRGB @ xyz


#: C_b: linear sRGB of BLUE_GREY_XY with luminance Y = 1.
BLUE_GREY = _xy_to_linear_srgb_unit_luminance(*BLUE_GREY_XY)

# -- Acuity ---------------------------------------------------------------------------------
#: sigma of the Gaussian whose modulation transfer exp(-2 pi^2 sigma^2 f^2) is 1/2 at f = R:
#: sigma = sqrt(ln 2 / 2) / (pi R) (R in cycles/deg, sigma in deg).
HALF_TRANSFER_SIGMA_CYCLES = math.sqrt(math.log(2.0) / 2.0) / math.pi
#: Below this blur width (pixels) no blur is run (brief: "~0.5 px").
MIN_SIGMA_PX = 0.5
#: Taps on each side at most, at whichever resolution the blur runs (3 sigma up to
#: sigma = 2.67 px there); the resolution is halved until the blur is that narrow
#: (:func:`blur_plan`), so only a blur wider than the frame's smallest level is truncated.
MAX_BLUR_RADIUS = 8
#: A blur runs on the level 2^-k of a pyramid when its width there stays at least this (level
#: pixels): narrower, the sampled Gaussian is too coarse to stand for the blur.
PYRAMID_MIN_SIGMA = 1.0
#: Pyramid weights of one halving (per axis): the linear B-spline sampled at half-texel
#: offsets, [1, 3, 3, 1] / 8. It keeps the centroid of a point exactly, whatever its phase in
#: the 2 x 2 block, and adds a variance of 0.75 px^2 of the finer level (so a star is never
#: moved by the reduction, only widened, by an amount the Gaussian then leaves out).
DOWNSAMPLE_WEIGHTS = (0.125, 0.375, 0.375, 0.125)

# -- Noise ----------------------------------------------------------------------------------
#: Photon-count law of the noise: relative standard deviation 1 / sqrt(N), N = NOISE_QUANTA *
#: L_s (L_s in scotopic cd/m^2): the de Vries-Rose square-root law of quantum fluctuations
#: (Rose 1948; Kellnhofer et al. 2015, "Modeling luminance perception at absolute threshold",
#: EGSR, sec. 3). The constant is chosen for display: 10 % at 2e-4 cd/m^2 (a moonless sky),
#: 3 % at 2e-3, 0.4 % at a full-Moon sky's 0.1 cd/m^2 (and times 1 - m).
NOISE_QUANTA = 5.0e5
#: Largest relative amplitude: 1 / sqrt(6) keeps 1 + a n >= 0 for the triangular n on
#: [-sqrt 6, sqrt 6], so nothing is clipped and the mean is preserved.
NOISE_CAP = 1.0 / math.sqrt(6.0)

#: Grid of the S/P measurement (that of skydome.display.gpu_exposure).
GRID = (256, 128)


def _check_luminance(name: str, value: float) -> float:
    v = check_range(name, value, 0.0, 1e12, "cd/m^2")
    return v


def mesopic_coefficient(photopic_cd_m2: float, scotopic_cd_m2: float) -> tuple[float, float]:
    """CIE 191:2010 MES2: the adaptation coefficient m and the mesopic luminance L_mes.

    Fixed-point iteration from m0 = 0.5 as the standard prescribes:
    ``L_mes,n = (m_(n-1) L_p + (1 - m_(n-1)) L_s V'(555)) / (m_(n-1) + (1 - m_(n-1)) V'(555))``,
    ``m_n = 0.7670 + 0.3334 log10(L_mes,n)``, clamped to [0, 1].

    Args:
        photopic_cd_m2: photopic adaptation luminance L_p, cd/m^2 (>= 0).
        scotopic_cd_m2: scotopic adaptation luminance L_s, scotopic cd/m^2 (>= 0).

    Returns:
        (m, L_mes): m in [0, 1] (1 = photopic), L_mes in cd/m^2.
    """
    lp = _check_luminance("photopic luminance", photopic_cd_m2)
    ls = _check_luminance("scotopic luminance", scotopic_cd_m2)
    m = 0.5
    lmes = 0.0
    for _ in range(MES2_ITERATIONS):
        lmes = (m * lp + (1.0 - m) * ls * V_PRIME_555) / (m + (1.0 - m) * V_PRIME_555)
        nxt = MES2_A + MES2_B * math.log10(lmes) if lmes > 0.0 else 0.0
        nxt = min(max(nxt, 0.0), 1.0)
        done = abs(nxt - m) < MES2_TOLERANCE
        m = nxt
        if done:
            break
    lmes = (m * lp + (1.0 - m) * ls * V_PRIME_555) / (m + (1.0 - m) * V_PRIME_555)
    return m, lmes


def mesopic_weight(adaptation_cd_m2: float, sp_ratio: float = 1.0) -> float:
    """The CIE 191:2010 adaptation coefficient m for a photopic adaptation luminance.

    Args:
        adaptation_cd_m2: photopic adaptation luminance L_p, cd/m^2 (>= 0).
        sp_ratio: S/P ratio of the adaptation field (L_s / L_p, > 0); 1 by default, where
            L_mes = L_p and m = 0.767 + 0.3334 log10(L_p).

    Returns:
        m in [0, 1]: 1 at L_mes >= 5 cd/m^2 (photopic), 0 at L_mes <= 0.005 (scotopic).
    """
    lp = _check_luminance("adaptation luminance", adaptation_cd_m2)
    sp = check_range("S/P ratio", sp_ratio, 1e-6, 1e6)
    return mesopic_coefficient(lp, lp * sp)[0]


def photopic_share(m: float) -> float:
    """w_p = m / (m + (1 - m) V'(555)): the photopic channel's share of a pixel's mesopic
    luminance at adaptation coefficient m (the scotopic share is 1 - w_p)."""
    mm = check_range("m", m, 0.0, 1.0)
    return mm / (mm + (1.0 - mm) * V_PRIME_555)


def acuity_cycles_per_deg(luminance_cd_m2):
    """Highest resolvable spatial frequency (cycles/deg) at an adaptation luminance (cd/m^2):
    Ferwerda et al. 1996 eq. 7, their fit of Shaler's 1937 acuity data. Array-friendly."""
    lum = np.maximum(np.asarray(luminance_cd_m2, dtype=np.float64), 1e-30)
    r = 17.25 * np.arctan(1.4 * np.log10(lum) + 0.35) + 25.72
    return float(r) if np.ndim(r) == 0 else r


def blur_sigma_deg(luminance_cd_m2: float) -> float:
    """Standard deviation (deg of visual angle) of the Gaussian blur added at an adaptation
    luminance: ``sqrt(sigma(L)^2 - sigma(5 cd/m^2)^2)``, ``sigma(L) = sqrt(ln 2 / 2) / (pi R(L))``
    (the Gaussian whose transfer function is 1/2 at the acuity limit R of
    :func:`acuity_cycles_per_deg`); 0 from 5 cd/m^2 up, where vision is photopic and the
    viewer's own eye resolves what the scene's observer would."""
    lum = _check_luminance("adaptation luminance", luminance_cd_m2)
    s = HALF_TRANSFER_SIGMA_CYCLES / max(acuity_cycles_per_deg(lum), 1e-3)
    s_ref = HALF_TRANSFER_SIGMA_CYCLES / acuity_cycles_per_deg(PHOTOPIC_LIMIT_CD_M2)
    return math.sqrt(max(s * s - s_ref * s_ref, 0.0))


def blur_sigma_px(luminance_cd_m2: float, pixel_angle_rad: float) -> float:
    """:func:`blur_sigma_deg` in pixels of angular size ``pixel_angle_rad``."""
    px = check_range("pixel_angle_rad", pixel_angle_rad, 1e-9, math.pi, "rad")
    return blur_sigma_deg(luminance_cd_m2) / math.degrees(px)


def gaussian_weights(sigma_px: float) -> np.ndarray:
    """Normalised weights of the taps 0..r of a symmetric Gaussian of ``sigma_px`` (px, > 0),
    r = min(ceil(3 sigma), MAX_BLUR_RADIUS): w_0 + 2 (w_1 + ... + w_r) = 1."""
    s = check_range("sigma_px", sigma_px, 1e-6, 1e6, "px")
    r = min(math.ceil(3.0 * s), MAX_BLUR_RADIUS)
    i = np.arange(0, r + 1, dtype=np.float64)
    w = np.exp(-0.5 * i * i / (s * s))
    return w / (w[0] + 2.0 * w[1:].sum())


def pyramid_variance_px2(level: int) -> float:
    """Variance (px^2 of the full frame, per axis) that reducing ``level`` times by
    DOWNSAMPLE_WEIGHTS and enlarging back by one bilinear look-up adds to a blur.

    Each halving at level l adds 0.75 px^2 of that level, 0.75 4^l of the frame; the bilinear
    enlargement by f = 2^level is a tent of half-width f sampled at half-pixel offsets, of
    variance (f^2 + 1/2) / 6 (0.75 for f = 2). Exact for any phase of a point in the blocks,
    away from the frame's edges (checked against the float64 twin in the tests)."""
    if level <= 0:
        return 0.0
    f2 = 4.0**level
    return 0.25 * (f2 - 1.0) + (f2 + 0.5) / 6.0


def blur_plan(sigma_px: float, size: tuple[int, int]) -> tuple[int, float]:
    """Where the acuity blur of ``sigma_px`` (px of the full frame) runs: (k, s), a Gaussian of
    s px on the level 2^-k of the pyramid, s^2 4^k + pyramid_variance_px2(k) = sigma^2 (the
    total variance is the one asked for). k is the coarsest level on which s stays at least
    PYRAMID_MIN_SIGMA and whose smaller side keeps at least 2 px; (0, 0) below MIN_SIGMA_PX
    (no blur)."""
    if not sigma_px >= MIN_SIGMA_PX:
        return 0, 0.0
    level, s = 0, float(sigma_px)
    smallest = min(int(v) for v in size)
    while True:
        k = level + 1
        if -(-smallest // 2**k) < 2:
            break
        var = sigma_px * sigma_px - pyramid_variance_px2(k)
        if var <= 0.0 or var / 4.0**k < PYRAMID_MIN_SIGMA**2:
            break
        level, s = k, math.sqrt(var / 4.0**k)
    return level, s


def noise_amplitude(scotopic_cd_m2, m: float):
    """Relative standard deviation of the temporal noise of a pixel of scotopic luminance
    ``scotopic_cd_m2`` at adaptation coefficient m: ``(1 - m) min(cap, 1 / sqrt(Q L_s))``
    (photon-count law; see NOISE_QUANTA). Array-friendly."""
    ls = np.maximum(np.asarray(scotopic_cd_m2, dtype=np.float64), 0.0)
    with np.errstate(divide="ignore"):
        rel = np.where(ls > 0.0, 1.0 / np.sqrt(NOISE_QUANTA * ls), np.inf)
    a = (1.0 - m) * np.minimum(NOISE_CAP, rel)
    return float(a) if np.ndim(a) == 0 else a


def _pcg_hash(v: int) -> int:
    """PCG hash (O'Neill 2014, the RXS-M-XS output of a one-step LCG) of a uint32, as in
    ``post/night_noise.glsl``."""
    state = (v * 747796405 + 2891336453) & 0xFFFFFFFF
    word = (((state >> ((state >> 28) + 4)) ^ state) * 277803737) & 0xFFFFFFFF
    return (word >> 22) ^ word


def noise_base(seed: int, time_s: float) -> int:
    """The per-frame part of the noise hash: pcg(pcg(seed) ^ bits of float32(time_s))."""
    bits = int(np.array([time_s], dtype=np.float32).view(np.uint32)[0])
    return _pcg_hash(_pcg_hash(int(seed) & 0xFFFFFFFF) ^ bits)


def shader_defines() -> dict[str, object]:
    """The NV_* constants of the passes under ``shaders/post/`` (noise law)."""
    return {
        "NV_NOISE_QUANTA": float(NOISE_QUANTA),
        "NV_NOISE_CAP": float(NOISE_CAP),
    }


def _is_number(value) -> bool:
    return isinstance(value, (int, float, np.floating, np.integer)) and not isinstance(value, bool)


@dataclass(frozen=True)
class NightVisionInputs(ShaderInputs):
    """The night-vision passes (``post/night_*.glsl``, ``post/acuity_blur.glsl``): the
    source texture, and as each pass needs them the photopic share of the mesopic
    luminance, the noise's scale and seed, the colour of scotopic vision, the blur's
    weights, the enlargement's texture scale."""

    u_src: object
    u_wp: float | None = None
    u_noise_scale: float | None = None
    u_blue_grey: tuple[float, float, float] | None = None
    u_noise_base: int | None = None
    u_weights: tuple[float, ...] | None = None
    u_uv_scale: tuple[float, float] | None = None


@dataclass(frozen=True)
class MesopicBlend(ShaderInputs):
    """The eye's colours as a pass that reads the frame applies them
    (``post/tonemap.glsl`` with MESOPIC_BLEND): ``u_wp`` RGB + (1 - ``u_wp``) scotopic
    ``u_blue_grey``, what ``post/night_vision.glsl`` writes without blur and noise
    (:meth:`NightVision.colours`)."""

    u_wp: float
    u_blue_grey: tuple[float, float, float]


class NightVision:
    """The night-vision display pass for one context (GPU; GLSL under ``shaders/post/``).

    Args:
        ctx: a moderngl context.
        seed: seed of the temporal noise (non-negative integer < 2^32).
        noise: add the temporal noise of scotopic vision.
        acuity: blur for the loss of acuity.

    :meth:`apply` returns an RGBA32F texture owned by the pass (one set per frame size,
    reused): valid until the next :meth:`apply` of the same size or :meth:`release`; in
    photopic vision (m = 1), where the pass changes nothing, it returns the input texture.

    The adaptation state (two numbers: the photopic log-average and the S/P ratio, each the
    mean of a sample grid) is read back once per frame, and the passes are chosen on
    the CPU from it: none at m = 1; one pass (blend and noise) without blur; for a blur at
    m = 0 (scotopic: only the scotopic channel is seen) the scotopic channel alone, four
    pixels to a texel; for a wide blur a reduced-resolution copy (:func:`blur_plan`). At an
    adaptation of PHOTOPIC_ANY_SP_CD_M2 or more the S/P ratio is not measured (m = 1 whatever
    it is). :attr:`last_state` holds what the last :meth:`apply` used (``sp`` and ``ls``
    None when not measured).

    Below 5 cd/m^2 the output's luminance is each pixel's mesopic luminance, not its photopic
    one: a moonlit sky (S/P about 2.5) comes out about twice as luminous. An exposure taken
    from the input frame therefore shows the night brighter than one taken from the output.
    """

    def __init__(self, ctx, *, seed: int = 0, noise: bool = True, acuity: bool = True):
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
            raise ParameterError(f"seed = {seed!r} must be an integer in [0, 2^32 - 1]")
        if not 0 <= int(seed) < 2**32:
            raise ParameterError(f"seed = {seed} is outside the valid range [0, 4294967295]")
        self.ctx = ctx
        self.seed = int(seed)
        self.noise = bool(noise)
        self.acuity = bool(acuity)
        self.last_state: dict[str, float] = {}
        self._programs: dict[tuple, FullscreenPass] = {}
        self._targets = FloatTargets(ctx)
        w, h = GRID
        self._measure = FullscreenPass(
            ctx, "post/night_log_luminance.glsl", {"GRID_W": w, "GRID_H": h},
            inputs=(LogLuminanceInputs,),
        )  # fmt: skip
        self._measure_glared = FullscreenPass(
            ctx, "post/night_log_luminance.glsl", {"GRID_W": w, "GRID_H": h, "GLARE_HALO": 1},
            inputs=(LogLuminanceInputs, GlareHalo),
        )  # fmt: skip
        self._grid = ctx.texture(GRID, 4, dtype="f4")
        self._grid.filter = (ctx.NEAREST, ctx.NEAREST)
        self._grid_fbo = ctx.framebuffer(color_attachments=[self._grid])
        self._grid_mean = GridMean(ctx, GRID)

    def _program(self, name: str, **defines) -> FullscreenPass:
        key = (name, tuple(sorted(defines.items())))
        if key not in self._programs:
            self._programs[key] = FullscreenPass(
                self.ctx, name, {**shader_defines(), **defines}, inputs=(NightVisionInputs,)
            )
        return self._programs[key]

    def measure_sp_ratio(self, hdr_texture, glare_halo: GlareHalo | None = None) -> float:
        """The frame's S/P ratio: log-average scotopic over log-average photopic luminance on
        the 256 x 128 grid of ``post/night_log_luminance.glsl`` (averaged on the GPU by
        GridMean, one texel read back): as :func:`skydome.reference.night_vision.frame_sp_ratio`.
        With ``glare_halo``, of the frame with that glare added."""
        self._grid_fbo.viewport = (0, 0, *GRID)
        weights = tuple(float(x) for x in SRGB_LUMINANCE)
        inputs = LogLuminanceInputs(hdr_texture, weights, DEFAULT_DELTA)
        if glare_halo is None:
            self._measure.draw(self._grid_fbo, inputs)
        else:
            self._measure_glared.draw(self._grid_fbo, inputs, glare_halo)
        self._grid_mean.average(self._grid)
        top = self._grid_mean.read()
        log_p, log_s, weight = (float(v) for v in top[:3])
        if not weight > 0.0:
            return 1.0
        lp = max(math.exp(log_p / weight) - DEFAULT_DELTA, DEFAULT_DELTA)
        ls = max(math.exp(log_s / weight) - DEFAULT_DELTA, DEFAULT_DELTA)
        return ls / lp

    def _mesopic(self, hdr_texture, lp: float, glare_halo: GlareHalo | None = None):
        """(S/P ratio or None, m, L_mes) at the photopic adaptation ``lp`` (cd/m^2): the S/P
        ratio measured on the frame (with ``glare_halo`` added) only where m can be < 1."""
        if leaves_frame(lp):  # m = 1 whatever the S/P ratio: not measured
            return None, 1.0, lp
        sp = self.measure_sp_ratio(hdr_texture, glare_halo)
        m, lmes = mesopic_coefficient(lp, lp * sp)
        return sp, m, lmes

    def _record(self, lp, sp, m, lmes, sigma, level, level_sigma) -> None:
        """:attr:`last_state` of a pass (or of :meth:`colours`)."""
        self.last_state = {
            "lp": lp,
            "sp": sp,
            "ls": None if sp is None else lp * sp,
            "m": m,
            "lmes": lmes,
            "sigma_px": sigma,
            "level": level,
            "level_sigma_px": level_sigma,
        }

    def colours(
        self,
        hdr_texture,
        size: tuple[int, int],
        *,
        adaptation: float,
        glare_halo: GlareHalo | None = None,
    ) -> MesopicBlend | None:
        """The eye's colours of ``hdr_texture`` (with ``glare_halo`` added) at a photopic
        ``adaptation`` (cd/m^2) for the tone map to apply as it reads the frame
        (MESOPIC_BLEND), or None at m = 1: what :meth:`apply` draws, without its pass over
        the frame. For a pass without noise and blur (``NightVision(noise=False,
        acuity=False)``, the eye metering's); :attr:`last_state` as :meth:`apply` sets it."""
        if self.noise or self.acuity:
            raise ParameterError("colours() is the eye's colours alone: no noise, no acuity")
        w, h = (int(v) for v in size)
        if tuple(hdr_texture.size) != (w, h):
            raise ParameterError(f"size = {size!r} does not match the texture's {hdr_texture.size}")
        lp = check_range("adaptation", adaptation, 1e-12, 1e12, "cd/m^2")
        sp, m, lmes = self._mesopic(hdr_texture, lp, glare_halo)
        self._record(lp, sp, m, lmes, 0.0, 0, 0.0)
        if m >= 1.0:
            return None
        # m <= 0 (post/night_vision.glsl's NV_SCOTOPIC_ONLY): w_p = 0 gives L_s C_b exactly
        return MesopicBlend(photopic_share(m), tuple(float(c) for c in BLUE_GREY))

    def apply(
        self,
        hdr_texture,
        size: tuple[int, int],
        *,
        pixel_angle_rad: float,
        adaptation,
        time_s: float = 0.0,
    ):
        """Run the pass over ``hdr_texture`` (RGBA32F, GL rows, (width, height) = ``size``).

        Args:
            hdr_texture: R, G, B linear sRGB in cd/m^2, A scotopic cd/m^2.
            size: (width, height) in pixels.
            pixel_angle_rad: angular size of one pixel at the frame's centre, rad (> 0).
            adaptation: photopic adaptation luminance (cd/m^2, > 0), or a GpuExposure that
                has measured the frame (its log-average luminance, one texel, is read back).
            time_s: frame time, s: drives the noise (same seed and time, same image).

        Returns:
            An RGBA32F texture of the same size: R, G, B the displayed (photopic-equivalent)
            luminance in cd/m^2, A the input's scotopic channel (blurred with the rest);
            ``hdr_texture`` itself at m = 1 (photopic: nothing to change).
        """
        w, h = (int(v) for v in size)
        if w <= 0 or h <= 0:
            raise ParameterError(f"size = {size!r} must be two positive integers")
        if tuple(hdr_texture.size) != (w, h):
            raise ParameterError(f"size = {size!r} does not match the texture's {hdr_texture.size}")
        px = check_range("pixel_angle_rad", pixel_angle_rad, 1e-9, math.pi, "rad")
        t = check_range("time_s", time_s, -1e9, 1e9, "s")
        if _is_number(adaptation):
            lp = check_range("adaptation", adaptation, 1e-12, 1e12, "cd/m^2")
        elif hasattr(adaptation, "read") and hasattr(adaptation, "texture"):
            lp = float(adaptation.read())
        else:
            raise ParameterError(
                f"adaptation must be a luminance in cd/m^2 or a GpuExposure, got "
                f"{type(adaptation).__name__}"
            )
        sp, m, lmes = self._mesopic(hdr_texture, lp)
        sigma = blur_sigma_px(lp, px) if self.acuity and m < 1.0 else 0.0
        level, s = blur_plan(sigma, (w, h))
        self._record(lp, sp, m, lmes, sigma, level, s)
        if m >= 1.0:
            return hdr_texture

        uniforms = NightVisionInputs(
            u_src=None,
            u_wp=photopic_share(m),
            u_noise_scale=1.0 - m,
            u_blue_grey=tuple(float(c) for c in BLUE_GREY),
            u_noise_base=noise_base(self.seed, t),
        )
        final = {"NV_NOISE": int(self.noise), "NV_SCOTOPIC_ONLY": int(m <= 0.0)}
        source = hdr_texture
        if s > 0.0:
            weights = tuple(float(x) for x in gaussian_weights(s))
            radius = len(weights) - 1
            uniforms = replace(uniforms, u_weights=weights)
            if level == 0 and m <= 0.0:
                # Scotopic: blur the scotopic channel only, four pixels to a texel.
                packed = (-(-w // 4), h)
                tex_x, fbo_x = self._targets.get("packed_x", packed)
                tex_y, fbo_y = self._targets.get("packed_y", packed)
                self._run(
                    "post/night_scotopic_blur.glsl",
                    fbo_x,
                    packed,
                    uniforms,
                    hdr_texture,
                    NV_RADIUS=radius,
                )
                self._run(
                    "post/acuity_blur.glsl",
                    fbo_y,
                    packed,
                    uniforms,
                    tex_x,
                    NV_RADIUS=radius,
                    NV_AXIS=1,
                )
                source, final["NV_SOURCE"] = tex_y, 1
            elif level == 0:
                # Across; the final pass takes the taps down.
                tex_x, fbo_x = self._targets.get("full_x", (w, h))
                self._run(
                    "post/acuity_blur.glsl",
                    fbo_x,
                    (w, h),
                    uniforms,
                    hdr_texture,
                    NV_RADIUS=radius,
                    NV_AXIS=0,
                )
                source, final["NV_SOURCE"], final["NV_VRADIUS"] = tex_x, 0, radius
            else:
                # Reduced k times, blurred across and down there, enlarged by the final pass.
                src, lw, lh = hdr_texture, w, h
                for k in range(1, level + 1):
                    lw, lh = -(-lw // 2), -(-lh // 2)
                    tex_k, fbo_k = self._targets.get(f"level{k}", (lw, lh))
                    self._run("post/night_downsample.glsl", fbo_k, (lw, lh), uniforms, src)
                    src = tex_k
                tmp, fbo_tmp = self._targets.get(f"level{level}_x", (lw, lh))
                fbo_k = self._targets.get(f"level{level}", (lw, lh))[1]
                self._run(
                    "post/acuity_blur.glsl",
                    fbo_tmp,
                    (lw, lh),
                    uniforms,
                    src,
                    NV_RADIUS=radius,
                    NV_AXIS=0,
                )
                self._run(
                    "post/acuity_blur.glsl",
                    fbo_k,
                    (lw, lh),
                    uniforms,
                    tmp,
                    NV_RADIUS=radius,
                    NV_AXIS=1,
                )
                f = float(2**level)
                uniforms = replace(uniforms, u_uv_scale=(1.0 / (f * lw), 1.0 / (f * lh)))
                source, final["NV_SOURCE"] = src, 2
        else:
            final["NV_SOURCE"] = 0
        out_tex, out_fbo = self._targets.get("out", (w, h))
        self._run("post/night_vision.glsl", out_fbo, (w, h), uniforms, source, **final)
        return out_tex

    def _run(self, name, fbo, size, inputs: NightVisionInputs, source, **defines) -> None:
        fbo.viewport = (0, 0, *size)
        self._program(name, **defines).draw(fbo, replace(inputs, u_src=source))

    def release(self) -> None:
        """Free the programs, targets and the measurement grid."""
        self._targets.release()
        for prog in self._programs.values():
            prog.release()
        self._programs.clear()
        self._grid_mean.release()
        self._grid_fbo.release()
        self._grid.release()
        self._measure.release()
        self._measure_glared.release()
