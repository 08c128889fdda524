"""Screenshots: the window's pixels to PNG/JPEG, the same frame in cd/m^2 to EXR/HDR/NPY.

The 8-bit image is read from the framebuffer the frame was drawn into (before the panel
is drawn over it), so a PNG holds exactly what the sky looks like on screen; an HDR format
gets the frame of the same state (camera, time, exposure) rendered again in absolute units
(``ViewerScene.render``), since the screen holds only 8-bit values.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from skydome.display.gpu_tonemap import read_rgb8
from skydome.io import WRITERS, check_output_path, write_outputs


def read_screen(framebuffer, size: tuple[int, int]) -> np.ndarray:
    """The RGB pixels of ``framebuffer`` over (0, 0, w, h) as uint8 (h, w, 3), top row
    first."""

    w, h = size
    pixels = read_rgb8(framebuffer, w, h)
    if framebuffer.glo == 0:
        # moderngl selects GL_COLOR_ATTACHMENT0 as the read buffer, which the default
        # framebuffer lacks: GL flags GL_INVALID_OPERATION, reads its back buffer all the
        # same (checked against a clear colour). Take the flag so it is not reported as a
        # failing context.
        framebuffer.ctx.error  # noqa: B018
    return pixels


def wants_hdr(paths) -> bool:
    """Whether any of ``paths`` is an HDR format (.exr, .hdr, .npy)."""

    return any(WRITERS[Path(p).suffix.lower()].hdr for p in paths)


def save(paths, image: np.ndarray, scene=None, *, metadata: dict | None = None) -> list[Path]:
    """Write ``image`` (the screen's uint8 pixels) to the 8-bit paths, and the frame of
    ``scene``'s state at the image's size (cd/m^2) to the HDR ones; atomically, each
    format by its extension. Returns the written paths."""

    checked = [check_output_path(p) for p in paths]
    data = None
    info = dict(metadata or {})
    if wants_hdr(checked):
        if scene is None:
            raise ValueError("an HDR screenshot needs the scene to render the frame in cd/m^2")
        h, w = image.shape[:2]
        frame = scene.render(w, h, tonemap=False)
        data = frame.data
        info.update(frame.info)
    return write_outputs(checked, data, image, metadata=info)
