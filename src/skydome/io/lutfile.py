"""The lookup-table file format: named arrays plus a JSON header, checksummed, no pickle.

Layout::

    b"SKYDOMELUT\\x00\\x01"             magic and format version (12 bytes)
    uint64 little-endian               length of the JSON header in bytes
    JSON header                        {"key", "meta", "arrays": [{name, dtype, shape,
                                        offset, nbytes}], "sha256": hex of the payload}
    payload                            the arrays' bytes, C order, one after the other

Reading checks the magic, the header, the sizes and the SHA-256 of the payload; any
mismatch raises CacheError, so a truncated or corrupted file is never trusted.
"""

from __future__ import annotations

import hashlib
import json
import os
import struct
from pathlib import Path

import numpy as np

from skydome.errors import CacheError, ParameterError
from skydome.io.atomic import atomic_write

MAGIC = b"SKYDOMELUT\x00\x01"
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
    digest = hashlib.sha256()
    for b in blobs:
        digest.update(b)
    header = json.dumps(
        {"key": key, "meta": meta or {}, "arrays": entries, "sha256": digest.hexdigest()}
    ).encode()

    def write(tmp: Path) -> None:
        with open(tmp, "wb") as f:
            f.write(MAGIC)
            f.write(struct.pack("<Q", len(header)))
            f.write(header)
            for b in blobs:
                f.write(b)

    return atomic_write(path, write)


def read_lut_file(
    path: str | os.PathLike, key: str | None = None
) -> tuple[dict[str, np.ndarray], dict]:
    """Read and validate a LUT file; returns (arrays, meta). Raises CacheError if invalid.

    With ``key`` given, a file made for another key is rejected too.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise CacheError(f"cannot read {path}: {exc.strerror or exc}") from None
    if len(data) < len(MAGIC) + 8 or data[: len(MAGIC)] != MAGIC:
        raise CacheError(f"{path} is not a skydome LUT file (bad magic or truncated)")
    (hlen,) = struct.unpack_from("<Q", data, len(MAGIC))
    start = len(MAGIC) + 8
    try:
        header = json.loads(data[start : start + hlen].decode())
        entries = header["arrays"]
    except (ValueError, KeyError, UnicodeDecodeError):
        raise CacheError(f"{path} has a corrupt header") from None
    if key is not None and header.get("key") != key:
        raise CacheError(f"{path} was made for other parameters (key mismatch)")
    payload = memoryview(data)[start + hlen :]
    total = sum(int(e["nbytes"]) for e in entries)
    if len(payload) != total:
        raise CacheError(
            f"{path} is truncated or has trailing data ({len(payload)} of {total} payload bytes)"
        )
    if hashlib.sha256(payload).hexdigest() != header.get("sha256"):
        raise CacheError(f"{path} is corrupt (checksum mismatch)")
    arrays = {}
    for e in entries:
        if e["dtype"] not in _ALLOWED_DTYPES:
            raise CacheError(f"{path}: array {e['name']!r} has unsupported dtype {e['dtype']}")
        dt = np.dtype(e["dtype"]).newbyteorder("<")
        a = np.frombuffer(
            payload,
            dtype=dt,
            count=int(np.prod(e["shape"], dtype=np.int64)),
            offset=int(e["offset"]),
        )
        arrays[e["name"]] = a.reshape(e["shape"]).astype(dt.newbyteorder("="), copy=False)
    return arrays, header.get("meta", {})
