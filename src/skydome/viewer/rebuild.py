"""New atmosphere tables in the background, while the old ones stay on screen.

GL contexts belong to one thread, and a CPU rasterizer's precomputation takes seconds, so
the tables are computed in a child process with its own headless context
(``atmosphere.tables.load_tables``, which writes them to the disk cache, ``$SKYDOME_CACHE``),
reporting its progress through a queue. When it is done the viewer builds the new Sky in
its own context from the cache (a fraction of a second: one slow frame) and swaps it in
(``ViewerScene.replace_sky``). A second change while one is running stops that one and
starts anew.
"""

from __future__ import annotations

import multiprocessing as mp
import queue as queue_module
from dataclasses import dataclass, replace

import numpy as np

from skydome.atmosphere import preset
from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.presets import PRESETS
from skydome.atmosphere.tables import load_tables
from skydome.errors import ParameterError
from skydome.gpu import shared_context
from skydome.sky import Sky
from skydome.viewer.controls import clamp

#: The panel's atmosphere knobs and their ranges: ground albedo, the Mie amount (aerosol
#: optical depth at 550 nm) and asymmetry g, the ozone column (DU), and a factor on the
#: preset's Rayleigh scattering (an air of a different density).
KNOB_RANGES = {
    "albedo": (0.0, 1.0),
    "aod_550": (0.0, 5.0),
    "mie_g": (0.0, 0.99),
    "ozone_du": (0.0, 700.0),
    "rayleigh_scale": (0.25, 4.0),
}


@dataclass(frozen=True)
class Knobs:
    """A preset and the knobs set on it; ``base`` holds the preset's own values (a knob
    left at its preset's value is not applied, so the preset's spectra stay as they are)."""

    preset: str
    albedo: float
    aod_550: float
    mie_g: float
    ozone_du: float
    rayleigh_scale: float = 1.0
    base: tuple = ()

    @classmethod
    def of_preset(cls, name: str) -> Knobs:

        return cls.of(preset(name))

    @classmethod
    def of(cls, params) -> Knobs:
        """The knobs of ``params``, against its preset's own values (``params.name``; a
        params of no preset is its own base)."""

        values = _knob_values(params)
        base = _knob_values(preset(params.name)) if params.name in PRESETS else values
        return replace(clamp_knobs(cls(params.name, *values)), base=base)

    def params(self):
        """The AtmosphereParams: the preset with the knobs that differ from its own."""

        b = self.base or (None,) * 5
        changed = lambda i, v: v if b[i] is None or abs(v - b[i]) > 1e-9 else None  # noqa: E731
        p = preset(
            self.preset,
            albedo=changed(0, self.albedo),
            aod_550=changed(1, self.aod_550),
            ozone_du=changed(3, self.ozone_du),
        )
        if changed(2, self.mie_g) is not None:
            p = p.with_aerosol(mie_g=self.mie_g)
        if changed(4, self.rayleigh_scale) is not None:
            p = p.with_(rayleigh_scattering=p.rayleigh_scattering.scaled(self.rayleigh_scale))
        return p


def _knob_values(params) -> tuple[float, ...]:

    return (
        float(np.mean(params.ground_albedo.values)),
        float(params.aod_550),
        float(params.mie_g),
        float(params.ozone_du),
        1.0,
    )


def clamp_knobs(knobs: Knobs, **changes: float) -> Knobs:
    """``knobs`` with ``changes``, every knob clamped to KNOB_RANGES."""

    values = {f: getattr(knobs, f) for f in KNOB_RANGES}
    values.update(changes)
    return replace(knobs, **{f: clamp(v, *KNOB_RANGES[f]) for f, v in values.items()})


def _precompute(params, config, messages) -> None:  # runs in the child process
    try:

        def progress(stage: str, fraction: float) -> None:
            messages.put(("progress", str(stage), float(fraction)))

        load_tables(shared_context(), params, config, progress=progress)
        messages.put(("done", "", 1.0))
    except BaseException as exc:  # reported to the viewer, which keeps the old tables
        messages.put(("error", f"{type(exc).__name__}: {exc}", 0.0))


@dataclass
class RebuildStatus:
    """Where a background rebuild stands: ``running``; ``stage`` and ``fraction`` (0..1)
    of the precomputation; ``done`` (the tables are in the cache); ``error`` (a message,
    or None)."""

    running: bool = False
    stage: str = ""
    fraction: float = 0.0
    done: bool = False
    error: str | None = None


class AtmosphereRebuild:
    """One background precomputation at a time."""

    def __init__(self):
        self._proc = None
        self._messages = None
        self.params = None
        self.config = None
        self.status = RebuildStatus()

    def start(self, params, config=None) -> None:
        """Compute the tables of ``params`` (an AtmosphereParams) and ``config`` in the
        background (stopping a rebuild under way)."""

        if not isinstance(params, AtmosphereParams):
            raise ParameterError(f"a rebuild needs AtmosphereParams, got {type(params).__name__}")
        self.stop()
        context = mp.get_context("spawn")  # no fork: the parent holds a GL context
        self._messages = context.Queue()
        self._proc = context.Process(
            target=_precompute, args=(params, config, self._messages), daemon=True
        )
        self._proc.start()
        self.params, self.config = params, config
        self.status = RebuildStatus(running=True, stage="starting")

    def poll(self) -> RebuildStatus:
        """Read the child's messages; the status (``done`` once, then reset by
        :meth:`take`)."""
        if self._messages is None:
            return self.status
        while True:
            try:
                kind, text, fraction = self._messages.get_nowait()
            except queue_module.Empty:
                break
            if kind == "progress":
                self.status.stage, self.status.fraction = text, fraction
            elif kind == "done":
                self.status = RebuildStatus(running=False, stage="done", fraction=1.0, done=True)
            else:
                self.status = RebuildStatus(running=False, error=text)
        if self.status.running and self._proc is not None and not self._proc.is_alive():
            if self._proc.exitcode not in (0, None):
                self.status = RebuildStatus(
                    running=False,
                    error=f"the precomputation stopped (exit status {self._proc.exitcode})",
                )
        if not self.status.running:
            self._join()
        return self.status

    def take(self):
        """(params, config) of a finished rebuild, once; None while none is ready."""
        if not self.status.done:
            return None
        self.status = RebuildStatus()
        return self.params, self.config

    def _join(self) -> None:
        if self._proc is not None:
            self._proc.join(timeout=5)
            self._proc = None
        if self._messages is not None:
            self._messages.close()
            self._messages = None

    def stop(self) -> None:
        """Stop a rebuild under way (the old tables stay)."""
        if self._proc is not None and self._proc.is_alive():
            self._proc.terminate()
        self._join()
        self.status = RebuildStatus()


def build_sky(template, params, config=None):
    """A Sky like ``template`` (its description: place, time, layers, clouds and display;
    its context) with the atmosphere ``params`` and tables ``config``: its tables load from
    the cache when a rebuild put them there."""

    changes = {"atmosphere": params}
    if config is not None:
        changes["config"] = config
    sky = Sky(template.description.with_(**changes), ctx=template.graph.ctx)
    sky.graph.set_display(night_vision=template.night_vision, overlays=template.overlays)
    return sky
