"""8-bit sRGB JPEG images (already tone mapped), with the render settings in a comment."""

from __future__ import annotations

import os
from collections.abc import Mapping

import numpy as np

from skydome.io.exr import package_version, settings_json
from skydome.io.png import check_ldr_image

#: JPEG quality (Pillow's 1..95 scale; 95 is its highest recommended setting).
JPEG_QUALITY = 95
#: EXIF tag number of ``Software`` (EXIF 2.32 / TIFF 6.0, tag 0x0131).
EXIF_SOFTWARE_TAG = 0x0131


def write_jpeg(
    path: str | os.PathLike, image: np.ndarray, metadata: Mapping[str, object] | None = None
) -> None:
    """Write a tone-mapped uint8 (H, W, 3) sRGB image (row 0 at the top) as a baseline JPEG
    (not atomically; see ``skydome.io.write_outputs``).

    Quality :data:`JPEG_QUALITY`, no chroma subsampling (4:4:4: skies are smooth colour
    gradients, and 4:2:0 smears the coloured horizon band); EXIF ``Software`` names skydome
    and, when ``metadata`` is given, the COM segment holds the settings as JSON. An untagged
    JPEG is read as sRGB by convention, which the pixels are.
    """
    from PIL import Image

    a = check_ldr_image(image)
    exif = Image.Exif()
    exif[EXIF_SOFTWARE_TAG] = f"skydome {package_version()}"
    options = {"quality": JPEG_QUALITY, "subsampling": 0, "exif": exif.tobytes()}
    if metadata:
        options["comment"] = settings_json(metadata)
    Image.fromarray(a).save(path, format="JPEG", **options)
