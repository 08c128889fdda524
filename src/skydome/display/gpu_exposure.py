"""GPU automatic exposure: the log-average luminance of a frame texture, kept on the GPU.

Reinhard et al. 2002 eq. 1 as :func:`skydome.display.exposure.log_average_luminance`
computes it (pixels with no light ignored, delta subtracted again), over a 256 x 128 grid of
samples spread evenly over the frame (``post/log_luminance.glsl``), averaged by the
texture's mipmap chain: the tone-mapping pass reads the 1 x 1 level, so a window needs no
read-back. :meth:`GpuExposure.read` fetches that one texel for reports and eye adaptation.
"""

from __future__ import annotations

import math

import numpy as np

from skydome.display.exposure import DEFAULT_DELTA
from skydome.gpu import FullscreenPass
from skydome.spectra import SRGB_LUMINANCE

#: Sample grid (powers of two, so the mipmap chain averages exactly): 32768 samples.
GRID = (256, 128)


class GpuExposure:
    """The log-luminance pass and its mipmapped target for one context."""

    def __init__(self, ctx):
        self.ctx = ctx
        w, h = GRID
        self.pass_ = FullscreenPass(ctx, "post/log_luminance.glsl", {"GRID_W": w, "GRID_H": h})
        self.texture = ctx.texture(GRID, 4, dtype="f4")
        self.texture.filter = (ctx.LINEAR_MIPMAP_LINEAR, ctx.LINEAR)
        self.fbo = ctx.framebuffer(color_attachments=[self.texture])
        self.top_level = int(math.log2(max(GRID)))

    def measure(self, hdr_texture) -> None:
        """Average the log luminance of ``hdr_texture`` (RGBA32F) into the 1 x 1 level."""
        self.fbo.viewport = (0, 0, *GRID)
        self.pass_.draw(
            self.fbo,
            {
                "u_luminance_weights": tuple(float(x) for x in SRGB_LUMINANCE),
                "u_delta": DEFAULT_DELTA,
            },
            {"u_hdr": hdr_texture},
        )
        self.texture.build_mipmaps(0, self.top_level)

    def uniforms(self) -> dict[str, object]:
        """What ``post/tonemap.glsl`` compiled with AUTO_EXPOSURE reads."""
        return {"u_log_luminance_level": float(self.top_level), "u_delta": DEFAULT_DELTA}

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
        self.pass_.release()
