"""Data shipped in ``skydome/data``: maps as NumPy archives (one array plus JSON metadata with
a format version, written by a ``tools/`` script: the Moon's albedo, the Milky Way), and
tables as CSV files with ``#`` comment lines and a header row."""

from __future__ import annotations

import io
import json
from importlib import resources
from pathlib import Path

import numpy as np

from skydome.errors import SkydomeError
from skydome.io.atomic import atomic_write


def write_packaged_npz(path, meta: dict, **arrays) -> None:
    """Write ``arrays`` and ``meta`` (with its ``format_version``) to ``path`` as
    :func:`read_packaged_npz` reads them: a compressed NumPy archive whose ``meta_json`` holds
    the metadata; atomically (a killed tool leaves the old file)."""

    def write(tmp: Path) -> None:
        with open(tmp, "wb") as f:
            np.savez_compressed(f, meta_json=np.array(json.dumps(meta)), **arrays)

    atomic_write(path, write)


def read_packaged_npz(
    file_name: str, array_key: str, format_version: int, what: str, tool: str
) -> tuple[np.ndarray, dict]:
    """The array ``array_key`` and the metadata (``meta_json``) of ``skydome/data/file_name``.

    A missing, truncated or foreign file, or another format version, raises SkydomeError
    naming ``what`` it holds and the ``tool`` that rebuilds it."""
    try:
        raw = resources.files("skydome.data").joinpath(file_name).read_bytes()
        with np.load(io.BytesIO(raw), allow_pickle=False) as z:
            array = z[array_key]
            meta = json.loads(str(z["meta_json"]))
    except Exception as exc:  # missing, truncated or foreign file
        raise SkydomeError(
            f"the packaged {what} {file_name} cannot be read ({exc}); rebuild it with {tool}"
        ) from exc
    if meta.get("format_version") != format_version:
        raise SkydomeError(
            f"{file_name} has format {meta.get('format_version')}, expected {format_version}; "
            f"rebuild it with {tool}"
        )
    return array, meta


def read_packaged_csv(file_name: str, columns: tuple[str, ...] | None = None) -> dict:
    """The numeric columns of ``skydome/data/file_name`` by name (float64 arrays): ``#`` lines
    are comments, the first other line names the columns. ``columns``, when given, must be the
    file's (in order), else SkydomeError."""
    try:
        text = resources.files("skydome.data").joinpath(file_name).read_text()
        rows = [ln for ln in text.splitlines() if ln.strip() and not ln.startswith("#")]
        names = tuple(rows[0].split(","))
        table = np.array([[float(v) for v in r.split(",")] for r in rows[1:]], dtype=np.float64)
    except Exception as exc:  # missing or malformed file
        raise SkydomeError(f"the packaged table {file_name} cannot be read ({exc})") from exc
    if columns is not None and names != tuple(columns):
        raise SkydomeError(f"{file_name}: columns {names}, expected {tuple(columns)}")
    if table.ndim != 2 or table.shape[1] != len(names):
        raise SkydomeError(f"{file_name}: every row needs {len(names)} values")
    return {name: table[:, k].copy() for k, name in enumerate(names)}
