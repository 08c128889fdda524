"""Frames drawn in tiles, and per-pixel inputs made into textures tile by tile.

GL's framebuffer limit is 16384 a side on llvmpipe and most GPUs, and a tile's float
targets cost 64 MB per attachment at 2048 x 2048: frames larger than TILE_SIZE on a side are
drawn tile by tile (the shaders see the whole frame through ``u_resolution`` and the tile's
place through ``u_tile_offset``), so their size is bounded by memory only.
"""

from __future__ import annotations

import numpy as np

from skydome.errors import ParameterError, check_integer

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


#: The most rays a side of a pixel a supersampled frame draws (16 a pixel).
MAX_SUPERSAMPLE = 4


def check_supersample(supersample) -> int:
    """Validate a supersampling factor (rays per pixel side, 1 = none); returns it."""
    return check_integer("supersample", supersample, 1, MAX_SUPERSAMPLE, "rays per pixel side")


def block_mean(image: np.ndarray, n: int) -> np.ndarray:
    """An (H n, W n, ...) image reduced to (H, W, ...) by the mean of each n x n block (a box
    filter: what a pixel of n x n sensor sites measures; radiance averages, so a point
    source's flux is kept), in float64, returned as the input's dtype."""
    if n == 1:
        return image
    h, w = image.shape[0] // n, image.shape[1] // n
    blocks = image.reshape(h, n, w, n, *image.shape[2:])
    return blocks.mean(axis=(1, 3), dtype=np.float64).astype(image.dtype)


def repeat_pixels(image: np.ndarray, n: int) -> np.ndarray:
    """An (H, W, ...) per-pixel input made (H n, W n, ...): each value for its n x n rays."""
    if n == 1:
        return image
    return np.repeat(np.repeat(image, n, axis=0), n, axis=1)
