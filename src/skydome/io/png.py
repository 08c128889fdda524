"""8-bit sRGB PNG images (already tone mapped), with the render settings in tEXt chunks."""

from __future__ import annotations

import os
from collections.abc import Mapping

import numpy as np

from skydome.errors import ParameterError
from skydome.io.exr import package_version, settings_json

#: tEXt keyword that holds the render settings as JSON.
PNG_SETTINGS_KEY = "skydome"


def check_ldr_image(image: np.ndarray) -> np.ndarray:
    """A uint8 image (H, W, 3) as a C-contiguous array, or ParameterError."""
    a = np.asarray(image)
    if a.ndim != 3 or a.shape[-1] != 3 or 0 in a.shape or a.dtype != np.uint8:
        raise ParameterError(
            f"LDR image must be a non-empty uint8 (H, W, 3) array, got shape {a.shape} "
            f"dtype {a.dtype}"
        )
    return np.ascontiguousarray(a)


def write_png(
    path: str | os.PathLike, image: np.ndarray, metadata: Mapping[str, object] | None = None
) -> None:
    """Write a tone-mapped uint8 (H, W, 3) sRGB image (row 0 at the top) as PNG (not
    atomically; see ``skydome.io.write_outputs``).

    Chunks: sRGB (rendering intent perceptual), tEXt ``Software`` and, when ``metadata`` is
    given, tEXt ``skydome`` with the settings as JSON.
    """
    from PIL import Image
    from PIL.PngImagePlugin import PngInfo

    a = check_ldr_image(image)
    info = PngInfo()
    info.add(b"sRGB", b"\x00")  # the pixels are sRGB-encoded (PNG spec 11.3.3.5)
    info.add_text("Software", f"skydome {package_version()}")
    if metadata:
        info.add_text(PNG_SETTINGS_KEY, settings_json(metadata))
    Image.fromarray(a).save(path, format="PNG", pnginfo=info, compress_level=6)
