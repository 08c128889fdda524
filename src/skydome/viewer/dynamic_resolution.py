"""Dynamic resolution: a moving view drawn at a reduced size that holds a frame budget.

While the view moves (the camera turns, the time runs: a new frame every frame),
:class:`~skydome.viewer.scene.ViewerScene` draws the whole frame graph (the layers, the
exposure measure, glare, the eye's colours, the tone map) at ``scale`` times the window's
width and height, and :class:`Upsampler` brings the 8-bit image up to the window's size;
when the view stops, the next frame is drawn at full resolution (the refine) and kept, as
before. :class:`ResolutionController` chooses the scale from the measured frame times.

The law: a frame's time grows with its pixels, ``t = k s^2`` (s: the scale of both sides),
so the scale that would take the budget ``B`` after a frame of ``t`` ms at ``s`` is
``s* = s sqrt(B / t)``. The controller moves a continuous level part of the way there
(``damping``: 0.5 = half-way each frame: a frame that was slow by chance moves the scale
little) and shows it quantised to steps of SCALE_STEP between MIN_SCALE and MAX_SCALE, with
hysteresis: down to the step at or below the level as soon as the level is more than
SLACK under the scale (a frame over budget is not kept), up only when the level has
reached the next step (the scale up is within the budget too). The scale settles on the
largest step within the budget, and the reduced targets are not made again every frame.

The upsampling is bilinear, guided by the horizon: in a band around the ground's edge (the
sphere of the planet seen from the camera's height, ``physics.refraction.horizon_dip_sin``),
of the four reduced pixels around a window pixel those on the other side of the edge than
the pixel's own direction are left out, so the ground/sky edge stays as sharp as the
window's pixels (a fisheye's rim, its horizon, is bilinear). Point sources (stars, planets)
are drawn by the reduced frame with a PSF in its own pixels, whose weights sum to 1
(``celestial.point_sources``): every star's light is in the reduced frame, spread over more
of the window's pixels (softer, not lost). The Sun's and the Moon's disks average their
light over each reduced pixel's area (``core.cameras.disk_samples``): they keep their light
at any scale (softer too). Nothing is drawn at full resolution while the view moves: the post passes
(glare, the eye's colours, the tone map) cost more at 1280 x 720 on a CPU rasterizer than
the layers, so they run at the reduced size too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skydome.core.cameras import Camera, CameraInputs, EquirectCamera, PerspectiveCamera
from skydome.errors import ParameterError
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.textures import release_all
from skydome.physics.refraction import horizon_dip_sin

#: The frame budget (ms) by default: 30 frames per second.
DEFAULT_FRAME_BUDGET_MS = 33.0
#: The most a budget may be (ms); 0 turns dynamic resolution off.
MAX_FRAME_BUDGET_MS = 1000.0
#: The render scales (fraction of the window's width and of its height): SCALE_STEP steps
#: from MIN_SCALE to MAX_SCALE.
SCALE_STEP = 0.125
MIN_SCALE = 0.25
MAX_SCALE = 1.0
#: How far (scale) the controller's level may lie under the scale before it goes down: the
#: frame times' noise (a level within 2 % of the scale's is the same scale).
SLACK = 0.02
#: The fraction of the way to the budget's scale the level moves per frame measured.
DAMPING = 0.5


def check_frame_budget(budget_ms: float, name: str = "frame budget") -> float:
    """``budget_ms`` as a float: 0 (off) or a positive number of ms up to
    MAX_FRAME_BUDGET_MS; a ParameterError naming ``name`` otherwise."""
    try:
        value = float(budget_ms)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} {budget_ms!r} must be a number of ms (0: off)") from None
    if not (math.isfinite(value) and 0.0 <= value <= MAX_FRAME_BUDGET_MS):
        raise ParameterError(
            f"{name} {budget_ms!r} must be from 0 (off) to {MAX_FRAME_BUDGET_MS:g} ms"
        )
    return value


def quantise_scale(scale: float) -> float:
    """``scale`` snapped to the nearest SCALE_STEP within [MIN_SCALE, MAX_SCALE]."""
    s = min(max(float(scale), MIN_SCALE), MAX_SCALE)
    return min(max(round(s / SCALE_STEP) * SCALE_STEP, MIN_SCALE), MAX_SCALE)


def reduced_size(size: tuple[int, int], scale: float) -> tuple[int, int]:
    """The pixels (w, h) of a frame of ``size`` drawn at ``scale`` (each side rounded, at
    least 1)."""
    return (max(1, round(size[0] * scale)), max(1, round(size[1] * scale)))


class ResolutionController:
    """The render scale of a moving view, from measured frame times (see the module
    docstring for the law).

    Args:
        budget_ms: the frame time to hold (ms); 0: off (the scale stays MAX_SCALE).
        damping: the fraction of the way to the budget's scale moved per measurement.
    """

    def __init__(self, budget_ms: float = DEFAULT_FRAME_BUDGET_MS, *, damping: float = DAMPING):
        self.budget_ms = check_frame_budget(budget_ms)
        if not 0.0 < damping <= 1.0:
            raise ParameterError(f"damping {damping!r} must be within (0, 1]")
        self.damping = float(damping)
        #: The continuous level the measurements move, and the quantised scale in use.
        self.level = MAX_SCALE
        self.scale = MAX_SCALE

    def observe(self, frame_ms: float, scale: float) -> float:
        """A frame drawn at ``scale`` took ``frame_ms`` (ms, the whole frame: the loop's
        time between two frames); returns the scale for the next moving frame."""
        if self.budget_ms <= 0.0:
            self.level = self.scale = MAX_SCALE
            return self.scale
        if not (math.isfinite(frame_ms) and frame_ms > 0.0):
            return self.scale
        ideal = float(scale) * math.sqrt(self.budget_ms / float(frame_ms))
        ideal = min(max(ideal, MIN_SCALE), MAX_SCALE)
        self.level += self.damping * (ideal - self.level)
        steps = math.floor(self.level / SCALE_STEP + 1e-9)
        below = min(max(steps * SCALE_STEP, MIN_SCALE), MAX_SCALE)  # the step at/under it
        if self.level < self.scale - SLACK or below >= self.scale + SCALE_STEP - 1e-9:
            self.scale = below
        return self.scale


@dataclass(frozen=True)
class UpsampleInputs(ShaderInputs):
    """``viewer/upsample.glsl``: the reduced image, its size (px) and the horizon's dip."""

    u_reduced: object
    u_reduced_size: tuple[float, float]
    u_dip_sin: float


def horizon_band(
    camera: Camera, size: tuple[int, int], dip_sin: float, margin_px: float
) -> tuple[int, int, int, int] | None:
    """The window's pixels (x, y, w, h; GL: y up) within ``margin_px`` of the ground's edge
    (the directions ``dip_sin`` below the horizontal), as a rectangle; None where it is not
    in view, or for a fisheye (its horizon is its circle's rim: no ground in the frame)."""
    if not isinstance(camera, (PerspectiveCamera, EquirectCamera)):
        return None
    w, h = size
    az = np.linspace(0.0, 2.0 * np.pi, 1441)
    c = math.sqrt(max(1.0 - dip_sin * dip_sin, 0.0))
    d = np.stack([c * np.sin(az), c * np.cos(az), np.full_like(az, -dip_sin)], axis=-1)
    x, y, ok = camera.project(d, w, h)
    ok = ok & (x > -margin_px) & (x < w + margin_px) & (y > -margin_px) & (y < h + margin_px)
    if not ok.any():
        return None
    # between two samples (1/4 deg apart) the edge bulges by far less than a pixel
    x0 = max(int(math.floor(x[ok].min() - margin_px)), 0)
    x1 = min(int(math.ceil(x[ok].max() + margin_px)), w)
    y0 = max(int(math.floor(y[ok].min() - margin_px)), 0)
    y1 = min(int(math.ceil(y[ok].max() + margin_px)), h)
    if x1 <= x0 or y1 <= y0:
        return None
    return (x0, y0, x1 - x0, y1 - y0)


class Upsampler:
    """The reduced frames' 8-bit targets and the passes that bring them to a window's size:
    one bilinear fetch per window pixel, then, over the band of rows and columns around the
    ground's edge alone (:func:`horizon_band`), the pass guided by the horizon (see the
    module docstring). On llvmpipe at 1280 x 720 the plain pass costs about 5 ms, the guided
    one about 20 ms over the whole window (measured under load): hence the band."""

    def __init__(self, ctx):
        self.ctx = ctx
        self._passes: dict[tuple[int, int], FullscreenPass] = {}
        self._target = None  # (size, texture, framebuffer)
        #: The window's rectangle (x, y, w, h) the guided pass drew last (None: none).
        self.last_band: tuple[int, int, int, int] | None = None

    def target(self, size: tuple[int, int]):
        """The RGBA8 framebuffer (GL rows) a reduced frame of ``size`` is tone-mapped into."""
        if self._target is None or self._target[0] != size:
            self._release_target()
            tex = self.ctx.texture(size, 4, dtype="f1")
            tex.filter = (self.ctx.LINEAR, self.ctx.LINEAR)
            tex.repeat_x = tex.repeat_y = False
            self._target = (size, tex, self.ctx.framebuffer(color_attachments=[tex]))
        return self._target[2]

    def _pass(self, model: int, edge: int) -> FullscreenPass:
        key = (model, edge)
        if key not in self._passes:
            self._passes[key] = FullscreenPass(
                self.ctx, "viewer/upsample.glsl", {"CAMERA_MODEL": model, "EDGE": edge},
                inputs=(CameraInputs, UpsampleInputs),
            )  # fmt: skip
        return self._passes[key]

    def draw(
        self,
        framebuffer,
        size: tuple[int, int],
        camera: Camera,
        *,
        altitude_m: float,
        bottom_radius_m: float,
    ) -> None:
        """Draw the reduced image (the last :meth:`target`'s) into ``framebuffer`` over
        ``size`` (w, h) pixels; the camera's height ``altitude_m`` above a planet of
        ``bottom_radius_m`` places the horizon. ``framebuffer`` is left bound."""
        if self._target is None:
            raise ParameterError("the upsampler has no reduced image to draw")
        rsize, tex, _ = self._target
        dip = horizon_dip_sin(altitude_m, bottom_radius_m)
        inputs = (
            camera.inputs(*size),
            UpsampleInputs(tex, (float(rsize[0]), float(rsize[1])), dip),
        )
        framebuffer.viewport = (0, 0, *size)
        self._pass(int(camera.model), 0).draw(framebuffer, *inputs)
        ratio = max(size[0] / rsize[0], size[1] / rsize[1])
        self.last_band = horizon_band(camera, size, dip, 1.5 * ratio + 2.0)
        if self.last_band is not None:
            framebuffer.scissor = self.last_band
            try:
                self._pass(int(camera.model), 1).draw(framebuffer, *inputs)
            finally:
                framebuffer.scissor = None
        framebuffer.use()

    def _release_target(self) -> None:
        if self._target is not None:
            release_all(self._target[2], self._target[1])
            self._target = None

    def release(self) -> None:
        """Free the target and the passes."""
        self._release_target()
        for fpass in self._passes.values():
            fpass.release()
        self._passes.clear()
