"""Atomic file writes: a temporary file in the target's directory, then ``os.replace``.

Readers never see a partial file: the target either keeps its old content or gets the
complete new one; on any failure, KeyboardInterrupt included, the temporary file is removed.

Only a process killed outright (SIGKILL, a power cut) leaves its temporary file behind. The
name says whose it is, ``.<stem>.skydome-<pid>-<random>.tmp<suffix>`` (hidden; the suffix is
kept for libraries that choose a format by it), so the next run that checks an output in
that folder removes it with :func:`remove_stale_temps` once it is stale: the process that
wrote it is gone, or it has not changed for :data:`STALE_AFTER_S`.
"""

from __future__ import annotations

import contextlib
import os
import re
import secrets
import stat
import time
from collections.abc import Callable
from pathlib import Path

from skydome.errors import OutputError, SkydomeError

#: A temporary file whose writer still runs (by its PID) is stale after this long without a
#: change, s: the PID may have been reused by another program, or the file may come from
#: another machine sharing the folder. Not a minute: a live time-lapse's MP4 is not
#: written to while x264 fills its look-ahead, which takes minutes at seconds per frame.
STALE_AFTER_S = 24 * 3600.0

#: The names of skydome's temporary files; group "pid" is the writer's process id.
TEMP_NAME = re.compile(r"^\..*\.skydome-(?P<pid>\d+)-[0-9a-f]{8}\.tmp(\.[^./]*)?$")


def temp_name(path: Path) -> str:
    """A fresh temporary file name for ``path`` (see the module docstring)."""
    return f".{path.stem}.skydome-{os.getpid()}-{secrets.token_hex(4)}.tmp{path.suffix}"


def create_temp_beside(path: str | os.PathLike) -> Path:
    """Create an empty, uniquely named hidden file in ``path``'s directory and return it.

    Named by :func:`temp_name`; created with O_EXCL and mode 0o666 minus the umask, like an
    ordinary new file. Raises OSError if the directory is not writable.
    """
    path = Path(path)
    for _ in range(100):
        tmp = path.with_name(temp_name(path))
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:  # pragma: no cover - 32 random bits
            continue
        os.close(fd)
        return tmp
    raise FileExistsError(f"no free temporary name beside {path}")  # pragma: no cover


def probe_writable(directory: str | os.PathLike) -> None:
    """Create and remove a temporary file in ``directory`` (a real probe: read-only file
    systems and permissions are both caught, also for root). Raises OSError if it cannot."""
    probe = create_temp_beside(Path(directory) / "probe")
    with contextlib.suppress(OSError):
        os.unlink(probe)


def _pid_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):  # another user's process, or no way to tell
        return True
    return True


def is_stale_temp(path: str | os.PathLike, *, now: float | None = None) -> bool:
    """Whether ``path`` is a temporary file of skydome's that nobody will finish: named like
    one, a regular file of this user (not a link), and its writer's process is gone or it
    has not changed for :data:`STALE_AFTER_S` seconds."""
    p = Path(path)
    m = TEMP_NAME.match(p.name)
    if m is None:
        return False
    try:
        st = os.lstat(p)
    except OSError:
        return False
    if not stat.S_ISREG(st.st_mode) or (hasattr(os, "getuid") and st.st_uid != os.getuid()):
        return False
    age = (time.time() if now is None else now) - st.st_mtime
    return age > STALE_AFTER_S or not _pid_alive(int(m["pid"]))


def remove_stale_temps(
    directory: str | os.PathLike, suffix: str | None = None, max_age_s: float | None = None
) -> list[Path]:
    """Remove the stale temporary files (:func:`is_stale_temp`; with ``max_age_s``, also
    those unchanged for that long) that interrupted runs left in ``directory``, of the
    target suffix ``suffix`` (e.g. ``".lut"``; None: any); return their paths. A missing or
    unreadable directory removes nothing."""
    removed = []
    try:
        entries = [e.path for e in os.scandir(directory) if TEMP_NAME.match(e.name)]
    except OSError:
        return removed
    now = time.time()
    for entry in entries:
        if suffix is not None and not entry.endswith(".tmp" + suffix):
            continue
        stale = is_stale_temp(entry, now=now)
        if not stale and max_age_s is not None:
            with contextlib.suppress(OSError):
                stale = now - os.stat(entry, follow_symlinks=False).st_mtime > max_age_s
        if stale:
            with contextlib.suppress(OSError):
                os.unlink(entry)
                removed.append(Path(entry))
    return removed


def _fsync(path: Path) -> None:
    with open(path, "rb") as f:
        os.fsync(f.fileno())


def atomic_write(path: str | os.PathLike, write: Callable[[Path], None]) -> Path:
    """Call ``write(tmp)`` to fill a temporary file beside ``path``, then move it to ``path``.

    On failure the temporary file is deleted and the error is raised as OutputError (one
    line naming the path; the original exception is chained), except SkydomeErrors and
    KeyboardInterrupt, which pass through unchanged. Returns ``path`` as a Path.
    """
    path = Path(path)
    tmp = None
    try:
        tmp = create_temp_beside(path)
        write(tmp)
        _fsync(tmp)
        os.replace(tmp, path)
    except BaseException as exc:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        if isinstance(exc, SkydomeError) or not isinstance(exc, Exception):
            raise
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else exc
        if tmp is None:
            raise OutputError(f"cannot write {str(path)!r}: {reason}") from exc
        raise OutputError(f"cannot write {str(path)!r}: {type(exc).__name__}: {reason}") from exc
    return path
