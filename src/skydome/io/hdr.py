"""Radiance RGBE (``.hdr``) frames: linear Rec.709 / sRGB RGB in Radiance's absolute units.

**Units.** Radiance stores radiance in W/(sr m^2) and turns it into luminance with a fixed
luminous efficacy of 179 lm/W: ``L = 179 * (0.265 R + 0.670 G + 0.065 B)`` cd/m^2 (Ward,
"The RADIANCE Lighting Simulation and Rendering System", SIGGRAPH 1994; ``pvalue``,
``ximage``, ``evalglare`` and ``falsecolor`` all use it). skydome's frames are in cd/m^2, so
the writer divides every channel by :data:`RADIANCE_EFFICACY_LM_PER_W` = 179 and leaves
``EXPOSURE=1``: a Radiance-aware reader then reports the frame's luminance in cd/m^2, while a
tool that ignores the convention (most DCC software) sees the same picture 7.48 EV
(log2 179) darker, which its exposure control absorbs. :func:`read_hdr` multiplies by 179
again and returns cd/m^2.

The primaries are Rec.709 with a D65 white (a ``PRIMARIES=`` line says so), not Radiance's
default equal-energy primaries: for a grey pixel both sets of luminance weights give the same
luminance; on a rendered sky, Radiance's fixed weights give 0.97 to 1.04 times the Rec.709
luminance (0.2126, 0.7152, 0.0722) of the same pixel (median 0.970 with the Sun at 60 deg,
0.975 at 5 deg; upper sky of an equirect, measured).

**Encoding** (Ward, "Real Pixels", Graphics Gems II, 1991): each pixel is three 8-bit
mantissas sharing one exponent byte E, value = byte * 2^(E - 136), E = 0 for black. The
mantissas are rounded to the nearest step (so decoding ``byte * 2^(E-136)``, as Bruce
Walter's rgbe.c, OpenCV and stb_image do, is within 1/256 of the pixel's largest channel);
negative channels (colours outside the Rec.709 gamut) are written as 0. Scanlines are stored
flat (uncompressed), which every RGBE reader accepts; :func:`read_hdr` also reads the
new-style run-length-encoded scanlines other programs write (not the old-style repeat
pixels of files from before 1991).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from skydome.errors import OutputError, ParameterError
from skydome.io.exr import REC709_CHROMATICITIES, check_hdr_frame, package_version, settings_json

#: Radiance's luminous efficacy of its white, lm/W: luminance = 179 * weighted RGB radiance.
RADIANCE_EFFICACY_LM_PER_W = 179.0
#: Radiance's luminance weights of its own (default) primaries.
RADIANCE_LUMINANCE_WEIGHTS = (0.265, 0.670, 0.065)
#: The FORMAT line value of an RGBE file.
RGBE_FORMAT = "32-bit_rle_rgbe"
#: Header variable that holds skydome's render settings as JSON.
HDR_SETTINGS_KEY = "SKYDOME_SETTINGS"


def rgbe_encode(rgb: np.ndarray) -> np.ndarray:
    """Encode linear RGB (..., 3) (finite, any unit) as RGBE bytes (..., 4), uint8.

    Mantissas are rounded to nearest; negative channels become 0; pixels whose largest
    channel is below 2^-128 become black (E = 0). E.g. (1.0, 0.5, 0.25) -> (128, 64, 32, 129).
    Raises ParameterError for non-finite values or values of 2^127 or more.
    """
    c = np.maximum(np.asarray(rgb, dtype=np.float64), 0.0)
    if c.shape[-1:] != (3,):
        raise ParameterError(f"RGBE needs (..., 3) RGB values, got shape {c.shape}")
    if not np.all(np.isfinite(c)):
        raise ParameterError("RGBE cannot store non-finite values (NaN or infinity)")
    peak = c.max(axis=-1)
    _, exp = np.frexp(peak)  # peak = m * 2^exp with m in [0.5, 1)
    mant = np.floor(np.ldexp(c, (8 - exp)[..., None]) + 0.5)
    # A peak with m >= 255.5/256 rounds up to 256: take one exponent more.
    carry = mant.max(axis=-1) >= 256.0
    if np.any(carry):
        exp = exp + carry
        mant = np.floor(np.ldexp(c, (8 - exp)[..., None]) + 0.5)
    if np.any(exp > 127):
        raise ParameterError(
            f"value {float(peak.max()):g} is too large for RGBE (largest: 2^127 = 1.7e38)"
        )
    black = (peak == 0.0) | (exp < -127)
    out = np.empty(c.shape[:-1] + (4,), dtype=np.uint8)
    out[..., :3] = np.where(black[..., None], 0.0, mant)
    out[..., 3] = np.where(black, 0, exp + 128)
    return out


def rgbe_decode(rgbe: np.ndarray) -> np.ndarray:
    """Decode RGBE bytes (..., 4) into float32 RGB (..., 3): byte * 2^(E - 136); E = 0 is
    black. The inverse of :func:`rgbe_encode` within 1/256 of each pixel's largest channel."""
    b = np.asarray(rgbe, dtype=np.uint8)
    e = b[..., 3].astype(np.int32)
    rgb = np.ldexp(b[..., :3].astype(np.float64), (e - 136)[..., None])
    rgb[e == 0] = 0.0
    return rgb.astype(np.float32)


def hdr_header(width: int, height: int, metadata: Mapping[str, object] | None = None) -> bytes:
    """The header and resolution line of a top-to-bottom RGBE image of width x height.

    FORMAT comes last before the blank line: Bruce Walter's widely copied reader requires it.
    """
    primaries = " ".join(f"{v:.4f}" for v in REC709_CHROMATICITIES)
    lines = [
        "#?RADIANCE",
        "# linear Rec.709/sRGB RGB: luminance in cd/m^2 = 179 * weighted pixel value",
        f"SOFTWARE=skydome {package_version()}",
        f"PRIMARIES={primaries}",
        "EXPOSURE=1.0",
    ]
    if metadata:
        line = f"{HDR_SETTINGS_KEY}={settings_json(metadata)}"  # JSON is ASCII
        # Readers built on rgbe.c read lines in 127-byte pieces; a line of a multiple of 127
        # bytes would leave a lone newline, read as the blank line that ends the header.
        lines.append(line + " " if len(line) % 127 == 0 else line)
    lines += [f"FORMAT={RGBE_FORMAT}", "", f"-Y {height} +X {width}", ""]
    return "\n".join(lines).encode("ascii")


def write_hdr(
    path: str | os.PathLike, frame: np.ndarray, metadata: Mapping[str, object] | None = None
) -> None:
    """Write a frame (H, W, 4) or (H, W, 3) in cd/m^2 as a Radiance RGBE file (not
    atomically; see ``skydome.io.write_outputs``). Channels R, G, B divided by 179 (see the
    module docstring); the scotopic channel is not stored. Row 0 is the top scanline."""
    a = check_hdr_frame(frame)
    h, w = a.shape[:2]
    pixels = rgbe_encode(a[..., :3].astype(np.float64) / RADIANCE_EFFICACY_LM_PER_W)
    with open(path, "wb") as f:
        f.write(hdr_header(w, h, metadata))
        f.write(pixels.tobytes())


def _read_rle_scanline(data: memoryview, pos: int, width: int) -> tuple[np.ndarray, int]:
    """One new-style run-length-encoded scanline (after its 4-byte marker): each of the four
    byte planes in turn, as runs (count > 128: count - 128 copies of the next byte) and
    literals (count <= 128: that many bytes). Returns (width, 4) bytes and the new position."""
    line = np.empty((4, width), dtype=np.uint8)
    for plane in range(4):
        x = 0
        while x < width:
            count = data[pos]
            pos += 1
            if count > 128:
                count -= 128
                if x + count > width:
                    raise ValueError("run past the end of a scanline")
                line[plane, x : x + count] = data[pos]
                pos += 1
            else:
                if count == 0 or x + count > width:
                    raise ValueError("bad literal count in a scanline")
                line[plane, x : x + count] = np.frombuffer(data[pos : pos + count], np.uint8)
                pos += count
            x += count
    return line.T, pos


def read_hdr(path: str | os.PathLike) -> tuple[np.ndarray, dict[str, str]]:
    """Read a Radiance RGBE file with scanlines top to bottom ("-Y H +X W").

    Returns ``(frame, header)``: frame float32 (H, W, 3) in cd/m^2 (pixel values times 179,
    divided by the product of the EXPOSURE lines), row 0 at the top; header maps each
    ``NAME=value`` header variable to its (last) value. Flat and run-length-encoded
    scanlines are both read. Raises OutputError for anything else or a damaged file.
    """
    p = Path(path)
    try:
        data = memoryview(p.read_bytes())
    except OSError as exc:
        raise OutputError(f"cannot read HDR {str(p)!r}: {exc.strerror or exc}") from exc
    try:
        end = bytes(data[:65536]).index(b"\n\n")
        lines = bytes(data[:end]).decode("ascii", "replace").split("\n")
        if not lines[0].startswith("#?"):
            raise ValueError("no '#?' magic line")
        header, exposure = {}, 1.0
        for ln in lines[1:]:
            name, sep, value = ln.partition("=")
            if sep and not ln.startswith("#"):
                header[name.strip()] = value.strip()
                if name.strip() == "EXPOSURE":
                    exposure *= float(value)
        if header.get("FORMAT", RGBE_FORMAT) != RGBE_FORMAT:
            raise ValueError(f"FORMAT {header['FORMAT']} is not {RGBE_FORMAT}")
        nl = bytes(data[end + 2 : end + 2 + 64]).index(b"\n")
        res = bytes(data[end + 2 : end + 2 + nl]).decode("ascii").split()
        if len(res) != 4 or res[0] != "-Y" or res[2] != "+X":
            raise ValueError(f"unsupported orientation {' '.join(res)}")
        h, w = int(res[1]), int(res[3])
        pos = end + 3 + nl
        pixels = np.empty((h, w, 4), dtype=np.uint8)
        for y in range(h):
            marker = data[pos : pos + 4]
            if 8 <= w <= 0x7FFF and marker[0] == 2 and marker[1] == 2 and marker[2] < 128:
                if (marker[2] << 8) | marker[3] != w:
                    raise ValueError(f"scanline {y} has the wrong length")
                pixels[y], pos = _read_rle_scanline(data, pos + 4, w)
            else:
                row = np.frombuffer(data[pos : pos + 4 * w], np.uint8)
                if row.size != 4 * w:
                    raise ValueError("truncated pixel data")
                pixels[y] = row.reshape(w, 4)
                pos += 4 * w
    except (ValueError, IndexError) as exc:
        raise OutputError(f"cannot read HDR {str(p)!r}: {exc}") from exc
    scale = RADIANCE_EFFICACY_LM_PER_W / exposure
    return (rgbe_decode(pixels) * np.float32(scale)).astype(np.float32), header
