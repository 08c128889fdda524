"""GPU automatic exposure: the log-average luminance of a frame texture, kept on the GPU.

Reinhard et al. 2002 eq. 1 as :func:`skydome.display.exposure.log_average_luminance`
computes it (pixels with no light ignored, delta subtracted again), over a 256 x 128 grid of
samples spread evenly over the frame (``post/log_luminance.glsl``), averaged by the
texture's mipmap chain: the tone-mapping pass reads the 1 x 1 level, so a window needs no
read-back. :meth:`GpuExposure.read` fetches that one texel for reports and eye adaptation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skydome.display.exposure import (
    CENTER_SIGMA_FRACTION,
    DEFAULT_DELTA,
    METERING_IDS,
    SPOT_AREA_FRACTION,
    check_metering,
)
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.spectra import SRGB_LUMINANCE

#: Sample grid (powers of two, so the mipmap chain averages exactly): 32768 samples.
GRID = (256, 128)


@dataclass(frozen=True)
class LogLuminanceInputs(ShaderInputs):
    """``post/log_luminance.glsl``: the frame (RGBA32F), the luminance weights of its RGB, the
    small offset that keeps the logarithm finite (cd/m^2)."""

    u_hdr: object
    u_luminance_weights: tuple[float, float, float]
    u_delta: float


@dataclass(frozen=True)
class AutoExposureInputs(ShaderInputs):
    """What ``post/tonemap.glsl`` compiled with AUTO_EXPOSURE reads: the measured
    log-luminance texture, its 1 x 1 level, the logarithm's offset (cd/m^2)."""

    u_log_luminance: object
    u_log_luminance_level: float
    u_delta: float


class GpuExposure:
    """The log-luminance pass and its mipmapped target for one context."""

    def __init__(self, ctx):
        self.ctx = ctx
        self._passes: dict[int, FullscreenPass] = {}
        self.pass_ = self._pass(0)
        self.texture = ctx.texture(GRID, 4, dtype="f4")
        self.texture.filter = (ctx.LINEAR_MIPMAP_LINEAR, ctx.LINEAR)
        self.top_level = int(math.log2(max(GRID)))
        # The mip chain is allocated before the framebuffer holds level 0: Mesa (llvmpipe)
        # reallocates a texture's storage at its first glGenerateMipmap, after which a
        # framebuffer made before it no longer writes into the texture (every measure after
        # the first read the first frame's average).
        self.texture.build_mipmaps(0, self.top_level)
        self.fbo = ctx.framebuffer(color_attachments=[self.texture])

    def _pass(self, metering_id: int) -> FullscreenPass:
        if metering_id not in self._passes:
            w, h = GRID
            defines = {
                "GRID_W": w, "GRID_H": h, "METERING": metering_id,
                "CENTER_SIGMA_FRACTION": float(CENTER_SIGMA_FRACTION),
                "SPOT_AREA_FRACTION": float(SPOT_AREA_FRACTION),
            }  # fmt: skip
            self._passes[metering_id] = FullscreenPass(
                self.ctx, "post/log_luminance.glsl", defines, inputs=(LogLuminanceInputs,)
            )
        return self._passes[metering_id]

    def measure(self, hdr_texture, metering: str = "average") -> None:
        """Average the log luminance of ``hdr_texture`` (RGBA32F) into the 1 x 1 level, with
        the weights of ``metering`` (``skydome.display.exposure.METERINGS``)."""
        self.fbo.viewport = (0, 0, *GRID)
        weights = tuple(float(x) for x in SRGB_LUMINANCE)
        fpass = self._pass(METERING_IDS[check_metering(metering)])
        fpass.draw(self.fbo, LogLuminanceInputs(hdr_texture, weights, DEFAULT_DELTA))
        self.texture.build_mipmaps(0, self.top_level)

    def inputs(self) -> AutoExposureInputs:
        """What ``post/tonemap.glsl`` compiled with AUTO_EXPOSURE reads."""
        return AutoExposureInputs(self.texture, float(self.top_level), DEFAULT_DELTA)

    def read(self) -> float:
        """The log-average luminance (cd/m^2) of the last measured frame (one texel read)."""
        data = np.frombuffer(self.texture.read(level=self.top_level), dtype=np.float32)
        log_sum, weight = float(data[0]), float(data[1])
        if weight <= 0.0:
            return DEFAULT_DELTA
        return max(math.exp(log_sum / weight) - DEFAULT_DELTA, DEFAULT_DELTA)

    def release(self) -> None:
        self.fbo.release()
        self.texture.release()
        for fpass in self._passes.values():
            fpass.release()
        self._passes.clear()
