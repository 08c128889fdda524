"""KTX 2.0 cube maps with mip chains, half floats (Khronos, "KTX File Format Specification,
Version 2.0"): what Vulkan loaders, libktx and three.js' KTX2Loader read.

Layout: the 12-byte identifier, an 80-byte header (vkFormat VK_FORMAT_R16G16B16A16_SFLOAT =
97, typeSize 2, width = height = the face size, depth 0, layerCount 0, faceCount 6, the
level count, no supercompression; the byte ranges of the data format descriptor, of the
key/value data (none) and of the supercompression global data (none)), the level index
(offset, length, uncompressed length of each level, level 0 first), the data format
descriptor (one Khronos basic block: RGBSDA model, BT.709 primaries, linear transfer, four
16-bit signed float samples R, G, B, A), then the levels, **smallest first** (the spec's
order), each 8-byte aligned and holding its 6 faces +X, -X, +Y, -Y, +Z, -Z, rows top first.
"""

from __future__ import annotations

import os
import struct
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from skydome.io.atomic import atomic_write
from skydome.io.dds import cube_rgba16

KTX2_IDENTIFIER = b"\xabKTX 20\xbb\r\n\x1a\n"
VK_FORMAT_R16G16B16A16_SFLOAT = 97
KHR_DF_MODEL_RGBSDA = 1
KHR_DF_PRIMARIES_BT709 = 1
KHR_DF_TRANSFER_LINEAR = 1
#: Sample qualifiers: signed float.
KHR_DF_SAMPLE_DATATYPE_SIGNED_FLOAT = 0x40 | 0x80
#: Channel ids of the RGBSDA model: R, G, B and alpha.
RGBA_CHANNELS = (0, 1, 2, 15)
HEADER_BYTES = 80
LEVEL_INDEX_BYTES = 24


def data_format_descriptor() -> bytes:
    """The basic data format descriptor of RGBA16F, linear BT.709 (with its total size)."""
    block_size = 24 + 16 * 4
    block = struct.pack(
        "<IHH4B4B8B",
        0,  # vendor id 0 (Khronos, 17 bits) and descriptor type 0 (basic, 15 bits)
        2,  # version number
        block_size,
        KHR_DF_MODEL_RGBSDA, KHR_DF_PRIMARIES_BT709, KHR_DF_TRANSFER_LINEAR, 0,
        0, 0, 0, 0,  # texel block dimensions - 1
        8, 0, 0, 0, 0, 0, 0, 0,  # bytes per plane
    )  # fmt: skip
    for i, channel in enumerate(RGBA_CHANNELS):
        block += struct.pack(
            "<HBB4BII",
            16 * i,  # bit offset
            15,  # bit length - 1
            channel | KHR_DF_SAMPLE_DATATYPE_SIGNED_FLOAT,
            0, 0, 0, 0,  # sample position
            0xBF800000, 0x3F800000,  # lower -1.0, upper 1.0 (floats)
        )  # fmt: skip
    return struct.pack("<I", 4 + block_size) + block


def ktx2_cube_bytes(levels: Sequence[np.ndarray], scale: float = 1.0) -> bytes:
    """The KTX2 file (module docstring) of a cube's mip ``levels``, values x ``scale``."""
    data = cube_rgba16(levels, scale)
    n = data[0].shape[1]
    dfd = data_format_descriptor()
    dfd_offset = HEADER_BYTES + LEVEL_INDEX_BYTES * len(data)
    offset = dfd_offset + len(dfd)
    images = {}
    for k in reversed(range(len(data))):  # smallest level first in the file
        offset += -offset % 8
        images[k] = (offset, data[k].tobytes())
        offset += len(images[k][1])
    header = KTX2_IDENTIFIER + struct.pack(
        "<9I4I2Q",
        VK_FORMAT_R16G16B16A16_SFLOAT, 2, n, n, 0, 0, 6, len(data), 0,
        dfd_offset, len(dfd), 0, 0,  # the data format descriptor; no key/value data
        0, 0,  # no supercompression global data
    )  # fmt: skip
    index = b"".join(
        struct.pack("<3Q", images[k][0], len(images[k][1]), len(images[k][1]))
        for k in range(len(data))
    )
    out = bytearray(header + index + dfd)
    for k in reversed(range(len(data))):
        start, blob = images[k]
        out += b"\0" * (start - len(out))
        out += blob
    return bytes(out)


def write_ktx2_cube(
    path: str | os.PathLike, levels: Sequence[np.ndarray], scale: float = 1.0
) -> Path:
    """Write a cube's mip ``levels`` (each (6, n, n, 3|4), faces +X, -X, +Y, -Y, +Z, -Z, row
    0 at the top) to ``path`` as a KTX2 file (module docstring), atomically."""
    blob = ktx2_cube_bytes(levels, scale)
    return atomic_write(path, lambda tmp: Path(tmp).write_bytes(blob))
