"""Maps shipped in ``skydome/data`` as NumPy archives: one array plus JSON metadata with a
format version, written by a ``tools/`` script (the Moon's albedo, the Milky Way)."""

from __future__ import annotations

import io
import json
from importlib import resources

import numpy as np

from skydome.errors import SkydomeError


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
