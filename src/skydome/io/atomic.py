"""Atomic file writes: a temporary file in the target's directory, then ``os.replace``.

Readers never see a partial file: the target either keeps its old content or gets the
complete new one; on any failure the temporary file is removed.
"""

from __future__ import annotations

import contextlib
import os
import secrets
from collections.abc import Callable
from pathlib import Path

from skydome.errors import OutputError, SkydomeError


def create_temp_beside(path: Path) -> Path:
    """Create an empty, uniquely named hidden file in ``path``'s directory and return it.

    Named ``.<name>.<random>.tmp<suffix>`` (the suffix is kept for libraries that look at
    it); created with O_EXCL and mode 0o666 minus the umask, like an ordinary new file.
    Raises OSError if the directory is not writable.
    """
    path = Path(path)
    for _ in range(100):
        tmp = path.with_name(f".{path.stem}.{secrets.token_hex(4)}.tmp{path.suffix}")
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:
            continue
        os.close(fd)
        return tmp
    raise FileExistsError(f"no free temporary name beside {path}")  # pragma: no cover


def _fsync(path: Path) -> None:
    with open(path, "rb") as f:
        os.fsync(f.fileno())


def atomic_write(path: str | os.PathLike, write: Callable[[Path], None]) -> Path:
    """Call ``write(tmp)`` to fill a temporary file beside ``path``, then move it to ``path``.

    On failure the temporary file is deleted and the error is raised as OutputError (one
    line naming the path; the original exception is chained), except SkydomeErrors, which
    pass through unchanged. Returns ``path`` as a Path.
    """
    path = Path(path)
    try:
        tmp = create_temp_beside(path)
    except OSError as exc:
        raise OutputError(f"cannot write {str(path)!r}: {exc.strerror or exc}") from exc
    try:
        write(tmp)
        _fsync(tmp)
        os.replace(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if isinstance(exc, SkydomeError) or not isinstance(exc, Exception):
            raise
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else exc
        raise OutputError(f"cannot write {str(path)!r}: {type(exc).__name__}: {reason}") from exc
    return path
