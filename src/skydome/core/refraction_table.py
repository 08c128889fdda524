"""The refraction of each pixel's view ray as a texture, for full-screen passes.

``shaders/common/refraction.glsl``'s ``airless_direction`` (Bennett's law, then two
Saemundsson steps) costs ~30 ms a 1280 x 720 pass on llvmpipe; the smooth layers (the
zodiacal light, the Milky Way) read the same result from a table by the sine of the apparent
elevation instead (``shaders/common/airless_table.glsl``; the table and its float64 twin are
``skydome.physics.refraction.airless_offset_table`` and ``airless_offset_lookup``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from skydome.gpu.inputs import ShaderInputs
from skydome.physics.refraction import REFRACTION_TABLE_SIZE, airless_offset_table


@dataclass(frozen=True)
class AirlessTableInputs(ShaderInputs):
    """``common/airless_table.glsl``: the table (a texture) and where node i of n lies in
    texture coordinates (scale, offset)."""

    u_airless_offset: object
    u_offset_map: tuple[float, float]


class RefractionTable:
    """The table of :func:`airless_offset_table` as a texture (linear, clamped) for one
    context, remade when the weather's refraction factor changes; and the uniforms of
    ``common/airless_table.glsl``."""

    def __init__(self):
        self._texture = None
        self._scale = None

    def texture(self, ctx, refraction_scale: float):
        if self._texture is None or self._scale != refraction_scale:
            self.release()
            table = np.ascontiguousarray(airless_offset_table(float(refraction_scale)))
            tex = ctx.texture((len(table), 1), 1, table.tobytes(), dtype="f4")
            tex.filter = (ctx.LINEAR, ctx.LINEAR)
            tex.repeat_x = tex.repeat_y = False
            self._texture, self._scale = tex, refraction_scale
        return self._texture

    def inputs(self, ctx, refraction_scale: float) -> AirlessTableInputs:
        """The table of the weather's ``refraction_scale`` as a shader input."""
        n = REFRACTION_TABLE_SIZE
        # node i of n at (i + 0.5) / n
        return AirlessTableInputs(self.texture(ctx, refraction_scale), (0.5 * (n - 1) / n, 0.5))

    def release(self) -> None:
        if self._texture is not None:
            self._texture.release()
        self._texture = self._scale = None
