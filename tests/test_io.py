"""Output files: EXR / PNG / NPY round trips, path validation, atomic writes."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from skydome.errors import OutputError, ParameterError
from skydome.io import (
    SCOTOPIC_CHANNEL,
    WRITERS,
    Writer,
    atomic_write,
    check_output_path,
    read_exr,
    write_outputs,
)

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
    paths = [tmp_path / n for n in ("a.exr", "a.png", "a.npy")]
    assert write_outputs(paths, frame, ldr) == paths
    assert all(p.is_file() and p.stat().st_size > 0 for p in paths)
    assert leftovers(tmp_path) == []


@pytest.mark.parametrize("name", ["sky.jpg", "sky", "sky.exr.gz"])
def test_unknown_extension(tmp_path, name):
    with pytest.raises(OutputError) as exc:
        check_output_path(tmp_path / name)
    msg = str(exc.value)
    assert "\n" not in msg and ".exr" in msg and ".png" in msg and ".npy" in msg


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


def test_all_paths_checked_before_writing(tmp_path, frame, ldr):
    with pytest.raises(OutputError, match="jpg"):
        write_outputs([tmp_path / "a.exr", tmp_path / "b.jpg"], frame, ldr)
    with pytest.raises(ParameterError, match="tone-mapped image"):
        write_outputs([tmp_path / "a.exr", tmp_path / "b.png"], frame, None)
    with pytest.raises(ParameterError, match="uint8"):
        write_outputs([tmp_path / "a.exr", tmp_path / "b.png"], frame, ldr.astype(np.float32))
    with pytest.raises(ParameterError, match="HDR frame"):
        write_outputs(tmp_path / "a.npy", ldr.astype(np.int32))
    assert os.listdir(tmp_path) == []  # nothing written by any of these
