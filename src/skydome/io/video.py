"""Time-lapse outputs: an H.264 MP4 file, or a folder of numbered frames.

**MP4** (:class:`Mp4Writer`): 8-bit sRGB frames are piped to the ffmpeg executable that the
``imageio-ffmpeg`` package ships, through :func:`imageio_ffmpeg.write_frames`, and encoded
with libx264 at a constant rate factor (CRF, 0 = lossless ... 51 = worst; 18 is about
visually lossless, x264's own default is 23) into yuv420p: 4:2:0 chroma at limited ("TV")
range, the one layout every H.264 player and browser decodes (see FFmpeg's H.264 encoding
guide, "Encoding for dumb players"). 4:2:0 needs an even width and height: odd sizes are
refused, or padded by one repeated edge row or column with ``pad_odd=True``.

Colour: the RGB to YCbCr matrix is Rec.709 (ITU-R BT.709-6, item 3.2), and the stream is
tagged with it (matrix and primaries BT.709, transfer IEC 61966-2-1 = sRGB, the encoding of
the pixels). Without the tags a decoder guesses: ffmpeg's default conversion is BT.601, and
decoding that as BT.709 (what most players assume for HD) shifts saturated colours by up to
40 code values (measured: pure green); with them a round trip is within 2 code values.

Crash safety: frames go to a hidden temporary file beside the target
(``.name.skydome-<pid>-<random>.tmp.mp4``, see :mod:`skydome.io.atomic`), which is finalised
and renamed onto the target by ``close()``: the target path never holds a half-written file.
Leaving a ``with`` block by an exception, KeyboardInterrupt included, still finalises the
frames written so far into a playable file and then re-raises. ffmpeg runs in its own
process group, so a Ctrl-C in the terminal does not reach it, and a Ctrl-C that arrives
while a frame is being piped is held back until that frame is complete (a second one is
not). Only a hard kill of Python (SIGKILL, power loss)
leaves the temporary file behind, and never a broken target; the next run that checks an
output in that folder removes it. No frames: no file.

**Frames** (:class:`FrameSequenceWriter`): ``frame_000000.png`` (or ``.exr``, ``.hdr``,
``.npy``, ``.jpg``) in a folder, each written with the writers of ``skydome.io`` through
:func:`skydome.io.atomic.atomic_write`, so an interrupted run leaves only complete frames.
:func:`check_frame_folder` says whether a folder may take a new sequence (new or empty, or
holding only old frames to replace).

Paths are checked by :func:`check_video_output` before any rendering.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import subprocess
import threading
from collections.abc import Iterator, Mapping
from fractions import Fraction
from pathlib import Path

import numpy as np

from skydome.errors import OutputError, ParameterError, SkydomeError, check_range
from skydome.io.atomic import (
    atomic_write,
    create_temp_beside,
    probe_writable,
    remove_stale_temps,
)
from skydome.io.exr import check_hdr_frame, package_version, settings_json
from skydome.io.outputs import SUPPORTED_EXTENSIONS, WRITERS, check_output_path, file_kind
from skydome.io.png import check_ldr_image

#: The only video container written.
VIDEO_EXTENSION = ".mp4"
#: Default constant rate factor of libx264 (0 lossless ... 51 worst; 18 ~ visually lossless).
DEFAULT_CRF = 18
#: libx264's speed presets, fastest first (x264 --fullhelp).
X264_PRESETS = (
    "ultrafast",
    "superfast",
    "veryfast",
    "faster",
    "fast",
    "medium",
    "slow",
    "slower",
    "veryslow",
)
#: Largest frame side accepted (the renderer's limit, skydome.core.cameras.MAX_SIDE).
MAX_VIDEO_SIDE = 16384
#: Frame rates accepted, frames per second.
FPS_RANGE = (0.1, 1000.0)
#: Fewest digits in a frame number (``frame_000000``); more when the frame count needs them.
MIN_FRAME_DIGITS = 6
#: Extensions a frame folder can hold: every single-image writer of skydome.io.
FRAME_EXTENSIONS = SUPPORTED_EXTENSIONS

# Colour conversion and tags (see the module docstring): convert with the BT.709 matrix to
# limited range, then label the frames so that the encoder writes the VUI colour fields.
_COLOUR_FILTER = (
    "scale=out_color_matrix=bt709:out_range=tv,"
    "setparams=range=tv:colorspace=bt709:color_primaries=bt709:color_trc=iec61966-2-1"
)


class VideoOutputError(OutputError, ParameterError):
    """A time-lapse output path is unusable (missing or unwritable folder, wrong suffix).

    Both an :class:`~skydome.errors.OutputError` (like every other bad output path) and a
    :class:`~skydome.errors.ParameterError` (bad user input)."""


def _is_folder_request(raw: str, p: Path) -> bool:
    """A frame folder is asked for by a trailing slash, an existing directory, or a name
    without a suffix; anything else is a file name."""
    return raw.endswith(("/", os.sep)) or p.is_dir() or not p.suffix


def _check_writable_dir(d: Path, shown: str) -> None:
    """``d`` exists, is a directory, and a file can be created in it (a real probe, as in
    ``check_output_path``: read-only file systems and permissions are both caught, also for
    root); else VideoOutputError naming ``shown``. Stale temporary files of interrupted runs
    in ``d`` are removed."""
    if not d.exists():
        raise VideoOutputError(f"cannot write {shown!r}: directory {str(d)!r} does not exist")
    if not d.is_dir():
        raise VideoOutputError(f"cannot write {shown!r}: {str(d)!r} is not a directory")
    try:
        probe_writable(d)
    except OSError as exc:
        raise VideoOutputError(
            f"cannot write {shown!r}: directory {str(d)!r} is not writable ({exc.strerror or exc})"
        ) from None
    remove_stale_temps(d)


def check_video_output(path: str | os.PathLike) -> Path:
    """Validate a time-lapse output before any rendering; return it as a Path.

    Two kinds of output:

    * an ``.mp4`` file (any case): its folder must exist and be writable, and the path must
      not be a directory;
    * a folder of numbered frames, asked for with a trailing slash (``frames/``), an existing
      directory, or a name without a suffix: an existing one must be writable; a new one is
      created by :class:`FrameSequenceWriter`, so its parent must exist and be writable.

    The returned path has the suffix ``.mp4`` exactly when it is a video (a folder called
    ``x.mp4`` is refused). Nothing is written. Raises :class:`VideoOutputError` (an
    OutputError and a ParameterError) with one line naming the path and the problem.
    """
    try:
        raw = os.fspath(path)
        p = Path(raw).expanduser()
    except TypeError:
        raise VideoOutputError(f"output path must be a string or path, got {path!r}") from None
    shown = str(raw)
    if not raw:
        raise VideoOutputError("output path is empty (give a .mp4 file or a folder for frames)")
    if _is_folder_request(raw, p):
        if p.suffix.lower() == VIDEO_EXTENSION:
            raise VideoOutputError(
                f"cannot write {shown!r}: a folder named like a video (give a .mp4 file "
                "without a trailing slash, or another folder name for frames)"
            )
        if p.exists():
            _check_writable_dir(p, shown)
        else:
            _check_writable_dir(p.parent, shown)
        return p
    if p.suffix.lower() != VIDEO_EXTENSION:
        raise VideoOutputError(
            f"cannot write {shown!r}: extension {p.suffix!r} is not a video "
            f"(valid: {VIDEO_EXTENSION}, or a folder such as frames/ for numbered images)"
        )
    _check_writable_dir(p.parent, shown)
    kind = file_kind(p)
    if kind not in (None, "file"):
        raise VideoOutputError(f"cannot write {shown!r}: it is {kind}, not a regular file")
    return p


def frame_name_pattern(prefix: str = "frame_") -> re.Pattern[str]:
    """The names :class:`FrameSequenceWriter` gives its frames: ``prefix``, a number, and
    one of :data:`FRAME_EXTENSIONS` (lower case, as written)."""
    exts = "|".join(re.escape(e) for e in FRAME_EXTENSIONS)
    return re.compile(rf"^{re.escape(prefix)}\d+({exts})$")


def check_frame_folder(
    folder: str | os.PathLike,
    *,
    replace: bool = False,
    prefix: str = "frame_",
    replace_hint: str = "replace=True",
) -> list[Path]:
    """Check that a new frame sequence may go into ``folder``; return the frames it replaces.

    * a folder that does not exist yet, or is empty: nothing to replace, ``[]``;
    * a folder holding only frames (names as :func:`frame_name_pattern`, any extension and
      number of digits): with ``replace``, those frames, which the caller removes (with
      :func:`remove_frames`) before writing; without, VideoOutputError (the new frames
      would mix with the old ones);
    * anything else in it (another file, a folder, a link, a temporary file of a run still
      going): VideoOutputError, even with ``replace``: no file that skydome did not write is
      ever deleted.

    Stale temporary files of interrupted runs are removed first (they do not count).
    ``replace_hint`` is how the caller's user asks to replace (the CLI: ``--replace``).
    Nothing else is touched; errors are one line naming the folder.
    """
    p = Path(os.fspath(folder)).expanduser()
    shown = str(folder)
    if not p.is_dir():
        return []
    remove_stale_temps(p)
    pattern = frame_name_pattern(prefix)
    frames, others = [], []
    try:
        with os.scandir(p) as entries:
            for e in entries:
                regular = e.is_file(follow_symlinks=False)
                (frames if regular and pattern.match(e.name) else others).append(e.name)
    except OSError as exc:
        raise VideoOutputError(f"cannot read the folder {shown!r}: {exc.strerror or exc}") from None
    if others:
        example = sorted(others)[0]
        more = f" and {len(others) - 1} more" if len(others) > 1 else ""
        raise VideoOutputError(
            f"cannot write frames into {shown!r}: it holds {example!r}{more}, which are not "
            "frames of a time-lapse; choose an empty or new folder"
        )
    if frames and not replace:
        raise VideoOutputError(
            f"cannot write frames into {shown!r}: it holds {len(frames)} frames of an earlier "
            f"run ({sorted(frames)[0]}...); add {replace_hint} to replace them, or choose "
            "another folder"
        )
    return [p / name for name in sorted(frames)]


def remove_frames(frames: list[Path]) -> None:
    """Delete the frames :func:`check_frame_folder` returned (those already gone are
    skipped). Raises OutputError naming the first that cannot be deleted."""
    for f in frames:
        try:
            os.unlink(f)
        except FileNotFoundError:
            continue
        except OSError as exc:
            raise OutputError(
                f"cannot remove the old frame {str(f)!r}: {exc.strerror or exc}"
            ) from None


def _check_size(size: tuple[int, int]) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in size)
        ok = all(float(v) == int(v) for v in size)
    except (TypeError, ValueError):
        raise ParameterError(f"size must be (width, height) in pixels, got {size!r}") from None
    if not ok or not (1 <= w <= MAX_VIDEO_SIDE and 1 <= h <= MAX_VIDEO_SIDE):
        raise ParameterError(
            f"size {size!r} must be whole pixels from 1 to {MAX_VIDEO_SIDE} a side"
        )
    return w, h


class _DeferredInterrupt:
    """Hold back SIGINT (KeyboardInterrupt) while a frame is piped to or finalised by ffmpeg,
    then raise it: an interrupted pipe write would misalign every later frame, and an
    interrupted finalisation would kill ffmpeg. A second Ctrl-C interrupts at once.

    Only acts in the main thread and when Python's default SIGINT handler is installed."""

    def __init__(self) -> None:
        self.pending = False
        self._old = None

    def _handler(self, signum, frame) -> None:
        self.pending = True
        signal.signal(signal.SIGINT, self._old)  # the next Ctrl-C goes straight through

    def __enter__(self) -> _DeferredInterrupt:
        if (
            threading.current_thread() is threading.main_thread()
            and signal.getsignal(signal.SIGINT) is signal.default_int_handler
        ):
            self._old = signal.signal(signal.SIGINT, self._handler)
        return self

    def __exit__(self, exc_type, exc, tb) -> bool:
        if self._old is not None:
            if signal.getsignal(signal.SIGINT) == self._handler:
                signal.signal(signal.SIGINT, self._old)
            self._old = None
        if self.pending:  # the user asked to stop: that wins over any other error here
            self.pending = False
            raise KeyboardInterrupt
        return False


class Mp4Writer:
    """Write 8-bit sRGB frames into an H.264 MP4 file, atomically and crash-safely.

    Use as a context manager::

        with Mp4Writer("day.mp4", fps=30, size=(1280, 720)) as video:
            for image in images:          # uint8 (720, 1280, 3), row 0 at the top
                video.write(image)

    Args:
        path: the ``.mp4`` file (checked by :func:`check_video_output`; an existing file is
            replaced only when the new one is complete).
        fps: frames per second of playback, in [0.1, 1000] (29.97 and other non-integers are
            kept as exact fractions).
        size: (width, height) of every frame, pixels.
        crf: libx264 constant rate factor, 0 (lossless) to 51 (worst); 18 is about visually
            lossless and x264's default is 23.
        preset: libx264 speed preset (one of :data:`X264_PRESETS`); slower is smaller.
        pad_odd: H.264 in 4:2:0 needs an even width and height. False: an odd size raises
            ParameterError. True: the last column and/or row is repeated once.
        metadata: render settings, stored as JSON in the file's ``comment`` tag together with
            ``software`` (skydome's version).
    Attributes:
        frames_written: frames accepted so far.
        encoded_size: (width, height) of the encoded video (``size`` plus any padding).
    """

    def __init__(
        self,
        path: str | os.PathLike,
        fps: float,
        size: tuple[int, int],
        *,
        crf: int = DEFAULT_CRF,
        preset: str = "medium",
        pad_odd: bool = False,
        metadata: Mapping[str, object] | None = None,
    ) -> None:
        p = check_video_output(path)
        if p.suffix.lower() != VIDEO_EXTENSION:
            raise VideoOutputError(f"cannot write {str(path)!r}: an MP4 needs a .mp4 file name")
        fps_value = check_range("fps", fps, *FPS_RANGE, "frames/s")
        w, h = _check_size(size)
        crf_value = check_range("crf", crf, 0, 51)
        if crf_value != int(crf_value):
            raise ParameterError(f"crf = {crf} must be a whole number from 0 to 51")
        crf = int(crf_value)
        if preset not in X264_PRESETS:
            raise ParameterError(
                f"preset {preset!r}: unknown x264 preset; choose one of {', '.join(X264_PRESETS)}"
            )
        if (w % 2 or h % 2) and not pad_odd:
            raise ParameterError(
                f"size {w}x{h}: H.264 (yuv420p) needs an even width and height; use an even "
                "size or pad_odd=True to repeat the last column/row"
            )
        self.path = p
        # An exact fraction (e.g. Fraction(30000, 1001)) is kept; a float becomes the nearest
        # fraction with a denominator up to 10^6, as imageio-ffmpeg does.
        self.fps = fps if isinstance(fps, Fraction) else Fraction(fps_value).limit_denominator()
        self.size = (w, h)
        self.encoded_size = (w + w % 2, h + h % 2)
        self.crf = crf
        self.preset = preset
        self.metadata = dict(metadata) if metadata else None
        self.frames_written = 0
        self.closed = False
        self._done: Path | None = None  # the target, once the video is in place
        self._tmp: Path | None = None
        self._gen = None
        self._proc: subprocess.Popen | None = None

    # -- context manager -----------------------------------------------------------------
    def __enter__(self) -> Mp4Writer:
        return self

    def __exit__(self, exc_type, exc, tb) -> bool:
        if exc is None:
            self.close()
            return False
        try:
            self.close()
        except BaseException as close_exc:  # keep the original exception; note this one
            if hasattr(exc, "add_note"):
                exc.add_note(f"skydome: could not finalise {str(self.path)!r}: {close_exc}")
        return False

    def __del__(self) -> None:
        # Like a file object: an unclosed writer is finalised when it is collected.
        with contextlib.suppress(Exception):
            if not self.closed:
                self.close()

    # -- writing -------------------------------------------------------------------------
    def _output_params(self) -> list[str]:
        meta = self.metadata or {}
        params = [
            "-crf",
            str(self.crf),
            "-preset",
            self.preset,
            "-vf",
            _COLOUR_FILTER,
            "-movflags",
            "+faststart",  # index at the front: playback starts before the download ends
            # MP4 keeps only its known tags (a custom key is dropped): the comment holds all.
            "-metadata",
            "comment=" + settings_json({"software": f"skydome {package_version()}", **meta}),
        ]
        return params

    def _start(self) -> None:
        import imageio_ffmpeg

        try:
            self._tmp = create_temp_beside(self.path)
        except OSError as exc:
            raise OutputError(f"cannot write {str(self.path)!r}: {exc.strerror or exc}") from exc
        try:
            self._gen = imageio_ffmpeg.write_frames(
                str(self._tmp),
                self.encoded_size,
                pix_fmt_in="rgb24",
                pix_fmt_out="yuv420p",
                fps=self.fps,
                quality=None,  # rate control by -crf below
                codec="libx264",
                macro_block_size=1,  # sizes are already even; never let it rescale
                ffmpeg_log_level="error",
                output_params=self._output_params(),
            )
            self._gen.send(None)  # starts ffmpeg
        except Exception as exc:
            self._abort()
            raise OutputError(f"cannot start ffmpeg for {str(self.path)!r}: {exc}") from exc
        # The generator's Popen, to read ffmpeg's exit status after close (write_frames does
        # not check it); None if a future imageio-ffmpeg stores it elsewhere.
        frame = getattr(self._gen, "gi_frame", None)
        proc = frame.f_locals.get("p") if frame is not None else None
        self._proc = proc if isinstance(proc, subprocess.Popen) else None

    def _check_frame(self, image: np.ndarray) -> np.ndarray:
        a = check_ldr_image(image)
        w, h = self.size
        if a.shape != (h, w, 3):
            raise ParameterError(
                f"frame of shape {a.shape} does not match the video size {w}x{h} "
                f"(expected ({h}, {w}, 3))"
            )
        ew, eh = self.encoded_size
        if (ew, eh) != (w, h):
            a = np.pad(a, ((0, eh - h), (0, ew - w), (0, 0)), mode="edge")
        return np.ascontiguousarray(a)

    def write(self, image: np.ndarray) -> None:
        """Append one frame: uint8 (height, width, 3) sRGB, row 0 at the top.

        Raises ParameterError for a frame of the wrong shape or type (nothing is written),
        OutputError if ffmpeg has failed (the partial video is discarded)."""
        if self.closed:
            raise ParameterError(f"{str(self.path)!r} is closed; no more frames can be written")
        data = self._check_frame(image)
        if self._gen is None:
            self._start()
        with _DeferredInterrupt():  # a Ctrl-C now is raised once the frame is in the pipe
            try:
                self._send(data)
            except (OSError, StopIteration, RuntimeError) as exc:
                self._abort()
                text = str(exc).strip()
                reason = text.splitlines()[0] if text else type(exc).__name__
                raise OutputError(
                    f"cannot write {str(self.path)!r}: ffmpeg stopped after "
                    f"{self.frames_written} frames ({reason})"
                ) from exc
            self.frames_written += 1

    def _send(self, data: np.ndarray) -> None:
        """Pipe one frame's bytes to ffmpeg."""
        self._gen.send(data)

    def _abort(self) -> None:
        """Stop ffmpeg and delete the temporary file; the target is untouched."""
        self.closed = True
        if self._proc is not None and self._proc.poll() is None:
            with contextlib.suppress(OSError):
                self._proc.kill()
        if self._gen is not None:
            with contextlib.suppress(Exception):
                self._gen.close()
        if self._tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(self._tmp)

    def close(self) -> Path | None:
        """Finalise the video and move it onto the target path; return the path, or None
        when no frame was written (then no file is made). Calling it again does nothing.

        Raises OutputError if ffmpeg fails; the target then keeps its old content, if any."""
        if self.closed:
            return self._done
        self.closed = True
        if self._gen is None:
            return None
        tmp = self._tmp
        try:
            # A Ctrl-C during finalisation is raised once the file is in place.
            with _DeferredInterrupt():
                self._gen.close()  # closes ffmpeg's stdin and waits for it to finish the file
                rc = self._proc.returncode if self._proc is not None else 0
                if rc != 0:
                    raise OutputError(
                        f"cannot write {str(self.path)!r}: ffmpeg exited with status {rc}"
                    )
                with open(tmp, "rb") as f:
                    os.fsync(f.fileno())
                os.replace(tmp, self.path)
                self._done, self._tmp = self.path, None
        except BaseException as exc:
            if self._tmp is not None:
                with contextlib.suppress(OSError):
                    os.unlink(tmp)
            if isinstance(exc, SkydomeError) or not isinstance(exc, Exception):
                raise
            raise OutputError(f"cannot write {str(self.path)!r}: {exc}") from exc
        return self._done


class FrameSequenceWriter:
    """Write numbered frames ``<prefix><number><extension>`` into a folder, each atomically.

    Each frame is written to a hidden temporary file in the folder and renamed into place
    (:func:`skydome.io.atomic.atomic_write`), so an interrupted run leaves only complete
    frames. The folder is created if it does not exist (its parent must). Frames already in
    the folder with the same names are replaced (the CLI first asks
    :func:`check_frame_folder` whether the folder may take a new sequence).

    Args:
        folder: the output folder (checked by :func:`check_video_output`).
        extension: ``.png`` or ``.jpg`` (tone-mapped uint8 (H, W, 3) images), ``.exr``,
            ``.hdr`` or ``.npy`` (float frames (H, W, 4) or (H, W, 3) in cd/m^2).
        frame_count: the number of frames planned, to size the numbers: at least
            :data:`MIN_FRAME_DIGITS` digits, more for a million frames or more.
        prefix: the file name before the number.
        start: the number of the first frame.
        metadata: render settings stored in every frame (merged with each write's own).
    Attributes:
        frames_written: frames written so far; digits: the width of the numbers.
    """

    def __init__(
        self,
        folder: str | os.PathLike,
        extension: str = ".png",
        *,
        frame_count: int | None = None,
        prefix: str = "frame_",
        start: int = 0,
        metadata: Mapping[str, object] | None = None,
    ) -> None:
        folder_path = check_video_output(folder)
        if folder_path.suffix.lower() == VIDEO_EXTENSION:
            raise VideoOutputError(
                f"cannot write frames into {str(folder)!r}: that is a video file name "
                "(use Mp4Writer, or give a folder)"
            )
        ext = str(extension).lower()
        ext = ext if ext.startswith(".") else "." + ext
        if ext not in WRITERS:
            raise VideoOutputError(
                f"frame extension {extension!r} is not supported "
                f"(valid: {', '.join(FRAME_EXTENSIONS)})"
            )
        if not isinstance(prefix, str) or os.sep in prefix or "/" in prefix:
            raise ParameterError(
                f"prefix {prefix!r} must be a file name (a string without a folder)"
            )
        start = int(check_range("start", start, 0, 1e12))
        if frame_count is not None:
            frame_count = int(check_range("frame_count", frame_count, 1, 1e12))
        last = start + (frame_count or 1) - 1
        self.digits = max(MIN_FRAME_DIGITS, len(str(last)))
        self.folder = folder_path
        self.extension = ext
        self.prefix = prefix
        self.start = start
        self.frame_count = frame_count
        self.metadata = dict(metadata) if metadata else {}
        self.frames_written = 0
        self._shape: tuple[int, ...] | None = None
        try:
            self.folder.mkdir(exist_ok=True)
        except OSError as exc:
            raise VideoOutputError(
                f"cannot create {str(folder)!r}: {exc.strerror or exc}"
            ) from None
        try:  # the same checks as every other output file (extension, writable folder)
            check_output_path(self.path_for(start))
        except OutputError as exc:
            raise VideoOutputError(str(exc)) from None

    @property
    def hdr(self) -> bool:
        """True if frames are float HDR frames in cd/m^2, False if tone-mapped uint8."""
        return WRITERS[self.extension].hdr

    def path_for(self, number: int) -> Path:
        """The path of frame ``number`` (absolute numbering: ``start`` is the first)."""
        return self.folder / f"{self.prefix}{int(number):0{self.digits}d}{self.extension}"

    def __enter__(self) -> FrameSequenceWriter:
        return self

    def __exit__(self, exc_type, exc, tb) -> bool:
        self.close()
        return False

    def close(self) -> None:
        """Nothing is buffered (every frame is complete on disk once written); for symmetry
        with :class:`Mp4Writer`."""

    def write(self, image: np.ndarray, metadata: Mapping[str, object] | None = None) -> Path:
        """Write the next frame atomically and return its path.

        ``image`` is a uint8 (H, W, 3) sRGB image for .png/.jpg, a float frame (H, W, 4) or
        (H, W, 3) in cd/m^2 for .exr/.hdr/.npy; every frame must have the first one's shape.
        Raises ParameterError for a wrong image (nothing is written), OutputError if the file
        cannot be written (no partial file is left)."""
        writer = WRITERS[self.extension]
        data = check_hdr_frame(image) if writer.hdr else check_ldr_image(image)
        if self._shape is None:
            self._shape = data.shape
        elif data.shape != self._shape:
            raise ParameterError(
                f"frame of shape {data.shape} differs from the sequence's {self._shape}"
            )
        number = self.start + self.frames_written
        if number >= 10**self.digits:
            raise ParameterError(
                f"frame {number} needs more than {self.digits} digits; give frame_count"
            )
        meta = {**self.metadata, **dict(metadata or {})} or None
        path = self.path_for(number)

        def fill(tmp: Path) -> None:
            writer.write(tmp, data, meta)

        atomic_write(path, fill)
        self.frames_written += 1
        return path

    def paths(self) -> Iterator[Path]:
        """The paths of the frames written so far, in order."""
        for i in range(self.frames_written):
            yield self.path_for(self.start + i)
