"""Glare: the point spread function of the eye (or of a camera lens) on the displayed image.

A display cannot show the Sun, Venus or Sirius as bright as they are; an eye (or a lens)
looking at them scatters part of their light into a halo around them, and that halo is how
we see that they are bright. Spencer, Shirley, Zimmerman & Greenberg 1995 ("Physically-based
glare effects for digital images", SIGGRAPH 95) convolve the HDR image with the eye's point
spread function (PSF) before the tone map, so that the halo the real source would make in
the viewer's eye is drawn into the picture. This pass does so, on the display image only:
``Frame.data`` and the EXR/HDR/NPY files stay the physical frame, bit for bit.

**The eye** (``glare="eye"``): the CIE General Disability Glare Equation (CIE 146:2002,
Vos & van den Berg; Vos 2003, Clin. Exp. Optom. 86, 363), the veiling luminance a point
source of illuminance E (lx at the eye) makes at an angle theta (deg) from it,

    L_veil / E = 10 / theta^3 + (5 / theta^2 + 0.1 p / theta) (1 + (A / 62.5)^4) + 0.0025 p

(sr^-1, valid 0.1 deg < theta < 100 deg; age A = 25 years, pigmentation p = 0.5 here). Over
1-30 deg it lies within a factor 0.65-1.55 of the classic Stiles-Holladay L_veil = 10 E /
theta^2. Light falling within 0.1 deg of a source (below the equation's domain, and about
a pixel of a 90 deg view) stays where it is: the PSF's core, 1 minus the halo's share.

**A lens** (``glare="lens"``): a camera's veiling glare, a halo ``L / E = 1 / theta^3``
(theta in deg, > 0.1 deg): 2 % of the light scattered outside 0.1 deg, the veiling-glare
index of a good multi-coated lens (ISO 9358 measures 1-3 %), falling faster than the eye's.

**How.** The halo is a weighted sum of Gaussians at octave scales, each one level of an image
pyramid: the frame is halved K times by the [1, 3, 3, 1] / 8 B-spline
(``post/glare_down.glsl``: four bilinear look-ups, variance 0.75 px^2 of each level per
halving), then climbed
back up, each level adding w_k times its own image to the cubic B-spline enlargement of the
coarser levels' sum (``post/glare_up.glsl``, ``post/glare_upsample.glsl``: variance 4/3 px^2
of the finer level per enlargement, and no squares around a bright point as a bilinear one
leaves); the last pass adds that sum to (1 - sum w_k) times the frame
(``post/glare_composite.glsl``). Level k therefore stands for a Gaussian of variance
``25/36 (4^k - 1)`` frame px^2 per axis (:func:`level_variance_px2`), and the weights are
fitted to the PSF in pixels of the camera's angular size (:func:`glare_weights`, non-negative
least squares on the relative error, at radii from 2 px or 0.1 deg to half the frame's
diagonal or 90 deg). All four channels (R, G, B and scotopic) are spread alike: the eye
scatters the light before the receptors. The cost is a few passes over a quarter of the
frame and one over the frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from skydome.errors import ParameterError, check_range
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.textures import FloatTargets
from skydome.physics.fitting import nonnegative_lstsq

#: Glare modes: none, the human eye's PSF, a camera lens's veiling glare.
GLARES = ("off", "eye", "lens")
#: Glare used for tone-mapped images when none is named.
DEFAULT_GLARE = "eye"
#: Observer of the CIE general disability glare equation: age (years), pigmentation factor
#: (0 black eyes, 0.5 brown, 1 light blue: CIE 146:2002).
EYE_AGE_YEARS = 25.0
EYE_PIGMENTATION = 0.5
#: The CIE equations' lower bound of validity (deg): closer to a source, its light is the core.
PSF_MIN_DEG = 0.1
#: The field (deg, horizontal) a picture is taken to fill of its viewer's sight. A camera
#: with a narrower field magnifies the sky (a telescope's view) by NATURAL_VIEW_DEG / its
#: field, and the eye's glare, which the viewer's own eye adds to what it sees, spreads over
#: the magnified angles: a 1 deg close-up of the Moon gets the halo of a 60 deg disk's edge,
#: not a halo 60 times the Moon's size.
NATURAL_VIEW_DEG = 60.0
#: The widest angle the halo is fitted to (deg).
PSF_MAX_DEG = 90.0
#: Lens veiling glare: L / E = LENS_PSF_A / theta^3 (theta in deg): 2 % outside 0.1 deg.
LENS_PSF_A = 1.0
#: The halo starts at least this far from a source, frame pixels (the smallest level is a
#: Gaussian of 1.4 px: nearer, the pyramid cannot draw the PSF's shape).
MIN_RADIUS_PX = 2.0
#: Sample radii of the fit.
FIT_SAMPLES = 160
#: Weight of the energy equation in the fit (as many samples of the relative error).
ENERGY_WEIGHT = 10.0


def check_glare(glare) -> str:
    """The glare mode ``glare`` (one of GLARES; None and False mean off), or a ParameterError."""
    if glare is None or glare is False:
        return "off"
    if not isinstance(glare, str) or glare.lower() not in GLARES:
        raise ParameterError(f"glare {glare!r} must be one of {', '.join(GLARES)}")
    return glare.lower()


def cie_disability_glare(
    theta_deg, age_years: float = EYE_AGE_YEARS, pigmentation: float = EYE_PIGMENTATION
):
    """L_veil / E_glare (cd/m^2 per lx, i.e. sr^-1) at ``theta_deg`` from a point source:
    the CIE General Disability Glare Equation (CIE 146:2002), valid 0.1-100 deg."""
    t = np.asarray(theta_deg, dtype=np.float64)
    age = (float(age_years) / 62.5) ** 4
    p = float(pigmentation)
    return 10.0 / t**3 + (5.0 / t**2 + 0.1 * p / t) * (1.0 + age) + 0.0025 * p


def lens_veiling_glare(theta_deg):
    """L_veil / E (sr^-1) of the lens mode at ``theta_deg``: LENS_PSF_A / theta^3."""
    t = np.asarray(theta_deg, dtype=np.float64)
    return LENS_PSF_A / t**3


def psf_sr(theta_deg, glare: str):
    """The halo of glare mode ``glare`` (sr^-1) at ``theta_deg``; 0 below PSF_MIN_DEG."""
    mode = check_glare(glare)
    t = np.asarray(theta_deg, dtype=np.float64)
    if mode == "off":
        return np.zeros_like(t)
    safe = np.maximum(t, PSF_MIN_DEG)
    value = cie_disability_glare(safe) if mode == "eye" else lens_veiling_glare(safe)
    return np.where(t >= PSF_MIN_DEG, value, 0.0)


def eye_magnification(field_deg: float | None) -> float:
    """How much a camera of horizontal field ``field_deg`` (None: a wide map, fisheye or
    equirect) magnifies the sky for the eye: NATURAL_VIEW_DEG / the field, at least 1."""
    if field_deg is None or not field_deg > 0.0:
        return 1.0
    return max(1.0, NATURAL_VIEW_DEG / float(field_deg))


def level_sizes(width: int, height: int) -> list[tuple[int, int]]:
    """Sizes of the pyramid's levels 1..K: each the half (rounded up) of the one before,
    down to the last whose smaller side is at least 2 px."""
    sizes = []
    w, h = int(width), int(height)
    while min(-(-w // 2), -(-h // 2)) >= 2:
        w, h = -(-w // 2), -(-h // 2)
        sizes.append((w, h))
    return sizes


def level_variance_px2(level: int) -> float:
    """Variance (frame px^2 per axis) of the Gaussian that level ``level`` of the pyramid
    stands for: k halvings (0.75 4^l each, l = 0..k-1: 0.25 (4^k - 1)) and k cubic B-spline
    enlargements (4/3 4^(l-1) each, l = 1..k: 4/9 (4^k - 1)), 25/36 (4^k - 1) in all, for
    any phase of a point in the blocks, away from the frame's edges (checked against a 1-D
    float64 simulation of the passes in the tests)."""
    return 25.0 / 36.0 * (4.0**level - 1.0)


@lru_cache(maxsize=64)
def _weights(pixel_deg: float, width: int, height: int, mode: str) -> tuple[tuple, float, float]:
    sizes = level_sizes(width, height)
    r_lo = max(MIN_RADIUS_PX, PSF_MIN_DEG / pixel_deg)
    r_hi = min(0.5 * math.hypot(width, height), PSF_MAX_DEG / pixel_deg)
    if mode == "off" or not sizes or r_lo >= r_hi:
        return (0.0,) * len(sizes), 0.0, 0.0
    r = np.geomspace(r_lo, r_hi, FIT_SAMPLES)
    pixel_sr = math.radians(pixel_deg) ** 2
    target = psf_sr(r * pixel_deg, mode) * pixel_sr  # share of a source's light per pixel
    var = np.array([level_variance_px2(k) for k in range(1, len(sizes) + 1)])
    basis = np.exp(-(r[:, None] ** 2) / (2.0 * var[None, :])) / (2.0 * math.pi * var[None, :])
    # The halo's share of the light: the PSF's integral from r_lo to r_hi (sr^-1 * sr), one
    # more equation (weighted as ENERGY_WEIGHT samples), so that the Gaussians cannot put
    # light inside r_lo, where no sample constrains them.
    t = np.radians(np.geomspace(r_lo, r_hi, 4096) * pixel_deg)
    integrand = psf_sr(np.degrees(t), mode) * 2.0 * math.pi * np.sin(t) * t  # d(ln t)
    share = float(np.sum(0.5 * (integrand[1:] + integrand[:-1]) * np.diff(np.log(t))))
    a = np.vstack([basis / target[:, None], np.full((1, len(var)), ENERGY_WEIGHT / share)])
    b = np.concatenate([np.ones_like(r), [ENERGY_WEIGHT]])
    w = nonnegative_lstsq(a, b)
    fit = basis @ w
    error = float(np.max(np.abs(fit / target - 1.0)))
    return tuple(float(x) for x in w), float(np.sum(w)), error


def glare_weights(
    pixel_angle_rad: float, size: tuple[int, int], glare: str
) -> tuple[np.ndarray, float]:
    """The pyramid's weights w_1..w_K (share of a pixel's light each level spreads) and the
    core share 1 - sum w for frames of ``size`` = (width, height) px whose pixels subtend
    ``pixel_angle_rad`` (rad). Raises ParameterError for a bad angle or mode."""
    p = check_range("pixel_angle_rad", pixel_angle_rad, 1e-9, math.pi, "rad")
    mode = check_glare(glare)
    w, total, _ = _weights(round(math.degrees(p), 12), int(size[0]), int(size[1]), mode)
    return np.array(w), max(1.0 - total, 0.0)


def glare_fit_error(pixel_angle_rad: float, size: tuple[int, int], glare: str) -> float:
    """Largest relative error of the Gaussian-sum fit to the PSF over the fitted radii."""
    mode = check_glare(glare)
    return _weights(round(math.degrees(pixel_angle_rad), 12), int(size[0]), int(size[1]), mode)[2]


@dataclass(frozen=True)
class GlareInputs(ShaderInputs):
    """``post/glare_up.glsl`` (and the halving, ``post/glare_down.glsl``, and the frame of
    ``post/glare_composite.glsl``): the source level, the coarser sum, this level's weight,
    whether there is a coarser level (1) or not (0)."""

    u_src: object
    u_coarse: object = None
    u_weight: float | None = None
    u_coarse_on: float | None = None


@dataclass(frozen=True)
class GlareHalo(ShaderInputs):
    """The glare still to be added to a frame (:meth:`GpuGlare.halo`), for a pass that adds
    it as it reads the frame (``post/tonemap.glsl`` with GLARE_HALO): the frame's value is
    ``u_glare_core`` times its own plus the cubic B-spline enlargement of ``u_glare_halo``
    (RGBA32F, half the frame's size), what ``post/glare_composite.glsl`` would write."""

    u_glare_halo: object
    u_glare_core: float


class GpuGlare:
    """The glare pass for one context: :meth:`apply` returns an RGBA32F texture owned by the
    pass (valid until the next apply of the same size), or the input when there is no halo.
    :attr:`last_ms` is not measured here (see the benchmarks)."""

    def __init__(self, ctx):
        self.ctx = ctx
        self._down = FullscreenPass(ctx, "post/glare_down.glsl", inputs=(GlareInputs,))
        self._up = FullscreenPass(ctx, "post/glare_up.glsl", inputs=(GlareInputs,))
        self._composite = FullscreenPass(
            ctx, "post/glare_composite.glsl", inputs=(GlareInputs, GlareHalo)
        )
        self._targets = FloatTargets(ctx)

    def apply(self, hdr_texture, size: tuple[int, int], *, pixel_angle_rad: float, glare: str):
        """``hdr_texture`` (RGBA32F, GL rows, cd/m^2) with the halo of ``glare`` added."""
        halo = self.halo(hdr_texture, size, pixel_angle_rad=pixel_angle_rad, glare=glare)
        if halo is None:
            return hdr_texture
        return self.composite(hdr_texture, size, halo)

    def composite(self, hdr_texture, size: tuple[int, int], halo: GlareHalo):
        """``hdr_texture`` with ``halo`` (this pass's :meth:`halo` of it) added: an RGBA32F
        texture owned by the pass."""
        w, h = (int(v) for v in size)
        out, fbo = self._targets.get("out", (w, h))
        fbo.viewport = (0, 0, w, h)
        self._composite.draw(fbo, GlareInputs(u_src=hdr_texture), halo)
        return out

    def halo(
        self, hdr_texture, size: tuple[int, int], *, pixel_angle_rad: float, glare: str
    ) -> GlareHalo | None:
        """The halo of ``glare`` over ``hdr_texture`` (RGBA32F, GL rows, cd/m^2) and the
        frame's core share, not yet added (the pyramid's passes, without the composite over
        the whole frame); None when there is no halo. The texture is the pass's own, valid
        until the next call of the same size."""
        w, h = (int(v) for v in size)
        weights, core = glare_weights(pixel_angle_rad, (w, h), glare)
        sizes = level_sizes(w, h)
        if not sizes or not np.any(weights > 0.0):
            return None
        # Halve down to the coarsest level that carries a weight.
        last = int(np.nonzero(weights > 0.0)[0][-1]) + 1
        src = hdr_texture
        downs = []
        # The halving samples bilinearly with clamped edges: the frame's texture is set so
        # for the pass and given back as it was.
        saved = (hdr_texture.filter, hdr_texture.repeat_x, hdr_texture.repeat_y)
        hdr_texture.filter = (self.ctx.LINEAR, self.ctx.LINEAR)
        hdr_texture.repeat_x = hdr_texture.repeat_y = False
        try:
            for k in range(1, last + 1):
                tex, fbo = self._targets.get(f"down{k}", sizes[k - 1])
                fbo.viewport = (0, 0, *sizes[k - 1])
                self._down.draw(fbo, GlareInputs(u_src=src))
                downs.append(tex)
                src = tex
        finally:
            hdr_texture.filter = saved[0]
            hdr_texture.repeat_x, hdr_texture.repeat_y = saved[1], saved[2]
        # Climb back: sum_k = w_k down_k + enlarge(sum_{k+1}).
        coarse = None
        for k in range(last, 0, -1):
            lw, lh = sizes[k - 1]
            tex, fbo = self._targets.get(f"up{k}", (lw, lh))
            fbo.viewport = (0, 0, lw, lh)
            on = 0.0 if coarse is None else 1.0
            below = downs[k - 1] if coarse is None else coarse
            self._up.draw(fbo, GlareInputs(downs[k - 1], below, float(weights[k - 1]), on))
            coarse = tex
        return GlareHalo(coarse, float(core))

    def release(self) -> None:
        self._targets.release()
        for p in (self._down, self._up, self._composite):
            p.release()
