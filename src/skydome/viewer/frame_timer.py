"""Frame times: CPU time per stage and GPU time per pass, as medians over recent frames.

``FrameTimer.cpu(name)`` times a stage of the main loop on the CPU (perf_counter);
``FrameTimer.section(name)`` (the FrameGraph's ``profiler`` protocol) wraps a GPU pass in a
GL timer query (``GL_TIME_ELAPSED``; one query per pass name, summed when a name recurs in
a frame), read back at the end of the frame. GL allows one timer query at a time, so GPU
sections do not nest: the graph's sections are its layers' passes, the exposure and the
display passes; the panel's is "panel". The GPU total is the sum of the sections.
"""

from __future__ import annotations

import contextlib
import statistics
import time
from collections import deque

#: Frames over which the readout's medians are taken.
WINDOW_FRAMES = 60


class FrameTimer:
    """Per-frame timing of a main loop.

    Args:
        ctx: the moderngl context (for GPU timer queries); None: CPU times only.
        gpu: time the GPU passes (each query's read waits for its pass: on a CPU
            rasterizer that costs little, on a GPU it serialises the frame).
        window: frames kept for the medians.
    """

    def __init__(self, ctx=None, *, gpu: bool = True, window: int = WINDOW_FRAMES):
        self.ctx = ctx
        self.gpu = bool(gpu and ctx is not None)
        self.window = int(window)
        self.frame_ms: deque[float] = deque(maxlen=self.window)
        self.cpu_ms: dict[str, deque[float]] = {}
        self.gpu_ms: dict[str, deque[float]] = {}
        self._queries: dict[str, object] = {}
        self._used: list[str] = []
        self._cpu_now: dict[str, float] = {}
        self._t_frame: float | None = None
        self._active = False
        #: Frame times (ms) of the frames that drew the sky anew (not a kept frame shown
        #: again): what the view costs while it moves.
        self.redraw_ms: deque[float] = deque(maxlen=self.window)
        self._redrawn = False
        #: Frames ended, and of them those that drew the sky anew, since the start.
        self.frames = 0
        self.redraws = 0

    # ------------------------------------------------------------------ frames

    def begin_frame(self) -> None:
        """Start a frame (the time between two begins is the frame time)."""
        now = time.perf_counter()
        if self._t_frame is not None:
            ms = (now - self._t_frame) * 1e3
            self.frame_ms.append(ms)
            if self._redrawn:
                self.redraw_ms.append(ms)
        self._t_frame = now
        self._redrawn = False
        self._used = []
        self._cpu_now = {}

    def end_frame(self, redrawn: bool = True) -> None:
        """Read this frame's GPU queries and keep the CPU stages' times; ``redrawn``: the
        frame drew the sky anew (False: it showed a kept frame again)."""
        self._redrawn = bool(redrawn)
        self.frames += 1
        self.redraws += self._redrawn
        for name, ms in self._cpu_now.items():
            self.cpu_ms.setdefault(name, deque(maxlen=self.window)).append(ms)
        if self.gpu:
            totals: dict[str, float] = {}
            for name in self._used:
                q = self._queries[name]
                totals[name] = totals.get(name, 0.0) + q.elapsed / 1e6  # ns -> ms
            for name, ms in totals.items():
                self.gpu_ms.setdefault(name, deque(maxlen=self.window)).append(ms)
        self._used = []

    @contextlib.contextmanager
    def cpu(self, name: str):
        """Time a stage of the frame on the CPU."""
        t0 = time.perf_counter()
        try:
            yield
        finally:
            ms = (time.perf_counter() - t0) * 1e3
            self._cpu_now[name] = self._cpu_now.get(name, 0.0) + ms

    def section(self, name: str):
        """A GPU timer query around a pass (a no-op without GPU timing, or inside another
        section). A name used twice in a frame reads its first query early and sums."""
        if not self.gpu or self._active:
            return contextlib.nullcontext()
        return self._gpu_section(name)

    @contextlib.contextmanager
    def _gpu_section(self, name: str):
        key = name
        n = 1
        while key in self._used:  # the same pass again this frame: its own query
            n += 1
            key = f"{name}#{n}"
        q = self._queries.get(key)
        if q is None:
            q = self._queries[key] = self.ctx.query(time=True)
        self._active = True
        try:
            # Finish the work queued before the pass, and the pass itself before its query
            # ends: a CPU rasterizer (llvmpipe) runs queued passes at the next flush, and a
            # query would otherwise time the pass that flushed, not its own.
            self.ctx.finish()
            with q:
                yield
                self.ctx.finish()
        finally:
            self._active = False
            self._used.append(key)

    # ------------------------------------------------------------------ readout

    def median_frame_ms(self) -> float | None:
        """The median frame time (ms) over the window, None before two frames."""
        return statistics.median(self.frame_ms) if self.frame_ms else None

    def fps(self) -> float | None:
        """Frames per second from the median frame time (every frame of the loop, kept
        frames shown again included)."""
        ms = self.median_frame_ms()
        return None if not ms else 1e3 / ms

    def median_redraw_ms(self) -> float | None:
        """The median time (ms) of the frames that drew the sky anew, None before one."""
        return statistics.median(self.redraw_ms) if self.redraw_ms else None

    def drawn_fps(self) -> float | None:
        """Drawn frames per second: 1000 / the median redraw time (what a moving view
        gets), None while no frame of the window drew the sky anew."""
        ms = self.median_redraw_ms()
        return None if not ms else 1e3 / ms

    def report(self) -> dict[str, dict[str, float]]:
        """Medians (ms): ``{"cpu": {stage: ms}, "gpu": {pass: ms}}``; the GPU passes of a
        name drawn several times a frame (``name#2``...) are folded into ``name``."""
        gpu: dict[str, float] = {}
        for key, values in self.gpu_ms.items():
            base = key.split("#")[0]
            gpu[base] = gpu.get(base, 0.0) + statistics.median(values)
        return {
            "cpu": {k: statistics.median(v) for k, v in self.cpu_ms.items()},
            "gpu": gpu,
        }

    def release(self) -> None:
        """Drop the GL queries (moderngl 5.13's Query has no release: they live as long as
        the context; the timer makes one per pass name, reused every frame)."""
        self._queries.clear()
