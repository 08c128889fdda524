"""Frames drawn in tiles, and per-pixel inputs made into textures tile by tile.

GL's framebuffer limit is 16384 a side on llvmpipe and most GPUs, and a tile's float
targets cost 64 MB per attachment at 2048 x 2048: frames larger than TILE_SIZE on a side are
drawn tile by tile (the shaders see the whole frame through ``u_resolution`` and the tile's
place through ``u_tile_offset``), so their size is bounded by memory only.
"""

from __future__ import annotations

import numpy as np

from skydome.errors import ParameterError

#: Frames larger than this on a side are drawn in tiles of this size.
TILE_SIZE = 2048


def frame_tiles(width: int, height: int, tile: int = TILE_SIZE):
    """(x0, y0, w, h) of the tiles covering a frame, in GL pixel coordinates (y up)."""
    for y0 in range(0, height, tile):
        for x0 in range(0, width, tile):
            yield x0, y0, min(tile, width - x0), min(tile, height - y0)


def input_image(
    name: str, image, size: tuple[int, int], scale: float = 1.0, posinf: float = 0.0
) -> np.ndarray:
    """A per-pixel input: an (H, W) float32 image (row 0 at the top) scaled by ``scale``.

    +inf becomes ``posinf`` (for a depth image 0: no scene along that ray, as values <= 0;
    for shadow lengths a length past any ray's end). NaN and -inf are refused.
    """
    w, h = size
    try:
        a = np.asarray(image, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(
            f"{name} must be a ({h}, {w}) array of numbers, got {type(image).__name__}"
        ) from None
    if a.shape != (h, w):
        raise ParameterError(f"{name} must be a ({h}, {w}) array for this frame, got {a.shape}")
    if np.isnan(a).any() or np.isneginf(a).any():
        raise ParameterError(f"{name} must hold finite numbers or +inf (no scene), not NaN/-inf")
    return np.where(np.isposinf(a), posinf, a * scale).astype(np.float32)


def input_texture(ctx, image: np.ndarray):
    """A float32 texture (texelFetch) of one tile of a per-pixel input (H, W) or (H, W, C),
    row 0 at the top, in GL row order. The caller releases it."""
    th, tw = image.shape[:2]
    channels = 1 if image.ndim == 2 else image.shape[2]
    data = np.ascontiguousarray(image[::-1], dtype="f4")
    return ctx.texture((tw, th), channels, data.tobytes(), dtype="f4")
