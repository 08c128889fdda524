"""Time-lapse outputs: MP4 read back by ffmpeg, crash safety, atomic numbered frames, and
output path checks."""

from __future__ import annotations

import os
import signal
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")

from skydome.errors import OutputError, ParameterError  # noqa: E402
from skydome.io import WRITERS, Writer, read_exr  # noqa: E402
from skydome.io.video import (  # noqa: E402
    FrameSequenceWriter,
    Mp4Writer,
    VideoOutputError,
    check_video_output,
)

W, H = 64, 48
# Uniform colours, saturated ones included (they show a wrong YCbCr matrix most).
COLOURS = [
    (255, 0, 0),
    (0, 255, 0),
    (0, 0, 255),
    (128, 128, 128),
    (10, 200, 60),
    (250, 250, 5),
    (3, 3, 3),
    (255, 255, 255),
    (200, 120, 40),
    (40, 90, 220),
    (0, 0, 0),
    (90, 30, 150),
]
# A uniform colour survives H.264 (CRF 18, yuv420p) within the rounding of the 8-bit
# limited-range YCbCr it passes through: a luma step is 255/219 = 1.16 RGB code values and a
# chroma step moves B by 1.8556 * 255/224 = 2.1 (BT.709 matrix, ITU-R BT.709-6 item 3.2), so
# rounding alone gives up to 0.58 + 1.06 = 1.6, and the encoder's quantizer may add about a
# step more: 4 code values (measured: at most 2, for these colours).
CODEC_TOLERANCE = 4


def _read_back(path: Path) -> tuple[dict, list[np.ndarray]]:
    """Decode every frame with imageio-ffmpeg's reader (ffmpeg, rgb24)."""
    gen = imageio_ffmpeg.read_frames(str(path))
    meta = next(gen)
    w, h = meta["size"]
    frames = [np.frombuffer(f, np.uint8).reshape(h, w, 3) for f in gen]
    return meta, frames


def _frame(colour) -> np.ndarray:
    return np.full((H, W, 3), colour, dtype=np.uint8)


def test_mp4_reads_back_with_the_frames_written(tmp_path):
    target = tmp_path / "day.mp4"
    with Mp4Writer(target, fps=30, size=(W, H), metadata={"place": "Valletta"}) as video:
        for c in COLOURS:
            video.write(_frame(c))
        assert video.frames_written == 12
    meta, frames = _read_back(target)
    assert meta["codec"] == "h264"
    assert meta["size"] == (W, H) and meta["fps"] == pytest.approx(30.0)
    assert "yuv420p" in meta["pix_fmt"] and "bt709" in meta["pix_fmt"]  # tagged colours
    assert len(frames) == 12
    errors = [int(np.abs(f.astype(int) - c).max()) for f, c in zip(frames, COLOURS, strict=True)]
    assert max(errors) <= CODEC_TOLERANCE, errors
    assert sorted(os.listdir(tmp_path)) == ["day.mp4"]  # the temporary file is gone
    # The settings are in the MP4's comment tag (ffmpeg prints the tags on stderr).
    probe = subprocess.run(
        [imageio_ffmpeg.get_ffmpeg_exe(), "-hide_banner", "-i", str(target)],
        capture_output=True,
        text=True,
    )
    assert '"place":"Valletta"' in probe.stderr and '"software":"skydome' in probe.stderr


def test_exception_inside_with_finalises_the_frames_so_far(tmp_path):
    target = tmp_path / "day.mp4"
    with pytest.raises(RuntimeError, match="render failed"):
        with Mp4Writer(target, fps=30, size=(W, H)) as video:
            for i in range(5):
                video.write(_frame(COLOURS[i]))
            raise RuntimeError("render failed")
    assert os.listdir(tmp_path) == ["day.mp4"]  # no temporary file
    n, _ = imageio_ffmpeg.count_frames_and_secs(str(target))
    _, frames = _read_back(target)
    assert n == 5 and len(frames) == 5  # playable, all five frames
    assert np.abs(frames[4].astype(int) - COLOURS[4]).max() <= CODEC_TOLERANCE


def test_keyboard_interrupt_inside_with_finalises_too(tmp_path):
    target = tmp_path / "day.mp4"
    with pytest.raises(KeyboardInterrupt):
        with Mp4Writer(target, fps=30, size=(W, H)) as video:
            for i in range(3):
                video.write(_frame(COLOURS[i]))
            raise KeyboardInterrupt
    assert os.listdir(tmp_path) == ["day.mp4"]
    assert imageio_ffmpeg.count_frames_and_secs(str(target))[0] == 3


@pytest.fixture
def default_sigint():
    """Python's own SIGINT handler for the test: a process started in the background by a
    non-interactive shell (as CI jobs may be) inherits SIGINT ignored, and Python then
    installs no KeyboardInterrupt handler, which the writer leaves alone."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def test_ctrl_c_while_a_frame_is_piped_keeps_that_frame(tmp_path, default_sigint):
    # A SIGINT arriving in the middle of a pipe write is held back until the frame is in.
    target = tmp_path / "day.mp4"
    with pytest.raises(KeyboardInterrupt):
        with Mp4Writer(target, fps=30, size=(W, H)) as video:
            video.write(_frame(COLOURS[0]))
            send = video._send

            def send_interrupted(data):
                signal.raise_signal(signal.SIGINT)  # delivered during the "pipe write"
                send(data)

            video._send = send_interrupted
            video.write(_frame(COLOURS[1]))
            pytest.fail("the interrupt was lost")  # pragma: no cover
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    assert video.frames_written == 2
    assert imageio_ffmpeg.count_frames_and_secs(str(target))[0] == 2
    assert os.listdir(tmp_path) == ["day.mp4"]


def test_zero_frames_make_no_file(tmp_path):
    with Mp4Writer(tmp_path / "none.mp4", fps=30, size=(W, H)) as video:
        pass
    assert video.close() is None and video.frames_written == 0
    assert os.listdir(tmp_path) == []
    # An existing file is not touched when nothing is written.
    (tmp_path / "old.mp4").write_bytes(b"old")
    with pytest.raises(RuntimeError):
        with Mp4Writer(tmp_path / "old.mp4", fps=30, size=(W, H)):
            raise RuntimeError
    assert (tmp_path / "old.mp4").read_bytes() == b"old"


def test_ffmpeg_dying_leaves_the_old_target_and_no_temporary_file(tmp_path):
    target = tmp_path / "day.mp4"
    target.write_bytes(b"old video")
    video = Mp4Writer(target, fps=30, size=(W, H))
    video.write(_frame(COLOURS[0]))
    video._proc.kill()
    video._proc.wait()
    with pytest.raises(OutputError, match="ffmpeg") as exc:
        for _ in range(200):  # the pipe buffer may take a few frames before it breaks
            video.write(_frame(COLOURS[1]))
    assert "\n" not in str(exc.value)
    assert target.read_bytes() == b"old video"
    assert os.listdir(tmp_path) == ["day.mp4"]


def test_odd_sizes_are_refused_or_padded(tmp_path):
    with pytest.raises(ParameterError, match="even width and height") as exc:
        Mp4Writer(tmp_path / "odd.mp4", fps=30, size=(65, 48))
    assert "\n" not in str(exc.value)
    with Mp4Writer(tmp_path / "odd.mp4", fps=30, size=(65, 47), pad_odd=True) as video:
        assert video.encoded_size == (66, 48)
        video.write(np.full((47, 65, 3), (10, 200, 60), np.uint8))
    meta, frames = _read_back(tmp_path / "odd.mp4")
    assert meta["size"] == (66, 48) and len(frames) == 1
    assert np.abs(frames[0].astype(int) - (10, 200, 60)).max() <= CODEC_TOLERANCE


def test_bad_frames_and_settings_raise_parameter_error(tmp_path):
    with Mp4Writer(tmp_path / "v.mp4", fps=30, size=(W, H)) as video:
        with pytest.raises(ParameterError, match="does not match the video size"):
            video.write(np.zeros((H, W + 2, 3), np.uint8))
        with pytest.raises(ParameterError, match="uint8"):
            video.write(np.zeros((H, W, 3), np.float32))
    assert os.listdir(tmp_path) == []  # nothing valid was written: no file
    for kwargs, match in [
        ({"fps": 0}, "fps"),
        ({"fps": 30, "crf": 60}, "crf"),
        ({"fps": 30, "preset": "warp"}, "preset"),
    ]:
        kwargs.setdefault("size", (W, H))
        with pytest.raises(ParameterError, match=match):
            Mp4Writer(tmp_path / "v.mp4", **kwargs)
    with pytest.raises(ParameterError, match="size"):
        Mp4Writer(tmp_path / "v.mp4", fps=30, size=(0, 48))


# -- numbered frames ---------------------------------------------------------------------


def test_frames_are_numbered_and_read_back(tmp_path):
    folder = tmp_path / "frames"
    with FrameSequenceWriter(folder, ".png", frame_count=12) as frames:
        for c in COLOURS:
            frames.write(_frame(c), metadata={"time": "12:00"})
    names = sorted(os.listdir(folder))
    assert names == [f"frame_{i:06d}.png" for i in range(12)]
    assert frames.digits == 6 and frames.frames_written == 12
    assert list(frames.paths()) == [folder / n for n in names]
    assert np.array_equal(np.asarray(Image.open(folder / names[4])), _frame(COLOURS[4]))
    # The number width grows with the frame count: 10^6 frames still sort by name.
    assert FrameSequenceWriter(tmp_path / "big", frame_count=1_000_000).digits == 6
    big = FrameSequenceWriter(tmp_path / "big", frame_count=1_000_001)
    assert big.digits == 7 and big.path_for(1_000_000).name == "frame_1000000.png"


@pytest.mark.parametrize("ext", [".exr", ".hdr", ".npy"])
def test_hdr_frame_sequences(tmp_path, ext):
    frame = np.full((H, W, 4), 1234.5, np.float32)
    with FrameSequenceWriter(tmp_path / "hdr", ext) as frames:
        assert frames.hdr
        frames.write(frame)
        frames.write(frame * 2)
        with pytest.raises(ParameterError, match="differs"):
            frames.write(np.zeros((H + 2, W, 4), np.float32))
    assert sorted(os.listdir(tmp_path / "hdr")) == [f"frame_00000{i}{ext}" for i in (0, 1)]
    if ext == ".exr":
        back, _ = read_exr(tmp_path / "hdr" / "frame_000001.exr")
        assert np.array_equal(back, frame * 2)
    if ext == ".npy":
        assert np.array_equal(np.load(tmp_path / "hdr" / "frame_000000.npy"), frame)


def test_interrupted_frames_leave_only_complete_files(tmp_path, monkeypatch):
    folder = tmp_path / "frames"
    frames = FrameSequenceWriter(folder, ".png", frame_count=10)
    for i in range(3):
        frames.write(_frame(COLOURS[i]))

    calls = []

    def dies_halfway(path, image, metadata=None):
        Path(path).write_bytes(b"\x89PNG half a file")  # a partial file on disk ...
        calls.append(path)
        raise (OSError(28, "No space left on device") if len(calls) == 1 else KeyboardInterrupt)

    monkeypatch.setitem(WRITERS, ".png", Writer(".png", dies_halfway, False, "broken"))
    with pytest.raises(OutputError, match="No space left") as exc:
        frames.write(_frame(COLOURS[3]))
    assert "\n" not in str(exc.value)
    with pytest.raises(KeyboardInterrupt):
        frames.write(_frame(COLOURS[3]))
    # Only the three complete frames: no partial frame 3, no temporary file.
    assert sorted(os.listdir(folder)) == [f"frame_{i:06d}.png" for i in range(3)]
    for i in range(3):
        Image.open(folder / f"frame_{i:06d}.png").verify()
    assert frames.frames_written == 3


# -- output paths ------------------------------------------------------------------------


@pytest.fixture
def unwritable_dir(tmp_path):
    """A folder where files cannot be created: chmod 555 for an ordinary user; as root (who
    ignores permission bits) sysfs, where even root cannot create files; else skip."""
    if os.geteuid() != 0:
        d = tmp_path / "ro"
        d.mkdir()
        d.chmod(0o555)
        yield d
        d.chmod(0o755)
        return
    try:
        fd = os.open("/sys/.skydome-probe", os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    except OSError:
        yield Path("/sys")
        return
    os.close(fd)  # pragma: no cover
    os.unlink("/sys/.skydome-probe")  # pragma: no cover
    pytest.skip("running as root without a read-only folder")  # pragma: no cover


def test_good_outputs_are_returned_and_nothing_written(tmp_path):
    assert check_video_output(tmp_path / "day.MP4") == tmp_path / "day.MP4"
    assert check_video_output(f"{tmp_path}/frames/") == tmp_path / "frames"
    assert check_video_output(tmp_path / "frames") == tmp_path / "frames"  # no suffix: folder
    (tmp_path / "existing.d").mkdir()
    assert check_video_output(tmp_path / "existing.d") == tmp_path / "existing.d"
    assert sorted(os.listdir(tmp_path)) == ["existing.d"]


@pytest.mark.parametrize(
    ("name", "match"),
    [
        ("nope/day.mp4", "does not exist"),
        ("nope/frames/", "does not exist"),
        ("day.avi", "extension '.avi' is not a video"),
        ("day.png", "extension '.png' is not a video"),
        ("clip.mp4/", "folder named like a video"),
    ],
)
def test_bad_outputs_raise_one_line_and_write_nothing(tmp_path, name, match):
    with pytest.raises(ParameterError, match=match) as exc:
        check_video_output(f"{tmp_path}/{name}")
    assert isinstance(exc.value, OutputError)  # also an OutputError, like check_output_path
    assert "\n" not in str(exc.value)
    with pytest.raises(VideoOutputError):
        if name.endswith("/"):
            FrameSequenceWriter(f"{tmp_path}/{name}")
        else:
            Mp4Writer(f"{tmp_path}/{name}", fps=30, size=(W, H))
    assert os.listdir(tmp_path) == []


def test_unwritable_folder(unwritable_dir):
    for target in (unwritable_dir / "day.mp4", unwritable_dir / "frames", unwritable_dir):
        with pytest.raises(ParameterError, match="not writable") as exc:
            check_video_output(target)
        assert "\n" not in str(exc.value)
    assert not (unwritable_dir / "day.mp4").exists()
    assert not (unwritable_dir / "frames").exists()


def test_bad_frame_extension(tmp_path):
    with pytest.raises(ParameterError, match="'.gif' is not supported") as exc:
        FrameSequenceWriter(tmp_path / "frames", ".gif")
    assert "\n" not in str(exc.value)
    assert os.listdir(tmp_path) == []
    with pytest.raises(ParameterError, match="video file name"):
        FrameSequenceWriter(tmp_path / "day.mp4")


# -- a frame folder for a new sequence -----------------------------------------------------


def test_check_frame_folder(tmp_path):
    from skydome.io.video import check_frame_folder, remove_frames

    folder = tmp_path / "frames"
    assert check_frame_folder(folder) == []  # not there yet
    folder.mkdir()
    assert check_frame_folder(folder) == []  # empty
    with FrameSequenceWriter(folder, ".png", frame_count=2) as frames:
        frames.write(_frame(COLOURS[0]))
        frames.write(_frame(COLOURS[1]))
    (folder / "frame_1000000.exr").write_bytes(b"an older, longer run")
    with pytest.raises(VideoOutputError, match="holds 3 frames of an earlier run") as exc:
        check_frame_folder(folder, replace_hint="--replace")
    assert "--replace" in str(exc.value) and "\n" not in str(exc.value)
    old = check_frame_folder(folder, replace=True)
    assert [p.name for p in old] == ["frame_000000.png", "frame_000001.png", "frame_1000000.exr"]
    assert len(os.listdir(folder)) == 3  # checking deletes nothing
    # Anything that is not a frame: refused, also with replace; nothing is touched.
    for other in ("notes.txt", "frame_000002.png.bak", "Frame_000002.png", "sub"):
        path = folder / other
        path.mkdir() if other == "sub" else path.write_text("mine")
        with pytest.raises(VideoOutputError, match=f"holds '{other}'.*not frames"):
            check_frame_folder(folder, replace=True)
        path.rmdir() if other == "sub" else path.unlink()
    # A temporary file of a run still writing here is not a frame either ...
    live = folder / f".frame_000002.skydome-{os.getpid()}-0123abcd.tmp.png"
    live.write_bytes(b"being written")
    with pytest.raises(VideoOutputError, match="not frames"):
        check_frame_folder(folder, replace=True)
    # ... while one of a run that died is removed and does not count.
    dead = folder / ".frame_000002.skydome-999999999-0123abcd.tmp.png"
    live.rename(dead)
    assert check_frame_folder(folder, replace=True) == old
    assert not dead.exists()
    remove_frames(old)
    assert os.listdir(folder) == []


# The parent of a time-lapse killed outright after three frames (no Python cleanup runs).
_KILLED_MP4 = """
import os, signal, sys
import numpy as np
from skydome.io.video import Mp4Writer

video = Mp4Writer(sys.argv[1], fps=30, size=(64, 48))
for i in range(3):
    video.write(np.full((48, 64, 3), 40 * i, np.uint8))
os.kill(os.getpid(), signal.SIGKILL)
"""


def test_a_killed_mp4_writer_leaves_a_temporary_file_the_next_run_removes(tmp_path):
    import sys

    from skydome.io.atomic import TEMP_NAME
    from tests.cli_helpers import cli_env

    target = tmp_path / "day.mp4"
    r = subprocess.run([sys.executable, "-c", _KILLED_MP4, target], env=cli_env(), timeout=120)
    assert r.returncode == -signal.SIGKILL
    (left,) = os.listdir(tmp_path)  # no target: only the temporary file
    assert TEMP_NAME.match(left) and left.endswith(".tmp.mp4")
    assert check_video_output(tmp_path / "next.mp4") == tmp_path / "next.mp4"
    assert os.listdir(tmp_path) == []  # its writer is gone: removed
