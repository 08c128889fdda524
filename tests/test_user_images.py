"""A user's image files (``--weather-map IMAGE``) are opened safely: a decompression bomb, a huge
image, a FIFO, a directory, a text file or a truncated image is refused with one line, exit
status 2, quickly and in little memory, and nothing is written."""

from __future__ import annotations

import os
import struct
import zlib

import numpy as np
import pytest
from PIL import Image

from skydome.clouds.weather import MAX_IMAGE_SIDE, WeatherMap
from skydome.errors import ParameterError
from skydome.io.images import read_user_image
from tests.cli_helpers import run_process

# What a refusal may cost, as a real process from start to exit: Python, the CLI's imports
# and the check (measured: about 0.5 s and 110 MiB on 2 cores).
MAX_SECONDS = 2.0
MAX_RSS_MIB = 500.0


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png_claiming(width: int, height: int) -> bytes:
    """A 100-byte PNG whose header claims width x height 8-bit grey pixels (the image data
    is one zero row): decoding it would allocate width * height bytes or more."""
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + _chunk(b"IHDR", ihdr)
        + _chunk(b"IDAT", zlib.compress(b"\x00" * (width + 1)))
        + _chunk(b"IEND", b"")
    )


@pytest.fixture(scope="module")
def bad_images(tmp_path_factory):
    """name -> path of each kind of bad input, in a folder of their own."""
    d = tmp_path_factory.mktemp("bad-images")
    (d / "bomb.png").write_bytes(png_claiming(30000, 30000))  # over Pillow's own limit
    (d / "bomb-12k.png").write_bytes(png_claiming(12000, 12000))  # only Pillow's warning
    # A real 10000 x 9000 image (90 megapixels; 90 kB of PNG): its pixels are never decoded.
    Image.new("L", (10000, 9000), 128).save(d / "huge.png")
    os.mkfifo(d / "fifo.png")
    (d / "text.png").write_text("coverage = 0.5\nthis is not an image\n")
    noise = np.random.default_rng(1).integers(0, 256, (64, 64, 3), np.uint8)
    Image.fromarray(noise).save(d / "whole.png")
    data = (d / "whole.png").read_bytes()
    (d / "truncated.png").write_bytes(data[: len(data) // 2])
    (d / "folder.png").mkdir()
    return d


CASES = [
    ("bomb.png", "30000x30000", ["900,000,000 pixels", "decompression bomb", "4096x4096"]),
    ("bomb-12k.png", "12000x12000", ["12000x12000", "at most 4096x4096"]),
    ("huge.png", "10000x9000", ["10000x9000", "at most 4096x4096"]),
    ("fifo.png", "FIFO", ["a FIFO", "not a PNG, JPEG or TIFF image file"]),
    ("text.png", "text", ["not a PNG, JPEG or TIFF image"]),
    ("truncated.png", "truncated", ["truncated or damaged"]),
    ("folder.png", "directory", ["a directory"]),
]


@pytest.mark.parametrize(("name", "label", "needles"), CASES, ids=[c[1] for c in CASES])
def test_bad_weather_images_are_refused_quickly_through_the_cli(
    bad_images, tmp_path, name, label, needles
):
    image = bad_images / name
    r = run_process(
        "render", "--clouds", "fair", "--weather-map", image, "--size", "32x18", "-o", "sky.png",
        cwd=tmp_path, timeout=30,
    )  # fmt: skip
    lines = r.stderr.splitlines()
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert len(lines) == 1 and lines[0].startswith("skydome: error: cannot read weather map")
    assert repr(str(image)) in lines[0]
    for needle in needles:
        assert needle in lines[0], lines[0]
    print(f"{label}: {r.seconds:.2f} s, {r.max_rss_mib:.0f} MiB peak RSS")
    assert r.seconds < MAX_SECONDS, r.seconds
    assert r.max_rss_mib < MAX_RSS_MIB, r.max_rss_mib
    assert list(tmp_path.iterdir()) == []  # nothing written


@pytest.mark.parametrize("command", ["timelapse", "view"])
def test_every_command_with_weather_refuses_a_fifo(bad_images, tmp_path, command):
    """--weather-map is read by one helper for render, timelapse and view (view needs no window
    to refuse it: the flags are checked first)."""
    where = ["--lat", "35.9", "--lon", "14.5"]
    args = {
        "timelapse": [*where, "--start", "2021-06-21T10:00Z", "--end", "2021-06-21T10:02Z",
                      "-o", "day.mp4"],
        "view": [*where, "--time", "2021-06-21T10:00Z"],
    }[command]  # fmt: skip
    r = run_process(
        command, *args, "--clouds", "fair", "--weather-map", bad_images / "fifo.png", cwd=tmp_path
    )
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert "a FIFO" in r.stderr and r.seconds < MAX_SECONDS
    assert list(tmp_path.iterdir()) == []


def test_read_user_image_checks_the_header_before_decoding(tmp_path):
    """The size budget is checked on the header: a 5000 x 10 image (under the pixel budget,
    over the side) and a file over max_bytes are refused; within both it is decoded."""
    Image.new("RGB", (5000, 10)).save(tmp_path / "wide.png")
    with pytest.raises(ParameterError, match="5000x10 pixels; at most 4096x4096") as info:
        WeatherMap.from_image(tmp_path / "wide.png", 10.0)
    assert "\n" not in str(info.value)
    Image.new("RGB", (40, 30), (255, 128, 0)).save(tmp_path / "ok.png")
    with pytest.raises(ParameterError, match="at most 0 MiB"):
        read_user_image(tmp_path / "ok.png", what="x", max_pixels=10**6, max_bytes=10)
    with pytest.raises(ParameterError, match="not a PNG image"):
        Image.new("RGB", (4, 4)).save(tmp_path / "small.jpg")
        read_user_image(tmp_path / "small.jpg", what="x", max_pixels=100, max_bytes=10**6,
                        formats=("PNG",))  # fmt: skip
    img = read_user_image(tmp_path / "ok.png", what="x", max_pixels=1200, max_bytes=10**6)
    assert img.size == (40, 30) and np.asarray(img)[0, 0].tolist() == [255, 128, 0]
    with pytest.raises(ParameterError, match="40x30 pixels; at most 1,199 pixels"):
        read_user_image(tmp_path / "ok.png", what="x", max_pixels=1199, max_bytes=10**6)
    with pytest.raises(ParameterError, match="must be a file path"):
        read_user_image(None, what="x", max_pixels=1, max_bytes=1)


def test_a_link_to_an_image_is_read_and_a_link_to_a_fifo_is_not(tmp_path):
    Image.fromarray(np.full((3, 5), 255, np.uint8)).save(tmp_path / "w.png")
    (tmp_path / "link.png").symlink_to(tmp_path / "w.png")
    assert WeatherMap.from_image(tmp_path / "link.png", 1.0).size == (5, 3)
    os.mkfifo(tmp_path / "fifo")
    (tmp_path / "fifo-link.png").symlink_to(tmp_path / "fifo")
    with pytest.raises(ParameterError, match="a FIFO"):
        WeatherMap.from_image(tmp_path / "fifo-link.png", 1.0)


def test_the_budget_is_the_generators_largest_map():
    assert MAX_IMAGE_SIDE == 4096
    with pytest.raises(ParameterError, match="4096"):
        WeatherMap.generate(size=MAX_IMAGE_SIDE + 1)
