"""GPU tone mapping: an RGBA32F frame texture -> an 8-bit sRGB image, with ``post/tonemap.glsl``.

Row order: NumPy frames have row 0 at the top of the image; GL textures and framebuffers have
row 0 at the bottom. The flip happens only at the CPU/GPU boundary, in :func:`upload_frame`
(NumPy -> texture) and :func:`read_rgb8` (framebuffer -> NumPy). A texture rendered by a GL
pass (e.g. the sky renderer's float target) is already in GL order and is used as is.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from skydome.display.glare import GlareHalo
from skydome.display.gpu_exposure import AutoExposureInputs
from skydome.display.night_vision import MesopicBlend
from skydome.display.tonemap import (
    FILMIC_DESATURATION_STOPS,
    FILMIC_INPUT_CAP,
    as_array,
    check_exposure_scale,
    check_frame,
    get_operator,
)
from skydome.errors import ParameterError
from skydome.gpu import FullscreenPass, shared_context
from skydome.gpu.inputs import ShaderInputs
from skydome.spectra import SRGB_LUMINANCE

#: NumPy frames larger than this many pixels are tone-mapped in bands of rows (64 MB each).
BAND_PIXELS = 1 << 22


def upload_frame(ctx, frame: np.ndarray):
    """Upload a NumPy frame (H, W, 4) or (H, W, 3), row 0 at the top, as an RGBA32F texture
    in GL row order (row 0 = bottom). Nearest filtering. The caller releases the texture."""
    a = check_frame(frame)
    h, w = a.shape[:2]
    rgba = np.zeros((h, w, 4), dtype=np.float32)
    rgba[..., : a.shape[-1]] = a
    tex = ctx.texture((w, h), 4, np.ascontiguousarray(rgba[::-1]).tobytes(), dtype="f4")
    tex.filter = (ctx.NEAREST, ctx.NEAREST)
    return tex


def read_rgb8(fbo, width: int, height: int) -> np.ndarray:
    """Read an RGBA8 framebuffer back as uint8 (H, W, 3), row 0 at the top of the image."""
    data = np.frombuffer(
        fbo.read(viewport=(0, 0, width, height), components=3, alignment=1), dtype=np.uint8
    )
    return data.reshape(height, width, 3)[::-1].copy()  # GL rows are bottom-up


@dataclass(frozen=True)
class ToneMapInputs(ShaderInputs):
    """``post/tonemap.glsl``: the frame (RGBA32F), the output's size (px), the operator and
    its parameters (None where another operator's), the exposure (m^2/cd), the luminance
    weights of RGB."""

    u_hdr: object
    u_viewport: tuple[float, float]
    u_operator: int
    u_exposure: float
    u_luminance_weights: tuple[float, float, float]
    u_exp_k: float | None = None
    u_inv_white_sq: float | None = None
    u_hvs_a: float | None = None
    u_hvs_b: float | None = None
    u_hvs_x_scale: float | None = None
    u_filmic_pre_scale: float | None = None


class GpuToneMapper:
    """Runs ``post/tonemap.glsl``: one compiled program for all operators, RGBA8 targets cached
    per size. Also usable by the viewer: :meth:`draw` renders into any framebuffer.

    Args:
        ctx: a moderngl context (default: the shared headless one).
        quantize: snap outputs to 8-bit code values in the shader (exact round(255 v) in an
            RGBA8 target, whatever the driver's float -> unorm rounding). Keep it on for
            8-bit targets.
    """

    def __init__(self, ctx=None, *, quantize: bool = True):
        self.ctx = ctx or shared_context()
        defines = {
            "TONEMAP_QUANTIZE": int(quantize),
            "FILMIC_INPUT_CAP": float(FILMIC_INPUT_CAP),
            "FILMIC_DESATURATION_STOPS": float(FILMIC_DESATURATION_STOPS),
        }
        self._defines = defines
        # One program per (operator, auto exposure), compiled on first use: the operator is
        # a compile-time constant (a CPU rasterizer would run every operator's branch).
        self._passes: dict[tuple[int, bool, bool, bool], FullscreenPass] = {}
        self._targets: dict[tuple[int, int], tuple] = {}

    def program(
        self,
        name: str,
        auto_exposure: bool = False,
        glare_halo: bool = False,
        mesopic: bool = False,
    ) -> FullscreenPass:
        """The compiled pass of operator ``name`` (with AUTO_EXPOSURE, GLARE_HALO,
        MESOPIC_BLEND when asked)."""
        key = (get_operator(name).gl_id, bool(auto_exposure), bool(glare_halo), bool(mesopic))
        if key not in self._passes:
            defines = {**self._defines, "TONEMAP_OPERATOR": key[0]}
            inputs = [ToneMapInputs]
            if key[1]:
                defines["AUTO_EXPOSURE"] = 1
                inputs.append(AutoExposureInputs)
            if key[2]:
                defines["GLARE_HALO"] = 1
                inputs.append(GlareHalo)
            if key[3]:
                defines["MESOPIC_BLEND"] = 1
                inputs.append(MesopicBlend)
            self._passes[key] = FullscreenPass(
                self.ctx, "post/tonemap.glsl", defines, inputs=tuple(inputs)
            )
        return self._passes[key]

    def inputs(
        self, texture, viewport, name: str, exposure_scale: float, **params: float
    ) -> ToneMapInputs:
        """The inputs of ``post/tonemap.glsl`` for a frame texture, an operator, exposure
        and parameters (validated as in :func:`skydome.display.tonemap.tonemap`)."""
        op = get_operator(name)
        checked = op.check_params(params)
        return ToneMapInputs(
            u_hdr=texture,
            u_viewport=tuple(float(v) for v in viewport),
            u_operator=op.gl_id,
            u_exposure=check_exposure_scale(exposure_scale),
            u_luminance_weights=tuple(float(x) for x in SRGB_LUMINANCE),
            **op.gl_uniforms(checked),
        )

    def draw(
        self,
        texture,
        fbo,
        viewport: tuple[int, int],
        name: str,
        exposure_scale: float,
        *,
        auto_exposure=None,
        glare_halo: GlareHalo | None = None,
        mesopic: MesopicBlend | None = None,
        **params: float,
    ) -> None:
        """Tone-map ``texture`` (RGBA32F, GL row order) into ``fbo`` over ``viewport`` =
        (width, height) pixels (nearest-neighbour resampling if sizes differ).

        With ``auto_exposure`` (a :class:`skydome.display.gpu_exposure.GpuExposure` that has
        measured ``texture``), ``exposure_scale`` is the key times 2^compensation and the
        shader divides it by the measured log-average luminance: no read-back. With
        ``glare_halo`` (:meth:`skydome.display.glare.GpuGlare.halo` of ``texture``) the
        glare is added as the frame is read: the image of the glared frame, one pass less;
        with ``mesopic`` (:meth:`skydome.display.night_vision.NightVision.colours`), the
        eye's colours after it.
        """
        w, h = viewport
        fbo.viewport = (0, 0, w, h)
        inputs = [self.inputs(texture, (w, h), name, exposure_scale, **params)]
        fpass = self.program(
            name, auto_exposure is not None, glare_halo is not None, mesopic is not None
        )
        if auto_exposure is not None:
            inputs.append(auto_exposure.inputs())
        if glare_halo is not None:
            inputs.append(glare_halo)
        if mesopic is not None:
            inputs.append(mesopic)
        fpass.draw(fbo, *inputs)

    def _target(self, width: int, height: int):
        if (width, height) not in self._targets:
            tex = self.ctx.texture((width, height), 4, dtype="f1")
            self._targets[(width, height)] = (tex, self.ctx.framebuffer(color_attachments=[tex]))
        return self._targets[(width, height)]

    def render(
        self,
        source,
        name: str,
        exposure_scale: float,
        *,
        overlay=None,
        glare_halo: GlareHalo | None = None,
        mesopic: MesopicBlend | None = None,
        **params: float,
    ) -> np.ndarray:
        """Tone-map ``source`` and read it back as uint8 (H, W, 3), row 0 at the top
        (``glare_halo``, ``mesopic``: as in :meth:`draw`, for a texture ``source``).

        ``source`` is a NumPy frame (H, W, 4) in cd/m^2 (row 0 at the top; uploaded with
        :func:`upload_frame`; a ``Frame`` object's ``.data`` too) or a moderngl RGBA float
        texture in GL row order. ``overlay(fbo, (w, h))``, if given, draws over the
        tone-mapped image before it is read back (the whole frame: not banded).
        """
        if isinstance(getattr(source, "data", None), np.ndarray):
            source = as_array(source)
        if (
            overlay is None
            and isinstance(source, np.ndarray)
            and source.shape[0] * source.shape[1] > BAND_PIXELS
        ):
            # Large frames go up in bands of rows: GPU memory stays at one band's texture, and
            # no side reaches GL's texture limit. Tone maps are per pixel: bands are exact.
            rows = max(1, BAND_PIXELS // source.shape[1])
            bands = [
                self.render(source[y : y + rows], name, exposure_scale, **params)
                for y in range(0, source.shape[0], rows)
            ]
            return np.concatenate(bands)
        if isinstance(source, np.ndarray):
            texture = upload_frame(self.ctx, source)
            owned = True
        elif hasattr(source, "size") and hasattr(source, "use"):
            texture, owned = source, False
        else:
            raise ParameterError(
                f"tone-map source must be a NumPy frame or a moderngl texture, got "
                f"{type(source).__name__}"
            )
        try:
            w, h = texture.size
            _, fbo = self._target(w, h)
            self.draw(
                texture, fbo, (w, h), name, exposure_scale,
                glare_halo=glare_halo, mesopic=mesopic, **params,
            )  # fmt: skip
            if overlay is not None:
                overlay(fbo, (w, h))
            return read_rgb8(fbo, w, h)
        finally:
            if owned:
                texture.release()

    def release(self) -> None:
        """Free the program and the cached targets."""
        for tex, fbo in self._targets.values():
            fbo.release()
            tex.release()
        self._targets.clear()
        for p in self._passes.values():
            p.release()
        self._passes.clear()


_mappers: dict[int, GpuToneMapper] = {}


def gpu_tonemap(
    source,
    name: str,
    exposure_scale: float,
    *,
    ctx=None,
    overlay=None,
    glare_halo: GlareHalo | None = None,
    mesopic: MesopicBlend | None = None,
    **params: float,
) -> np.ndarray:
    """GPU twin of :func:`skydome.display.tonemap.tonemap`: uint8 (H, W, 3), row 0 at the top.

    ``source`` is a NumPy frame or an RGBA32F texture (GL row order); ``overlay(fbo, size)``
    draws over the image before the read-back; ``glare_halo`` adds a texture's glare and
    ``mesopic`` applies the eye's colours (:meth:`GpuToneMapper.draw`). The mapper for each
    context is created once and reused.
    """
    ctx = ctx or shared_context()
    mapper = _mappers.get(id(ctx))
    if mapper is None or mapper.ctx is not ctx:
        mapper = _mappers[id(ctx)] = GpuToneMapper(ctx)
    return mapper.render(
        source,
        name,
        exposure_scale,
        overlay=overlay,
        glare_halo=glare_halo,
        mesopic=mesopic,
        **params,
    )
