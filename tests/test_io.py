"""Output files: EXR / HDR / NPY / PNG / JPEG round trips, path validation, atomic writes."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from skydome.errors import OutputError, ParameterError
from skydome.io import (
    RADIANCE_EFFICACY_LM_PER_W,
    SCOTOPIC_CHANNEL,
    WRITERS,
    Writer,
    atomic_write,
    check_output_path,
    read_exr,
    read_hdr,
    write_outputs,
)
from skydome.io.hdr import RADIANCE_LUMINANCE_WEIGHTS, rgbe_decode, rgbe_encode

SETTINGS = {"model": "single", "camera": "fisheye", "exposure_ev": 14.5, "tonemap": "filmic"}


@pytest.fixture
def frame():
    """A float32 frame with awkward values: 0, -0, negatives, denormals, the Sun, 1e-30."""
    rng = np.random.default_rng(7)
    f = (10.0 ** rng.uniform(-6, 9, (13, 17, 4)) * rng.choice([-1, 1], (13, 17, 4))).astype(
        np.float32
    )
    f[0, 0] = [0.0, -0.0, 1e-45, 1e-30]
    f[1, 1, :3] = 1.6e9
    return f


@pytest.fixture
def ldr():
    return np.random.default_rng(8).integers(0, 256, (13, 17, 3), dtype=np.uint8)


def leftovers(directory: Path) -> list[str]:
    """Temporary files (hidden, '.tmp' in the name) left in a directory."""
    return [n for n in os.listdir(directory) if n.startswith(".") and ".tmp" in n]


def test_exr_round_trip_is_bit_exact_with_scotopic_channel(tmp_path, frame):
    (path,) = write_outputs(tmp_path / "sky.exr", frame, metadata=SETTINGS)
    back, header = read_exr(path)
    assert back.dtype == np.float32 and back.shape == frame.shape
    # Bit-exact: float32 channels and lossless ZIP compression (compare bit patterns, so
    # -0.0 and denormals count too).
    np.testing.assert_array_equal(back.view(np.uint32), frame.view(np.uint32))
    assert SCOTOPIC_CHANNEL in [c.name for c in header["channels"]]
    assert header["skydome_units"] == "cd/m^2"
    assert header["whiteLuminance"] == 1.0
    assert json.loads(header["skydome_settings"]) == SETTINGS
    assert leftovers(tmp_path) == []


def test_exr_without_scotopic_channel(tmp_path, frame):
    write_outputs(tmp_path / "rgb.EXR", frame[..., :3])  # extension in any case
    back, _ = read_exr(tmp_path / "rgb.EXR")
    assert back.shape == (13, 17, 3)
    np.testing.assert_array_equal(back, frame[..., :3])


def test_png_reads_back_with_settings(tmp_path, frame, ldr):
    (path,) = write_outputs([tmp_path / "sky.png"], frame, ldr, metadata=SETTINGS)
    with Image.open(path) as im:
        assert im.format == "PNG" and im.mode == "RGB"
        assert im.size == (17, 13)  # (width, height)
        np.testing.assert_array_equal(np.asarray(im), ldr)  # row 0 stays on top
        assert json.loads(im.text["skydome"]) == SETTINGS
        assert im.text["Software"].startswith("skydome")
        assert im.info.get("srgb") == 0  # sRGB chunk, perceptual intent


def test_npy_round_trip(tmp_path, frame):
    (path,) = write_outputs(str(tmp_path / "sky.npy"), frame)
    back = np.load(path)
    assert back.dtype == np.float32
    np.testing.assert_array_equal(back.view(np.uint32), frame.view(np.uint32))


def test_several_outputs_at_once(tmp_path, frame, ldr):
    paths = [tmp_path / n for n in ("a.exr", "a.png", "a.npy", "a.hdr", "a.jpg")]
    assert write_outputs(paths, frame, ldr) == paths
    assert all(p.is_file() and p.stat().st_size > 0 for p in paths)
    assert leftovers(tmp_path) == []


@pytest.mark.parametrize("name", ["sky.tif", "sky", "sky.exr.gz"])
def test_unknown_extension(tmp_path, name):
    with pytest.raises(OutputError) as exc:
        check_output_path(tmp_path / name)
    msg = str(exc.value)
    assert "\n" not in msg
    assert all(ext in msg for ext in (".exr", ".hdr", ".jpg", ".npy", ".png"))


def test_missing_directory_and_directory_target(tmp_path):
    with pytest.raises(OutputError, match="does not exist"):
        check_output_path(tmp_path / "nope" / "sky.png")
    (tmp_path / "d.png").mkdir()
    with pytest.raises(OutputError, match="is a directory"):
        check_output_path(tmp_path / "d.png")
    (tmp_path / "file").write_text("x")
    with pytest.raises(OutputError, match="not a directory"):
        check_output_path(tmp_path / "file" / "sky.png")


@pytest.fixture
def read_only_dir(tmp_path):
    """A directory where files cannot be created. chmod 555 stops ordinary users; root ignores
    permission bits, so there we use sysfs (/sys), where even root cannot create files."""
    if os.geteuid() != 0:
        d = tmp_path / "ro"
        d.mkdir()
        d.chmod(0o555)
        yield d
        d.chmod(0o755)
        return
    sys_dir = Path("/sys")
    try:
        fd = os.open(sys_dir / ".skydome-probe", os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    except OSError:
        yield sys_dir
        return
    os.close(fd)  # pragma: no cover - /sys writable: cannot build a read-only directory
    os.unlink(sys_dir / ".skydome-probe")  # pragma: no cover
    pytest.skip("running as root without a read-only directory")  # pragma: no cover


def test_read_only_directory(read_only_dir, frame):
    with pytest.raises(OutputError, match="not writable") as exc:
        check_output_path(read_only_dir / "sky.exr")
    assert "\n" not in str(exc.value)
    with pytest.raises(OutputError):
        write_outputs(read_only_dir / "sky.npy", frame)


def test_valid_path_is_returned_and_nothing_is_left(tmp_path):
    p = check_output_path(str(tmp_path / "Sky.PNG"))
    assert p == tmp_path / "Sky.PNG"
    assert os.listdir(tmp_path) == []  # the writability probe is removed


def test_failed_write_leaves_no_file(tmp_path, frame, ldr, monkeypatch):
    def broken(path, image, metadata=None):
        Path(path).write_bytes(b"\x89PNG half a file")  # something partial on disk...
        raise RuntimeError("disk on fire")  # ...then the writer dies

    monkeypatch.setitem(WRITERS, ".png", Writer(".png", broken, False, "broken"))
    with pytest.raises(OutputError, match="disk on fire") as exc:
        write_outputs(tmp_path / "sky.png", frame, ldr)
    assert isinstance(exc.value.__cause__, RuntimeError)
    assert os.listdir(tmp_path) == []

    # An existing file is left untouched by a failed replacement.
    target = tmp_path / "old.png"
    target.write_bytes(b"old content")
    with pytest.raises(OutputError):
        write_outputs(target, frame, ldr)
    assert target.read_bytes() == b"old content"
    assert os.listdir(tmp_path) == ["old.png"]


def test_atomic_write_cleans_up_on_interrupt(tmp_path):
    def interrupted(path):
        Path(path).write_bytes(b"partial")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic_write(tmp_path / "x.npy", interrupted)
    assert os.listdir(tmp_path) == []


# A writer killed in the middle of a file (SIGKILL: no Python cleanup runs).
_KILLED_MID_WRITE = """
import os, signal, sys
from skydome.io import atomic_write

def write(tmp):
    with open(tmp, "wb") as f:
        f.write(b"half a file")
    os.kill(os.getpid(), signal.SIGKILL)

atomic_write(sys.argv[1], write)
"""


def test_a_killed_writer_leaves_a_temporary_file_the_next_run_removes(tmp_path):
    import subprocess
    import sys

    from skydome.io.atomic import TEMP_NAME
    from tests.cli_helpers import cli_env

    target = tmp_path / "sky.png"
    r = subprocess.run([sys.executable, "-c", _KILLED_MID_WRITE, target], env=cli_env(), timeout=60)
    assert r.returncode == -9
    (left,) = os.listdir(tmp_path)  # the target is not there: only the temporary file
    assert TEMP_NAME.match(left) and left.startswith(".sky.") and left.endswith(".tmp.png")
    # The next run that checks an output in that folder removes it (its writer is gone),
    # and nothing else: a user's hidden file and a temporary file of a writer still running.
    mine = tmp_path / ".notes.tmp.png"
    mine.write_text("not skydome's")
    running = tmp_path / f".other.skydome-{os.getpid()}-0123abcd.tmp.exr"
    running.write_bytes(b"being written")
    assert check_output_path(tmp_path / "other.exr") == tmp_path / "other.exr"
    assert sorted(os.listdir(tmp_path)) == sorted([mine.name, running.name])
    # A temporary file of a live PID left unchanged for over a day is stale too (the PID
    # may be another program's by now, or the file another machine's).
    from skydome.io.atomic import STALE_AFTER_S, is_stale_temp

    assert not is_stale_temp(running)
    old = os.stat(running).st_mtime - STALE_AFTER_S - 60
    os.utime(running, (old, old))
    assert is_stale_temp(running)
    check_output_path(tmp_path / "sky.png")
    assert os.listdir(tmp_path) == [mine.name]


def test_write_outputs_uses_named_temporary_files(tmp_path, frame, monkeypatch):
    """The temporary file names its writer's PID, so another run can tell it is stale."""
    from skydome.io.atomic import TEMP_NAME

    seen = []

    def spy(path, data, metadata=None):
        seen.append(Path(path).name)
        np.save(Path(path).open("wb"), data)

    monkeypatch.setitem(WRITERS, ".npy", Writer(".npy", spy, True, "spy"))
    write_outputs(tmp_path / "f.npy", frame)
    (name,) = seen
    m = TEMP_NAME.match(name)
    assert m and int(m["pid"]) == os.getpid() and name.endswith(".tmp.npy")
    assert os.listdir(tmp_path) == ["f.npy"]


@pytest.mark.parametrize("kind", ["fifo", "dir"])
def test_special_files_are_not_output_targets(tmp_path, kind):
    target = tmp_path / "sky.png"
    os.mkfifo(target) if kind == "fifo" else target.mkdir()
    with pytest.raises(OutputError, match="a FIFO|a directory") as exc:
        check_output_path(target)
    assert "\n" not in str(exc.value) and "not a regular file" in str(exc.value)
    with pytest.raises(OutputError, match=r"valid: \.lut\)"):
        check_output_path(tmp_path / "t.txt", extensions=(".lut",))
    assert check_output_path(tmp_path / "t.LUT", extensions=(".lut",)) == tmp_path / "t.LUT"


def test_all_paths_checked_before_writing(tmp_path, frame, ldr):
    with pytest.raises(OutputError, match="gif"):
        write_outputs([tmp_path / "a.exr", tmp_path / "b.gif"], frame, ldr)
    with pytest.raises(ParameterError, match="tone-mapped image"):
        write_outputs([tmp_path / "a.exr", tmp_path / "b.png"], frame, None)
    with pytest.raises(ParameterError, match="uint8"):
        write_outputs([tmp_path / "a.exr", tmp_path / "b.png"], frame, ldr.astype(np.float32))
    with pytest.raises(ParameterError, match="HDR frame"):
        write_outputs(tmp_path / "a.npy", ldr.astype(np.int32))
    assert os.listdir(tmp_path) == []  # nothing written by any of these


# --- Radiance RGBE (.hdr) -------------------------------------------------------------------

#: A decoded RGBE channel is within half a mantissa step of the value: 2^(E-9), at most 1/256
#: of the pixel's largest channel (whose mantissa is at least 128). The extra 2^-20 covers the
#: float32 rounding of the decoded value and of the 179 factor.
RGBE_REL_TOL = 2.0**-8 + 2.0**-20
#: Pixels below the smallest exponent (2^-128 in Radiance units, 5e-37 cd/m^2) are black.
RGBE_FLOOR_CD_M2 = 179.0 * 2.0**-128


def rgbe_error_ok(back: np.ndarray, frame_rgb: np.ndarray) -> np.ndarray:
    """Per pixel: is every channel of ``back`` (cd/m^2) within RGBE's precision of
    ``frame_rgb`` (negative channels, which RGBE cannot hold, written as 0)?"""
    want = np.maximum(frame_rgb.astype(np.float64), 0.0)
    err = np.abs(back.astype(np.float64) - want).max(axis=-1)
    return err <= RGBE_REL_TOL * want.max(axis=-1) + RGBE_FLOOR_CD_M2


def test_rgbe_encoding_matches_the_published_example():
    # Ward, "Real Pixels" (Graphics Gems II) / Walter's rgbe.c: (1.0, 0.5, 0.25) has mantissa
    # 0.5 and exponent 1 (1.0 = 0.5 * 2^1): bytes 0.5*256, 0.25*256, 0.125*256 and 1 + 128.
    np.testing.assert_array_equal(rgbe_encode(np.array([1.0, 0.5, 0.25])), [128, 64, 32, 129])
    np.testing.assert_array_equal(rgbe_decode(np.array([128, 64, 32, 129])), [1.0, 0.5, 0.25])
    # Black is all zeros; a largest channel just under 1 rounds up into the next exponent
    # (0.9995 * 256 = 255.87 would need a mantissa of 256).
    np.testing.assert_array_equal(rgbe_encode(np.zeros(3)), [0, 0, 0, 0])
    np.testing.assert_array_equal(rgbe_encode(np.array([0.9995, 0.5, 0.0])), [128, 64, 0, 129])
    with pytest.raises(ParameterError, match="non-finite"):
        rgbe_encode(np.array([1.0, np.nan, 0.0]))


def test_hdr_is_read_by_opencv_in_radiance_units(tmp_path, frame):
    """OpenCV's reader (Walter's rgbe.c, an implementation independent of ours) gives the
    frame divided by 179 within RGBE's precision; row 0 stays on top, channel order kept."""
    import cv2  # OpenCV is in the dev extra: an independent RGBE reader, never skipped

    (path,) = write_outputs(tmp_path / "sky.hdr", frame, metadata=SETTINGS)
    bgr = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    assert bgr is not None and bgr.dtype == np.float32 and bgr.shape == (13, 17, 3)
    back = bgr[..., ::-1] * RADIANCE_EFFICACY_LM_PER_W
    ok = rgbe_error_ok(back, frame[..., :3])
    assert ok.all(), f"{(~ok).sum()} pixels off by more than 1/256"
    assert leftovers(tmp_path) == []


def test_hdr_grey_luminance_by_radiance_convention(tmp_path):
    """A Radiance-aware reader's luminance, 179 * (0.265 R + 0.670 G + 0.065 B), of a grey
    sky of 5000 cd/m^2 (the weights sum to 1) is 5000 cd/m^2 within 1/256."""
    import cv2  # OpenCV is in the dev extra: an independent RGBE reader, never skipped

    grey = np.full((4, 9, 4), 5000.0, dtype=np.float32)
    (path,) = write_outputs(tmp_path / "grey.hdr", grey)
    rgb = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)[..., ::-1].astype(np.float64)
    lum = 179.0 * rgb @ np.array(RADIANCE_LUMINANCE_WEIGHTS)
    np.testing.assert_allclose(lum, 5000.0, rtol=2.0**-8)


def test_hdr_header(tmp_path, frame):
    (path,) = write_outputs(tmp_path / "sky.hdr", frame, metadata=SETTINGS)
    head = path.read_bytes()[:2000].split(b"\n\n")[0].decode("ascii").split("\n")
    assert head[0] == "#?RADIANCE"
    # FORMAT is the last line before the blank one (rgbe.c-based readers require it).
    assert head[-1] == "FORMAT=32-bit_rle_rgbe"
    assert "EXPOSURE=1.0" in head
    assert "PRIMARIES=0.6400 0.3300 0.3000 0.6000 0.1500 0.0600 0.3127 0.3290" in head
    back, header = read_hdr(path)
    assert json.loads(header["SKYDOME_SETTINGS"]) == SETTINGS
    assert header["SOFTWARE"].startswith("skydome")
    # Our reader undoes the 179 and gives cd/m^2 within RGBE's precision.
    assert back.shape == (13, 17, 3) and rgbe_error_ok(back, frame[..., :3]).all()


def test_read_hdr_reads_run_length_encoded_files_from_opencv(tmp_path):
    """OpenCV writes run-length-encoded scanlines; read_hdr decodes them to the same values
    as OpenCV's own reader, times 179 (both decode byte * 2^(E - 136): float32-exact)."""
    import cv2  # OpenCV is in the dev extra: an independent RGBE reader, never skipped

    rng = np.random.default_rng(3)
    rgb = (10.0 ** rng.uniform(-3, 5, (20, 40, 3))).astype(np.float32)
    rgb[5:9] = rgb[5, 0]  # constant rows: long runs
    path = tmp_path / "cv.hdr"
    assert cv2.imwrite(str(path), np.ascontiguousarray(rgb[..., ::-1]))
    assert path.read_bytes().split(b"\n\n", 1)[1].split(b"\n", 1)[1][:2] == b"\x02\x02"
    ref = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)[..., ::-1] * np.float32(179.0)
    back, _ = read_hdr(path)
    np.testing.assert_allclose(back, ref, rtol=1e-6, atol=0)
    # OpenCV's encoder truncates the mantissas (ours rounds): within one step, 1/128.
    err = np.abs(back / 179.0 - rgb).max(axis=-1)
    assert np.all(err <= 2.0**-7 * rgb.max(axis=-1))


def test_damaged_hdr_and_non_finite_frames(tmp_path, frame):
    (path,) = write_outputs(tmp_path / "sky.hdr", frame)
    path.write_bytes(path.read_bytes()[:-100])
    with pytest.raises(OutputError, match="truncated"):
        read_hdr(path)
    bad = frame.copy()
    bad[3, 4, 1] = np.inf
    with pytest.raises(ParameterError, match="non-finite"):
        write_outputs(tmp_path / "bad.hdr", bad)
    assert sorted(os.listdir(tmp_path)) == ["sky.hdr"]


# --- JPEG -----------------------------------------------------------------------------------


def test_jpeg_reads_back_with_settings(tmp_path):
    """A smooth sky-like gradient survives quality 95, 4:4:4 JPEG within a few levels
    (measured: max 3, mean 0.42 of 255, with Pillow's and OpenCV's decoders alike)."""
    y, x = np.mgrid[0:48, 0:64]
    ldr = np.stack([40 + 2 * y, 90 + y + x // 2, 200 + x // 2], axis=-1).astype(np.uint8)
    (path,) = write_outputs(tmp_path / "sky.jpg", None, ldr, metadata=SETTINGS)
    with Image.open(path) as im:
        assert im.format == "JPEG" and im.mode == "RGB" and im.size == (64, 48)
        assert json.loads(im.info["comment"]) == SETTINGS
        assert im.getexif()[0x0131].startswith("skydome")  # EXIF Software
        err = np.abs(np.asarray(im).astype(int) - ldr)
    # Bounds: twice the measured error; a swapped channel or flipped image is off by 40+.
    assert err.max() <= 6 and err.mean() <= 1.0
    assert leftovers(tmp_path) == []
