"""The lookup-table file format: named arrays plus a JSON header, checksummed, no pickle.

Layout (format version 2)::

    b"SKYDOMELUT\\x00\\x02"     magic and format version (12 bytes)
    uint64 little-endian       length H of the JSON header in bytes (at most 1 MiB)
    JSON header (H bytes)      {"key", "meta", "arrays": [{name, dtype, shape, offset,
                                nbytes}]}; offsets count from the payload's start
    payload                    the arrays' bytes, little-endian, C order, one after the other
    SHA-256 (32 bytes)         of every byte before it: magic, length, header and payload

Reading never trusts a byte it has not checked: only a regular file is opened (no link,
FIFO, device or directory: those could hang or never end), at most its size is read, the
checksum is verified before the header is parsed, and every entry's dtype, shape, offset and
size must tile the payload exactly. Any fault raises CacheError, so a truncated, corrupted
or foreign file is never turned into arrays.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
import struct
from pathlib import Path

import numpy as np

from skydome.errors import CacheError, ParameterError
from skydome.io.atomic import atomic_write

#: Bump with any change of the layout above (it is part of the cache keys too).
FORMAT_VERSION = 2
MAGIC = b"SKYDOMELUT\x00" + bytes([FORMAT_VERSION])
_PREFIX = len(MAGIC) + 8  # magic + header length
_DIGEST = 32  # SHA-256 trailer
#: Bounds: a header holds a few names and numbers; the largest tables are a few hundred MiB.
MAX_HEADER_BYTES = 1 << 20
MAX_FILE_BYTES = 1 << 33
_ALLOWED_DTYPES = {"float32", "float16", "float64", "int32", "uint16", "uint8"}


def write_lut_file(
    path: str | os.PathLike, key: str, arrays: dict[str, np.ndarray], meta: dict | None = None
) -> Path:
    """Write ``arrays`` atomically to ``path`` with the cache ``key`` and JSON-able ``meta``."""
    entries, blobs, offset = [], [], 0
    for name, a in arrays.items():
        a = np.ascontiguousarray(a)
        if a.dtype.name not in _ALLOWED_DTYPES:
            raise ParameterError(
                f"array {name!r} has dtype {a.dtype}; a LUT file holds "
                f"{', '.join(sorted(_ALLOWED_DTYPES))}"
            )
        blob = a.astype(a.dtype.newbyteorder("<"), copy=False).tobytes()
        entries.append(
            {
                "name": name,
                "dtype": a.dtype.name,
                "shape": list(a.shape),
                "offset": offset,
                "nbytes": len(blob),
            }
        )
        blobs.append(blob)
        offset += len(blob)
    header = json.dumps({"key": key, "meta": meta or {}, "arrays": entries}).encode()
    if len(header) > MAX_HEADER_BYTES:
        raise ValueError(f"LUT header of {len(header)} bytes exceeds {MAX_HEADER_BYTES}")

    def write(tmp: Path) -> None:
        digest = hashlib.sha256()
        with open(tmp, "wb") as f:
            for part in (MAGIC, struct.pack("<Q", len(header)), header, *blobs):
                digest.update(part)
                f.write(part)
            f.write(digest.digest())

    return atomic_write(path, write)


def _kind(mode: int) -> str:
    for test, name in (
        (stat.S_ISLNK, "a symbolic link"),
        (stat.S_ISDIR, "a directory"),
        (stat.S_ISFIFO, "a FIFO"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return name
    return "not a regular file"


def _read_regular(path: Path) -> bytearray:
    """All bytes of the regular file ``path``, read through one descriptor; CacheError for
    anything else (a link, even to a regular file: the cache writes none) or a size out of
    bounds. Never blocks on a FIFO and never reads more than the size it stat'ed."""
    try:
        before = os.lstat(path)
        if not stat.S_ISREG(before.st_mode):
            raise CacheError(f"{path} is {_kind(before.st_mode)}, not a table file")
        if not _PREFIX + _DIGEST <= before.st_size <= MAX_FILE_BYTES:
            raise CacheError(f"{path} has an impossible size ({before.st_size} bytes)")
        flags = os.O_RDONLY | getattr(os, "O_BINARY", 0) | getattr(os, "O_CLOEXEC", 0)
        # No link followed, no wait for a writer if a FIFO was swapped in since lstat.
        flags |= getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
        fd = os.open(path, flags)
        with open(fd, "rb", buffering=0) as f:
            st = os.fstat(fd)
            if not stat.S_ISREG(st.st_mode) or (st.st_dev, st.st_ino) != (
                before.st_dev,
                before.st_ino,
            ):
                raise CacheError(f"{path} was replaced while being opened")
            data = bytearray(st.st_size)
            view, done = memoryview(data), 0
            while done < len(data):
                n = f.readinto(view[done:])
                if not n:
                    raise CacheError(f"{path} is shorter than its size ({done} of {len(data)})")
                done += n
    except OSError as exc:
        raise CacheError(f"cannot read {path}: {exc.strerror or exc}") from None
    if len(data) != before.st_size:
        raise CacheError(f"{path} changed size while being read")
    return data


def _int(value, what: str, path: Path) -> int:
    if type(value) is not int or value < 0:
        raise CacheError(f"{path}: {what} is {value!r}, not a non-negative integer")
    return value


def read_lut_file(
    path: str | os.PathLike, key: str | None = None
) -> tuple[dict[str, np.ndarray], dict]:
    """Read and validate a LUT file; returns (arrays, meta). Raises CacheError if invalid.

    With ``key`` given, a file made for another key is rejected too.
    """
    path = Path(path)
    data = _read_regular(path)
    if data[: len(MAGIC) - 1] != MAGIC[:-1]:
        raise CacheError(f"{path} is not a skydome LUT file (bad magic)")
    if data[len(MAGIC) - 1] != FORMAT_VERSION:
        raise CacheError(
            f"{path} has LUT format version {data[len(MAGIC) - 1]}, expected {FORMAT_VERSION}"
        )
    (hlen,) = struct.unpack_from("<Q", data, len(MAGIC))
    if hlen > MAX_HEADER_BYTES or _PREFIX + hlen + _DIGEST > len(data):
        raise CacheError(f"{path} is truncated or corrupt (header length {hlen})")
    body = memoryview(data)[: len(data) - _DIGEST]
    if hashlib.sha256(body).digest() != data[len(data) - _DIGEST :]:
        raise CacheError(f"{path} is corrupt or truncated (checksum mismatch)")
    # The checksum held: what follows catches a writer's bug, not damage on disk.
    try:
        header = json.loads(bytes(body[_PREFIX : _PREFIX + hlen]).decode())
        entries, meta = header["arrays"], header.get("meta", {})
        if not isinstance(entries, list) or not isinstance(meta, dict):
            raise TypeError("arrays is not a list or meta not an object")
    except (ValueError, KeyError, TypeError) as exc:
        raise CacheError(f"{path} has a corrupt header ({exc})") from None
    if key is not None and header.get("key") != key:
        raise CacheError(f"{path} was made for other parameters (key mismatch)")
    start, payload = _PREFIX + hlen, len(body) - _PREFIX - hlen
    arrays, expected_offset = {}, 0
    for e in entries:
        if not isinstance(e, dict) or not isinstance(e.get("name"), str):
            raise CacheError(f"{path}: an array entry has no name")
        name, dtype, shape = e["name"], e.get("dtype"), e.get("shape")
        if dtype not in _ALLOWED_DTYPES:
            raise CacheError(f"{path}: array {name!r} has unsupported dtype {dtype!r}")
        if not isinstance(shape, list) or len(shape) > 8:
            raise CacheError(f"{path}: array {name!r} has a bad shape {shape!r}")
        shape = [_int(s, f"a dimension of {name!r}", path) for s in shape]
        offset = _int(e.get("offset"), f"the offset of {name!r}", path)
        nbytes = _int(e.get("nbytes"), f"the size of {name!r}", path)
        dt = np.dtype(dtype).newbyteorder("<")
        count = int(np.prod(shape, dtype=object))
        # The arrays tile the payload in order: no gap, no overlap, nothing past its end.
        if offset != expected_offset or nbytes != count * dt.itemsize or offset + nbytes > payload:
            raise CacheError(
                f"{path}: array {name!r} ({dtype}, {shape}) does not fit at payload bytes "
                f"{offset}-{offset + nbytes} of {payload}"
            )
        a = np.frombuffer(data, dtype=dt, count=count, offset=start + offset)
        arrays[name] = a.reshape(shape).astype(dt.newbyteorder("="), copy=False)
        expected_offset += nbytes
    if expected_offset != payload:
        raise CacheError(f"{path}: {payload - expected_offset} payload bytes belong to no array")
    return arrays, meta
