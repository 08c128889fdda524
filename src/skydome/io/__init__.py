"""Output files: EXR and Radiance HDR (absolute units), PNG and JPEG (tone-mapped sRGB), NPY;
validated up front and written atomically.

Typical use::

    paths = [check_output_path(p) for p in user_paths]      # before rendering
    ...
    write_outputs(paths, frame.data, ldr, metadata=frame.info)
"""

from skydome.io.atomic import atomic_write
from skydome.io.exr import SCOTOPIC_CHANNEL, read_exr, write_exr
from skydome.io.hdr import RADIANCE_EFFICACY_LM_PER_W, read_hdr, write_hdr
from skydome.io.jpeg import write_jpeg
from skydome.io.outputs import (
    SUPPORTED_EXTENSIONS,
    WRITERS,
    Writer,
    check_output_path,
    write_npy,
    write_outputs,
)
from skydome.io.png import PNG_SETTINGS_KEY, write_png

__all__ = [
    "PNG_SETTINGS_KEY",
    "RADIANCE_EFFICACY_LM_PER_W",
    "SCOTOPIC_CHANNEL",
    "SUPPORTED_EXTENSIONS",
    "WRITERS",
    "Writer",
    "atomic_write",
    "check_output_path",
    "read_exr",
    "read_hdr",
    "write_exr",
    "write_hdr",
    "write_jpeg",
    "write_npy",
    "write_outputs",
    "write_png",
]
