"""Atomic file writes: a temporary file in the target's directory, then ``os.replace``.

Readers never see a partial file: the target either keeps its old content or gets the
complete new one; on any failure the temporary file is removed. A writer killed before it
could remove it leaves ``.<name>.<pid>.<random>.tmp<suffix>``, which
:func:`remove_stale_temps` recognises and removes once its writer is gone.
"""

from __future__ import annotations

import contextlib
import os
import re
import secrets
import time
from collections.abc import Callable
from pathlib import Path

from skydome.errors import OutputError, SkydomeError


def create_temp_beside(path: Path) -> Path:
    """Create an empty, uniquely named hidden file in ``path``'s directory and return it.

    Named ``.<name>.<pid>.<random>.tmp<suffix>`` (the writer's process id, for
    :func:`remove_stale_temps`; the suffix is kept for libraries that look at it); created
    with O_EXCL and mode 0o666 minus the umask, like an ordinary new file. Raises OSError if
    the directory is not writable.
    """
    path = Path(path)
    for _ in range(100):
        tmp = path.with_name(f".{path.stem}.{os.getpid()}.{secrets.token_hex(4)}.tmp{path.suffix}")
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:
            continue
        os.close(fd)
        return tmp
    raise FileExistsError(f"no free temporary name beside {path}")  # pragma: no cover


_TEMP_NAME = re.compile(r"\..+\.(?P<pid>[0-9]+)\.[0-9a-f]{8}\.tmp(?P<suffix>.*)")


def _alive(pid: int) -> bool:
    """Whether process ``pid`` exists on this machine (assumed so where that cannot be asked)."""
    if os.name == "nt":  # os.kill there terminates the process: rely on the age alone
        return True
    try:
        os.kill(pid, 0)
    except (ProcessLookupError, OverflowError):  # gone, or a number no process can have
        return False
    except OSError:  # exists, owned by someone else
        return True
    return True


def remove_stale_temps(directory: str | os.PathLike, suffix: str, max_age_s: float = 60.0) -> int:
    """Remove the temporary files of :func:`create_temp_beside` in ``directory`` (with target
    suffix ``suffix``) left by writers that died: whose process no longer exists, or that
    nobody has modified for ``max_age_s`` seconds (a writer writes continuously, so an older
    one is stuck or its process id was reused). Returns how many were removed; errors
    (a file already gone, a read-only directory) are ignored."""
    removed, now = 0, time.time()
    try:
        entries = list(os.scandir(directory))
    except OSError:
        return 0
    for entry in entries:
        m = _TEMP_NAME.fullmatch(entry.name)
        if m is None or m["suffix"] != suffix:
            continue
        try:
            age = now - entry.stat(follow_symlinks=False).st_mtime
            if age > max_age_s or not _alive(int(m["pid"])):
                os.unlink(entry.path)
                removed += 1
        except OSError:
            pass
    return removed


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
