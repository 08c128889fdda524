"""OpenEXR frames in absolute units: float32 channels R, G, B (linear sRGB / Rec.709, cd/m^2)
and Y_scotopic (scotopic cd/m^2), lossless ZIP compression, row 0 at the top.

Header attributes: the standard ``chromaticities`` (Rec.709 primaries, D65 white) and
``whiteLuminance`` = 1.0 (RGB (1, 1, 1) has a luminance of 1 cd/m^2, i.e. values are absolute),
plus ``skydome_units``, ``skydome_scotopic_units``, ``skydome_version`` and, when given,
``skydome_settings`` (the render settings as JSON).
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from skydome.errors import OutputError, ParameterError

#: Name of the scotopic-luminance channel (frame channel 3).
SCOTOPIC_CHANNEL = "Y_scotopic"
#: Rec.709 / sRGB primaries and D65 white point (x, y): red, green, blue, white.
REC709_CHROMATICITIES = (0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290)


def package_version() -> str:
    try:
        from importlib.metadata import version

        return version("skydome")
    except Exception:  # pragma: no cover - not installed
        return "unknown"


def check_hdr_frame(frame: np.ndarray) -> np.ndarray:
    """A float frame (H, W, 4) or (H, W, 3) (or a Frame object's ``.data``) as C-contiguous
    float32, or ParameterError."""
    a = frame.data if isinstance(getattr(frame, "data", None), np.ndarray) else frame
    a = np.asarray(a)
    if a.ndim != 3 or a.shape[-1] not in (3, 4) or 0 in a.shape or a.dtype.kind != "f":
        raise ParameterError(
            f"HDR frame must be a non-empty float (H, W, 4) or (H, W, 3) array, got shape "
            f"{a.shape} dtype {a.dtype}"
        )
    return np.ascontiguousarray(a, dtype=np.float32)


def settings_json(metadata: Mapping[str, object] | None) -> str:
    """Render settings as compact JSON (non-JSON values as their str())."""
    return json.dumps(dict(metadata or {}), sort_keys=True, default=str, separators=(",", ":"))


def write_exr(
    path: str | os.PathLike, frame: np.ndarray, metadata: Mapping[str, object] | None = None
) -> None:
    """Write a frame (H, W, 4) or (H, W, 3) in cd/m^2 to ``path`` as float32 OpenEXR (not
    atomically; see ``skydome.io.write_outputs``). Channel 3 becomes ``Y_scotopic``."""
    import OpenEXR

    a = check_hdr_frame(frame)
    channels = {name: np.ascontiguousarray(a[..., i]) for i, name in enumerate("RGB")}
    if a.shape[-1] == 4:
        channels[SCOTOPIC_CHANNEL] = np.ascontiguousarray(a[..., 3])
    header = {
        "compression": OpenEXR.ZIP_COMPRESSION,
        "type": OpenEXR.scanlineimage,
        "chromaticities": REC709_CHROMATICITIES,
        "whiteLuminance": 1.0,
        "skydome_units": "cd/m^2",
        "skydome_scotopic_units": "scotopic cd/m^2",
        "skydome_version": package_version(),
    }
    if metadata:
        header["skydome_settings"] = settings_json(metadata)
    with OpenEXR.File(header, channels) as f:
        f.write(str(path))


def read_exr(path: str | os.PathLike) -> tuple[np.ndarray, dict]:
    """Read an EXR written by :func:`write_exr`.

    Returns ``(frame, header)``: frame float32 (H, W, 4) (R, G, B, Y_scotopic) or (H, W, 3)
    without a scotopic channel, row 0 at the top; header is the attribute dictionary. Raises
    OutputError if the file cannot be read or lacks R, G, B.
    """
    import OpenEXR

    p = Path(path)
    try:
        with OpenEXR.File(str(p), separate_channels=True) as f:
            header = dict(f.header())
            channels = {name: np.asarray(ch.pixels) for name, ch in f.channels().items()}
    except Exception as exc:
        raise OutputError(f"cannot read EXR {str(p)!r}: {exc}") from exc
    missing = [c for c in "RGB" if c not in channels]
    if missing:
        raise OutputError(f"EXR {str(p)!r} has no channel(s) {', '.join(missing)}")
    names = ["R", "G", "B"] + ([SCOTOPIC_CHANNEL] if SCOTOPIC_CHANNEL in channels else [])
    frame = np.stack([channels[n].astype(np.float32, copy=False) for n in names], axis=-1)
    return frame, header
