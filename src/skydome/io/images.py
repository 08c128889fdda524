"""Opening a user's image file safely (a weather map given with ``--weather-map``, ...).

A file named on a command line may be anything: a FIFO or a device that blocks or never
ends, a directory, a text file, a truncated download, or a "decompression bomb" (a small
file whose header claims a huge image, to make the reader allocate gigabytes). Every image
skydome decodes for a user goes through :func:`read_user_image`, which refuses all of these
with one-line :class:`~skydome.errors.ParameterError` messages before decoding anything big:

1. the path is looked at (``stat``) and must be a regular file (or a link to one) of at
   most ``max_bytes``; it is opened without blocking and checked again on the open file
   (``fstat``), so a file swapped for a FIFO in between is refused too;
2. Pillow reads only the header (``Image.open`` is lazy): the format must be one of
   ``formats`` and the size within ``max_side`` and ``max_pixels``;
3. only then are the pixels decoded (``load``); a truncated or damaged file is an error,
   never a partial image.

Pillow's own decompression-bomb guard (``Image.MAX_IMAGE_PIXELS``, 89 megapixels: a
warning, an error above twice that) fires on open, before step 2; its error is reported
like ours and its warning is left to our smaller budget.
"""

from __future__ import annotations

import contextlib
import os
import re
import stat
import warnings
from pathlib import Path

from skydome.errors import ParameterError


def describe_mode(mode: int) -> str:
    """What a ``st_mode`` that is not a regular file is, in words: "a directory", "a FIFO
    (named pipe)", "a device", "a socket"."""
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "a special file"  # pragma: no cover


def _format_list(formats: tuple[str, ...]) -> str:
    return formats[0] if len(formats) == 1 else ", ".join(formats[:-1]) + " or " + formats[-1]


def read_user_image(
    path: str | os.PathLike,
    *,
    what: str,
    max_pixels: int,
    max_bytes: int,
    max_side: int | None = None,
    formats: tuple[str, ...] = ("PNG", "JPEG", "TIFF"),
):
    """Open and decode the image file ``path`` with the checks of the module docstring.

    Args:
        path: the file, as the user gave it.
        what: what the file is for, in words, for the messages (e.g. "weather map image").
        max_pixels: the most pixels (width x height) decoded.
        max_bytes: the largest file read, bytes.
        max_side: the longest side accepted, pixels (None: any within ``max_pixels``).
        formats: Pillow format names accepted, e.g. ("PNG", "JPEG", "TIFF").
    Returns: a loaded ``PIL.Image.Image`` (the file is closed).
    Raises: ParameterError, one line naming the file, what is wrong and what is expected.
    """
    from PIL import Image, UnidentifiedImageError

    try:
        p = Path(os.fspath(path)).expanduser()
    except TypeError:
        raise ParameterError(f"{what} must be a file path, got {path!r}") from None
    shown = repr(str(path))
    expected = f"a {_format_list(formats)} image"

    def refuse(reason: str) -> ParameterError:
        return ParameterError(f"cannot read {what} {shown}: {reason}")

    try:
        st = os.stat(p)
    except FileNotFoundError:
        raise ParameterError(f"{what} not found: {shown}") from None
    except OSError as exc:
        raise refuse(exc.strerror or str(exc)) from None
    if not stat.S_ISREG(st.st_mode):
        raise refuse(f"it is {describe_mode(st.st_mode)}, not {expected} file")
    if st.st_size > max_bytes:
        raise refuse(
            f"the file has {st.st_size / 2**20:.0f} MiB; at most {max_bytes / 2**20:.0f} MiB "
            f"is read for {expected} of at most {_budget(max_pixels, max_side)}"
        )
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
    try:
        fd = os.open(p, flags | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0))
    except OSError as exc:
        raise refuse(exc.strerror or str(exc)) from None
    with os.fdopen(fd, "rb") as f:
        st = os.fstat(f.fileno())  # the file opened, whatever the path names now
        if not stat.S_ISREG(st.st_mode) or st.st_size > max_bytes:
            raise refuse(f"it changed while being opened; give {expected} file")
        with warnings.catch_warnings():
            # Pillow's warning above 89 megapixels: our budget below is the smaller one.
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            try:
                img = Image.open(f, formats=list(formats))
            except Image.DecompressionBombError as exc:
                claimed = re.search(r"\((\d+) pixels\)", str(exc))
                size = f"{int(claimed[1]):,} pixels" if claimed else "a huge size"
                raise refuse(
                    f"its header claims {size} (a decompression bomb?); at most "
                    f"{_budget(max_pixels, max_side)} are read"
                ) from None
            except UnidentifiedImageError:
                raise refuse(f"not {expected} (unknown or damaged header)") from None
            except (OSError, ValueError, SyntaxError) as exc:
                raise refuse(f"not {expected} ({_first_line(exc)})") from None
        w, h = img.size
        if w * h > max_pixels or (max_side is not None and max(w, h) > max_side):
            img.close()
            raise refuse(f"it is {w}x{h} pixels; at most {_budget(max_pixels, max_side)}")
        if w < 1 or h < 1:
            img.close()
            raise refuse(f"it is {w}x{h} pixels, an empty image")
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # e.g. TIFF tag warnings: the pixels decide
                img.load()
        except Exception as exc:  # truncated ("image file is truncated"), broken stream...
            with contextlib.suppress(Exception):
                img.close()
            raise refuse(
                f"{img.format or 'image'} data is truncated or damaged ({_first_line(exc)})"
            ) from None
    return img


def _budget(max_pixels: int, max_side: int | None) -> str:
    """The size budget in words, e.g. "4096x4096 pixels" or "16,777,216 pixels"."""
    if max_side is not None and max_side * max_side == max_pixels:
        return f"{max_side}x{max_side} pixels"
    side = f" and {max_side} pixels a side" if max_side is not None else ""
    return f"{max_pixels:,} pixels{side}"


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__
