"""Output files chosen by extension, validated up front and written atomically.

============ ================================================================ ============
extension    content                                                          input
============ ================================================================ ============
``.exr``     float32 R, G, B (cd/m^2) + Y_scotopic, absolute-unit header      HDR frame
``.hdr``     Radiance RGBE, linear R, G, B in cd/m^2 / 179 (Radiance units)   HDR frame
``.npy``     the float32 frame (H, W, 4) as is (``np.load`` reads it)          HDR frame
``.png``     8-bit sRGB, tone mapped, settings in a tEXt chunk                LDR image
``.jpg``     8-bit sRGB JPEG (also ``.jpeg``), tone mapped, quality 95,       LDR image
             settings in the COM segment
============ ================================================================ ============
"""

from __future__ import annotations

import os
import stat
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from skydome.errors import OutputError, ParameterError
from skydome.io.atomic import atomic_write, probe_writable, remove_stale_temps
from skydome.io.exr import check_hdr_frame, write_exr
from skydome.io.hdr import write_hdr
from skydome.io.images import describe_mode
from skydome.io.jpeg import write_jpeg
from skydome.io.png import check_ldr_image, write_png


def write_npy(
    path: str | os.PathLike, frame: np.ndarray, metadata: Mapping[str, object] | None = None
) -> None:
    """Write the float32 frame (H, W, 4) as a .npy file (not atomically; metadata unused)."""
    a = check_hdr_frame(frame)
    with open(path, "wb") as f:
        np.save(f, a, allow_pickle=False)


@dataclass(frozen=True)
class Writer:
    """How one extension is written: the function and whether it takes the HDR frame
    (``hdr=True``) or the tone-mapped uint8 image."""

    extension: str
    write: Callable[..., None]
    hdr: bool
    description: str


#: Writers by lower-case extension.
WRITERS: dict[str, Writer] = {
    ".exr": Writer(".exr", write_exr, True, "OpenEXR float32, absolute units"),
    ".png": Writer(".png", write_png, False, "8-bit sRGB PNG, tone mapped"),
    ".npy": Writer(".npy", write_npy, True, "NumPy float32 frame"),
    ".hdr": Writer(".hdr", write_hdr, True, "Radiance RGBE, cd/m^2 / 179"),
    ".jpg": Writer(".jpg", write_jpeg, False, "8-bit sRGB JPEG, tone mapped"),
    ".jpeg": Writer(".jpeg", write_jpeg, False, "8-bit sRGB JPEG, tone mapped"),
}
SUPPORTED_EXTENSIONS = tuple(sorted(WRITERS))


def check_output_path(path: str | os.PathLike, extensions: Iterable[str] | None = None) -> Path:
    """Validate an output path before rendering; return it as a Path.

    Checks: the extension is one of ``extensions`` (lower case, with the dot; by default
    :data:`SUPPORTED_EXTENSIONS`), in any case; the path is not a directory, FIFO, device
    or socket (an existing regular file is replaced); its parent directory exists and a file
    can be created in it (a real probe, so read-only file systems and permissions are both
    caught, also for root). Raises OutputError with one line naming the path and the
    problem. Stale temporary files of interrupted runs in that directory are removed
    (:func:`skydome.io.atomic.remove_stale_temps`); nothing else is touched.
    """
    try:
        p = Path(os.fspath(path)).expanduser()
    except TypeError:
        raise OutputError(f"output path must be a string or path, got {path!r}") from None
    shown = str(path)
    valid = tuple(extensions) if extensions is not None else SUPPORTED_EXTENSIONS
    ext = p.suffix.lower()
    if ext not in valid:
        got = f"extension {ext!r}" if ext else "no extension"
        raise OutputError(f"cannot write {shown!r}: {got} (valid: {', '.join(valid)})")
    parent = p.parent
    if not parent.exists():
        raise OutputError(f"cannot write {shown!r}: directory {str(parent)!r} does not exist")
    if not parent.is_dir():
        raise OutputError(f"cannot write {shown!r}: {str(parent)!r} is not a directory")
    kind = file_kind(p)
    if kind not in (None, "file"):
        raise OutputError(f"cannot write {shown!r}: it is {kind}, not a regular file")
    try:
        probe_writable(parent)
    except OSError as exc:
        raise OutputError(
            f"cannot write {shown!r}: directory {str(parent)!r} is not writable "
            f"({exc.strerror or exc})"
        ) from None
    remove_stale_temps(parent)
    return p


def file_kind(path: str | os.PathLike) -> str | None:
    """What ``path`` is, in words: None if nothing is there (or it cannot be looked at: the
    write will say why), "file" for a regular file or a link to one, else "a directory",
    "a FIFO (named pipe)", "a device" or "a socket"."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return None
    return "file" if stat.S_ISREG(mode) else describe_mode(mode)


def write_outputs(
    paths: str | os.PathLike | Iterable[str | os.PathLike],
    frame: np.ndarray | None,
    ldr: np.ndarray | None = None,
    *,
    metadata: Mapping[str, object] | None = None,
) -> list[Path]:
    """Write one frame to every path, each format chosen by its extension, atomically.

    All paths and the inputs they need are checked before anything is written. Each file is
    written to a temporary file in its own directory and moved into place with
    ``os.replace``, so no partial file is ever left; on failure the temporary file is
    removed and OutputError is raised.

    Args:
        paths: one path or several (``.exr``, ``.hdr``, ``.npy``, ``.png``, ``.jpg``).
        frame: float32 (H, W, 4) frame in cd/m^2 (row 0 at the top), for .exr, .hdr, .npy.
        ldr: tone-mapped uint8 (H, W, 3) sRGB image, for .png and .jpg.
        metadata: render settings stored as JSON in EXR and HDR headers, PNG tEXt chunks
            and JPEG comments.
    Returns: the written paths.
    """
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    checked = [check_output_path(p) for p in paths]
    writers = [WRITERS[p.suffix.lower()] for p in checked]
    needs_hdr = [str(p) for p, w in zip(checked, writers, strict=True) if w.hdr]
    needs_ldr = [str(p) for p, w in zip(checked, writers, strict=True) if not w.hdr]
    if needs_hdr and frame is None:
        raise ParameterError(f"an HDR frame is needed to write {needs_hdr[0]!r}")
    if needs_ldr and ldr is None:
        raise ParameterError(f"a tone-mapped image is needed to write {needs_ldr[0]!r}")
    hdr = check_hdr_frame(frame) if needs_hdr else None
    image = check_ldr_image(ldr) if needs_ldr else None
    for p, w in zip(checked, writers, strict=True):
        data = hdr if w.hdr else image

        def write(tmp: Path, w: Writer = w, data: np.ndarray = data) -> None:
            w.write(tmp, data, metadata)

        atomic_write(p, write)
    return checked
