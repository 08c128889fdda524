"""The refraction of each pixel's view ray as a table, for full-screen passes.

``shaders/common/refraction.glsl``'s ``airless_direction`` (Bennett's law, then two
Saemundsson steps) costs ~30 ms a 1280 x 720 pass on llvmpipe; the smooth layers (the
zodiacal light, the Milky Way) read the same result from a table by the sine of the apparent
elevation instead (``shaders/common/airless_table.glsl``): the airless direction of a unit
apparent direction ``d`` is parallel to ``d + k(z) (z d - up)``. :class:`RefractionTable`
holds the table as a texture for the weather's refraction factor.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = [
    "REFRACTION_TABLE_SIZE",
    "RefractionTable",
    "airless_offset",
    "airless_offset_lookup",
    "airless_offset_table",
]


#: Nodes of the refraction table over the sine of the apparent elevation, -1 to 1.
REFRACTION_TABLE_SIZE = 4096


def airless_offset(z, refraction_scale: float = 1.0) -> np.ndarray:
    """Float64 twin of ``airless_direction`` in ``shaders/common/refraction.glsl`` (Bennett
    1982 then two Saemundsson 1986 steps, Meeus eq. 16.3-16.4, with their cut-offs at -1 and
    -1.9 deg), written as one number per sine ``z`` of the apparent elevation: the airless
    direction of a unit apparent one ``d`` is parallel to ``d + k (z d - up)`` with
    k = tan(R) / cos(h), R the refraction (rad). ``refraction_scale`` is the weather's
    factor (P / 1010 hPa)(283 K / T); 0 gives k = 0."""
    z = np.clip(np.asarray(z, dtype=np.float64), -1.0, 1.0)
    c = np.sqrt(np.maximum(1.0 - z * z, 0.0))
    h = np.degrees(np.arctan2(z, c))
    s = float(refraction_scale)

    def law(x, a, b, d, cut):
        with np.errstate(divide="ignore", invalid="ignore"):
            r = s * np.radians(a / 60.0) / np.tan(np.radians(x + b / (x + d)))
        return np.where(x < cut, 0.0, r)

    r = law(h, 1.0, 7.31, 4.4, -1.0)
    r = law(h - np.degrees(r), 1.02, 10.3, 5.11, -1.9)
    r = law(h - np.degrees(r), 1.02, 10.3, 5.11, -1.9)
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(c > 0.0, np.tan(r) / c, 0.0)
    return k


@lru_cache(maxsize=8)
def airless_offset_table(refraction_scale: float) -> np.ndarray:
    """:func:`airless_offset` at REFRACTION_TABLE_SIZE nodes z = -1 + 2 i / (n - 1), float32
    (read-only), for ``common/airless_table.glsl``: one linear fetch by
    the pixel's z instead of the refraction's trigonometry (the node at the zenith, where
    ``z d - up`` vanishes, takes its neighbour's value)."""
    n = REFRACTION_TABLE_SIZE
    z = np.linspace(-1.0, 1.0, n)
    k = airless_offset(z, refraction_scale)
    k[-1] = k[-2]
    out = k.astype(np.float32)
    out.setflags(write=False)
    return out


def airless_offset_lookup(z, refraction_scale: float = 1.0) -> np.ndarray:
    """Float64 twin of the shaders' fetch: :func:`airless_offset_table` interpolated linearly
    in z between its nodes."""
    t = airless_offset_table(float(refraction_scale)).astype(np.float64)
    x = (np.clip(np.asarray(z, dtype=np.float64), -1.0, 1.0) + 1.0) * 0.5 * (len(t) - 1)
    i = np.clip(np.floor(x).astype(int), 0, len(t) - 2)
    f = x - i
    return (1.0 - f) * t[i] + f * t[i + 1]


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

    @staticmethod
    def uniforms() -> dict:
        n = REFRACTION_TABLE_SIZE
        return {"u_offset_map": (0.5 * (n - 1) / n, 0.5)}  # node i of n at (i + 0.5) / n

    def release(self) -> None:
        if self._texture is not None:
            self._texture.release()
        self._texture = self._scale = None
