"""DirectDraw Surface (DDS) cube maps with mip chains, half floats: what Direct3D, Unity,
Unreal's importer and three.js' loaders read.

Layout (Microsoft, "DDS file layout" and "DDS_HEADER_DXT10"): the magic ``"DDS "``, a
124-byte DDS_HEADER (flags CAPS | HEIGHT | WIDTH | PITCH | PIXELFORMAT | MIPMAPCOUNT, the
pitch of a row of level 0, the mip count; a pixel format of FOURCC ``"DX10"``; caps COMPLEX
| TEXTURE | MIPMAP, caps2 CUBEMAP and its 6 faces), a 20-byte DDS_HEADER_DXT10
(DXGI_FORMAT_R16G16B16A16_FLOAT = 10, D3D10_RESOURCE_DIMENSION_TEXTURE2D = 3, misc flag
D3D11_RESOURCE_MISC_TEXTURECUBE = 4, array size 1: one cube), then the faces in the order
+X, -X, +Y, -Y, +Z, -Z, each with all its mip levels, largest first, rows top first.
"""

from __future__ import annotations

import os
import struct
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from skydome.errors import ParameterError
from skydome.io.atomic import atomic_write

DDS_MAGIC = b"DDS "
DDSD_CAPS, DDSD_HEIGHT, DDSD_WIDTH, DDSD_PITCH = 0x1, 0x2, 0x4, 0x8
DDSD_PIXELFORMAT, DDSD_MIPMAPCOUNT = 0x1000, 0x20000
DDPF_FOURCC = 0x4
DDSCAPS_COMPLEX, DDSCAPS_TEXTURE, DDSCAPS_MIPMAP = 0x8, 0x1000, 0x400000
DDSCAPS2_CUBEMAP = 0x200
DDSCAPS2_CUBEMAP_ALLFACES = 0x400 | 0x800 | 0x1000 | 0x2000 | 0x4000 | 0x8000
DXGI_FORMAT_R16G16B16A16_FLOAT = 10
D3D10_RESOURCE_DIMENSION_TEXTURE2D = 3
D3D11_RESOURCE_MISC_TEXTURECUBE = 0x4
#: The largest finite half float.
HALF_MAX = 65504.0


def cube_rgba16(levels: Sequence[np.ndarray], scale: float = 1.0) -> list[np.ndarray]:
    """The levels (each (6, n, n, 3|4), n halving) as float16 RGBA (alpha 1 if absent),
    times ``scale``; ParameterError if a value is not finite or beyond half float's range."""
    out = []
    size = None
    for k, level in enumerate(levels):
        a = np.asarray(level, dtype=np.float64)
        if a.ndim != 4 or a.shape[0] != 6 or a.shape[1] != a.shape[2] or a.shape[3] not in (3, 4):
            raise ParameterError(f"cube level {k} must be (6, n, n, 3 or 4), got {a.shape}")
        if size is not None and a.shape[1] != max(size // 2, 1):
            raise ParameterError(f"cube level {k} is {a.shape[1]} texels, not half of {size}")
        size = a.shape[1]
        rgba = np.ones((*a.shape[:3], 4))
        rgba[..., : a.shape[3]] = a
        rgba[..., :3] *= scale
        peak = float(np.max(np.abs(rgba))) if np.all(np.isfinite(rgba)) else float("inf")
        if not peak <= HALF_MAX:
            raise ParameterError(
                f"cube level {k} holds {peak:.4g} (x scale {scale:g}), beyond half float's "
                f"{HALF_MAX:g}: write it with a smaller scale"
            )
        out.append(rgba.astype("<f2"))
    if not out:
        raise ParameterError("a cube map needs at least one level")
    return out


def dds_cube_bytes(levels: Sequence[np.ndarray], scale: float = 1.0) -> bytes:
    """The DDS file (module docstring) of a cube's mip ``levels``, RGBA16F, values x scale."""
    data = cube_rgba16(levels, scale)
    n = data[0].shape[1]
    flags = DDSD_CAPS | DDSD_HEIGHT | DDSD_WIDTH | DDSD_PITCH | DDSD_PIXELFORMAT
    flags |= DDSD_MIPMAPCOUNT
    pixel_format = struct.pack("<II4s5I", 32, DDPF_FOURCC, b"DX10", 0, 0, 0, 0, 0)
    caps = DDSCAPS_COMPLEX | DDSCAPS_TEXTURE | DDSCAPS_MIPMAP
    header = struct.pack(
        "<7I44x32s4I4x",
        124, flags, n, n, n * 8, 0, len(data),  # size, flags, height, width, pitch, depth, mips
        pixel_format,
        caps, DDSCAPS2_CUBEMAP | DDSCAPS2_CUBEMAP_ALLFACES, 0, 0,
    )  # fmt: skip
    dx10 = struct.pack(
        "<5I",
        DXGI_FORMAT_R16G16B16A16_FLOAT,
        D3D10_RESOURCE_DIMENSION_TEXTURE2D,
        D3D11_RESOURCE_MISC_TEXTURECUBE,
        1,
        0,
    )
    body = b"".join(level[face].tobytes() for face in range(6) for level in data)
    return DDS_MAGIC + header + dx10 + body


def write_dds_cube(
    path: str | os.PathLike, levels: Sequence[np.ndarray], scale: float = 1.0
) -> Path:
    """Write a cube's mip ``levels`` (each (6, n, n, 3|4), faces +X, -X, +Y, -Y, +Z, -Z, row
    0 at the top) to ``path`` as a DDS file (module docstring), atomically."""
    blob = dds_cube_bytes(levels, scale)
    return atomic_write(path, lambda tmp: Path(tmp).write_bytes(blob))
