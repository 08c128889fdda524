"""Output files: EXR (absolute units), PNG (tone-mapped sRGB), NPY; validated up front and
written atomically.

Typical use::

    paths = [check_output_path(p) for p in user_paths]      # before rendering
    ...
    write_outputs(paths, frame.data, ldr, metadata=frame.info)
"""

from skydome.io.atomic import atomic_write
from skydome.io.exr import SCOTOPIC_CHANNEL, read_exr, write_exr
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
    "SCOTOPIC_CHANNEL",
    "SUPPORTED_EXTENSIONS",
    "WRITERS",
    "Writer",
    "atomic_write",
    "check_output_path",
    "read_exr",
    "write_exr",
    "write_npy",
    "write_outputs",
    "write_png",
]
