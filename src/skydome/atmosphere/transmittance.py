"""The transmittance table on the GPU: column densities from (r, mu) to the top."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from skydome.atmosphere.inputs import AirGeometry, geometry_inputs, profile_defines
from skydome.atmosphere.params import AtmosphereParams
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.textures import release_unbound

DEFAULT_SIZE = (1024, 256)
#: Simpson intervals per texel (even).
DEFAULT_STEPS = 300


@dataclass(frozen=True)
class TableSizeInputs(ShaderInputs):
    """``atmosphere/transmittance_pass.glsl``: the size (texels) of the table it fills."""

    u_transmittance_size: tuple[int, int]


class TransmittanceTable:
    """An RGBA32F texture of column densities (Rayleigh, Mie, absorption), in km.

    Sampled in GLSL through ``atmosphere/transmittance_lut.glsl`` (``column_to_top``). Depends only on
    the radii and density profiles, not on wavelengths.
    """

    def __init__(
        self,
        ctx,
        params: AtmosphereParams,
        size: tuple[int, int] = DEFAULT_SIZE,
        steps: int = DEFAULT_STEPS,
    ):
        self.ctx = ctx
        self.params = params
        self.size = (int(size[0]), int(size[1]))
        self.texture = ctx.texture(self.size, 4, dtype="f4")
        self.texture.filter = (ctx.LINEAR, ctx.LINEAR)
        self.texture.repeat_x = self.texture.repeat_y = False
        fbo = ctx.framebuffer(color_attachments=[self.texture])
        defines = {"TRANSMITTANCE_STEPS": int(steps), **profile_defines(params)}
        fill = FullscreenPass(
            ctx, "atmosphere/transmittance_pass.glsl", defines,
            inputs=(AirGeometry, TableSizeInputs),
        )  # fmt: skip
        fbo.viewport = (0, 0, *self.size)
        fill.draw(fbo, geometry_inputs(params), TableSizeInputs(self.size))
        ctx.finish()
        fill.release()
        release_unbound(fbo)  # bound by the draw: unbind it (see release_unbound)

    def read(self) -> np.ndarray:
        """The table as (height, width, 3) float32 column densities in km (row 0 = r bottom)."""
        data = np.frombuffer(self.texture.read(), dtype=np.float32)
        return data.reshape(self.size[1], self.size[0], 4)[..., :3].copy()

    def release(self) -> None:
        self.texture.release()
