"""GPU automatic exposure: the log-average luminance of a frame texture, kept on the GPU.

Reinhard et al. 2002 eq. 1 as :func:`skydome.display.exposure.log_average_luminance`
computes it (pixels with no light ignored, delta subtracted again), over a 256 x 128 grid of
samples spread evenly over the frame (``post/log_luminance.glsl``), averaged into one texel
by :class:`GridMean` (``post/grid_mean.glsl``, two passes): the tone-mapping pass reads that
texel, so a window needs no read-back. :meth:`GpuExposure.read` fetches it for reports and
eye adaptation.
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
from skydome.errors import ParameterError
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.spectra import SRGB_LUMINANCE

#: Sample grid (a multiple of GridMean's blocks, so every sample weighs the same): 32768.
GRID = (256, 128)
#: GridMean's first pass averages blocks of this many samples (its second, the blocks).
GRID_BLOCK = (16, 16)


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
    log-luminance grid's mean (GridMean's 1 x 1 texture), its level (0), the logarithm's
    offset (cd/m^2)."""

    u_log_luminance: object
    u_log_luminance_level: float
    u_delta: float


@dataclass(frozen=True)
class GridMeanInputs(ShaderInputs):
    """``post/grid_mean.glsl``: the grid (or the block means) to average."""

    u_src: object


class GridMean:
    """The mean of every texel of a GRID-sized RGBA32F sample grid, into one texel kept on
    the GPU (:attr:`texture`, 1 x 1): the grid's GRID_BLOCK blocks averaged by one pass, then
    those means by a second. In real arithmetic the mean of a power-of-two grid's mipmap
    chain; on llvmpipe a fifth of glGenerateMipmap's time in a running pipeline."""

    def __init__(self, ctx, grid: tuple[int, int] = GRID, block: tuple[int, int] = GRID_BLOCK):
        if grid[0] % block[0] or grid[1] % block[1]:
            raise ParameterError(f"grid {grid} is not a whole number of {block} blocks")
        self.ctx = ctx
        self._mid_size = (grid[0] // block[0], grid[1] // block[1])
        self._blocks = FullscreenPass(
            ctx, "post/grid_mean.glsl", {"BLOCK_W": block[0], "BLOCK_H": block[1]},
            inputs=(GridMeanInputs,),
        )  # fmt: skip
        self._whole = FullscreenPass(
            ctx, "post/grid_mean.glsl", {"BLOCK_W": self._mid_size[0], "BLOCK_H": self._mid_size[1]},
            inputs=(GridMeanInputs,),
        )  # fmt: skip
        self._mid = ctx.texture(self._mid_size, 4, dtype="f4")
        self.texture = ctx.texture((1, 1), 4, dtype="f4")
        for tex in (self._mid, self.texture):
            tex.filter = (ctx.NEAREST, ctx.NEAREST)
        self._mid_fbo = ctx.framebuffer(color_attachments=[self._mid])
        self._fbo = ctx.framebuffer(color_attachments=[self.texture])

    def average(self, grid_texture) -> None:
        """Average ``grid_texture`` (RGBA32F, the grid's size) into :attr:`texture`."""
        self._mid_fbo.viewport = (0, 0, *self._mid_size)
        self._blocks.draw(self._mid_fbo, GridMeanInputs(grid_texture))
        self._fbo.viewport = (0, 0, 1, 1)
        self._whole.draw(self._fbo, GridMeanInputs(self._mid))

    def read(self) -> np.ndarray:
        """The mean (4 float32) of the last averaged grid."""
        return np.frombuffer(self.texture.read(), dtype=np.float32)

    def release(self) -> None:
        for obj in (self._mid_fbo, self._fbo, self._mid, self.texture, self._blocks, self._whole):
            obj.release()


class GpuExposure:
    """The log-luminance pass, its sample grid and the grid's mean for one context."""

    def __init__(self, ctx):
        self.ctx = ctx
        self._passes: dict[int, FullscreenPass] = {}
        self.pass_ = self._pass(0)
        self.texture = ctx.texture(GRID, 4, dtype="f4")
        self.texture.filter = (ctx.NEAREST, ctx.NEAREST)
        self.fbo = ctx.framebuffer(color_attachments=[self.texture])
        self.mean = GridMean(ctx)

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
        """Average the log luminance of ``hdr_texture`` (RGBA32F) into one texel, with
        the weights of ``metering`` (``skydome.display.exposure.METERINGS``)."""
        self.fbo.viewport = (0, 0, *GRID)
        weights = tuple(float(x) for x in SRGB_LUMINANCE)
        fpass = self._pass(METERING_IDS[check_metering(metering)])
        fpass.draw(self.fbo, LogLuminanceInputs(hdr_texture, weights, DEFAULT_DELTA))
        self.mean.average(self.texture)

    def inputs(self) -> AutoExposureInputs:
        """What ``post/tonemap.glsl`` compiled with AUTO_EXPOSURE reads."""
        return AutoExposureInputs(self.mean.texture, 0.0, DEFAULT_DELTA)

    def read(self) -> float:
        """The log-average luminance (cd/m^2) of the last measured frame (one texel read)."""
        data = self.mean.read()
        log_sum, weight = float(data[0]), float(data[1])
        if weight <= 0.0:
            return DEFAULT_DELTA
        return max(math.exp(log_sum / weight) - DEFAULT_DELTA, DEFAULT_DELTA)

    def release(self) -> None:
        self.mean.release()
        self.fbo.release()
        self.texture.release()
        for fpass in self._passes.values():
            fpass.release()
        self._passes.clear()
