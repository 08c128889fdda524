"""A two-channel float table as OpenEXR (the split-sum BRDF table of
:mod:`skydome.lighting_ibl`): channels R (the scale of F0) and G (its bias), float32, row 0 at
the top, lossless ZIP; ``skydome_table`` in the header says what the axes are."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from skydome.errors import ParameterError
from skydome.io.atomic import atomic_write


def write_table_exr(path: str | os.PathLike, table: np.ndarray, description: str) -> Path:
    """Write ``table`` (H, W, 2) as an EXR of channels R and G, atomically; ``description``
    goes into the header (``skydome_table``)."""
    import OpenEXR

    a = np.asarray(table)
    if a.ndim != 3 or a.shape[-1] != 2 or 0 in a.shape or not np.all(np.isfinite(a)):
        raise ParameterError(f"a table must be a finite (H, W, 2) array, got shape {a.shape}")
    channels = {name: np.ascontiguousarray(a[..., i], dtype=np.float32) for i, name in
                enumerate("RG")}  # fmt: skip
    header = {
        "compression": OpenEXR.ZIP_COMPRESSION,
        "type": OpenEXR.scanlineimage,
        "skydome_table": description,
    }

    def write(tmp: Path) -> None:
        with OpenEXR.File(header, channels) as f:
            f.write(str(tmp))

    return atomic_write(path, write)
