"""The layer interface, and what the frame graph hands a layer when it draws.

A layer owns its parameters, its GLSL files (``shaders/<its folder>/``) and its passes, in
three stages:

- ``prepare(host)``: once, when it joins a frame graph (tables, textures: may be cached);
- ``update(state)``: when the time or the place changes (light directions, irradiances);
- ``draw(frame)``: every frame, for one camera, into the frame graph's float target.

Layers of the ``"space"`` stage draw light from beyond the atmosphere (the Sun's and the
Moon's disks, the stars) additively and unattenuated; layers of the ``"volume"`` stage (the
atmosphere, clouds) composite over what lies behind them: they read it from
``frame.behind`` and write ``behind * transmittance + in-scattered light`` over their own
segment of each ray. A layer never edits another, and never imports another: what one
offers the others is a typed service (``skydome.core.services``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, Protocol

from skydome.core.basis import SpectralBasis
from skydome.core.cameras import Camera, CameraInputs, disk_scissor
from skydome.core.services import VolumeInputs
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs

if TYPE_CHECKING:
    from skydome.core.lights import SkyState

STAGES = ("space", "volume")


class LayerHost(Protocol):
    """What a layer's ``prepare`` gets: the frame graph, as far as a layer may know it."""

    ctx: object
    basis: SpectralBasis | None
    solar_scale: float

    def service(self, kind: type):
        """The service of type ``kind`` another layer of the graph provides (a
        ParameterError naming what is missing when none does)."""

    def find_service(self, kind: type):
        """The service of type ``kind`` another layer of the graph provides, or None."""


@dataclass(frozen=True)
class BehindInputs(ShaderInputs):
    """The light behind a volume layer (``shaders/common/behind.glsl``): the texture of the
    tile (GL rows), and, compiled with BEHIND_SMOOTH, the smooth space layers' light at a
    reduced resolution with its mapping."""

    u_behind: object
    u_behind_smooth: object = None
    u_smooth_map: tuple[float, float, float, float] | None = None


@dataclass
class DrawContext:
    """What a layer's ``draw`` gets for one tile of one frame.

    ``fbo``: the target, viewport set to the tile; ``behind``: for a volume layer, the
    texture (same size, GL rows) of the light arriving from behind it, else None;
    ``view``: the camera's shader inputs for this tile (its size, offset, direction map);
    ``altitude_m``: the camera's height above the ground.
    ``behind_smooth``: for the first volume layer when it ``merges_smooth``, the smooth
    space layers' light at a reduced resolution (read it with ``common/behind.glsl``'s
    ``light_behind`` compiled with BEHIND_SMOOTH, uniform ``u_smooth_map``), else None.
    ``volume_inputs``: what the volume layers give one another for this tile.
    ``target``: the texture ``fbo`` draws into; ``depth_map``: a user's scene distances
    (km, <= 0 where there is none) as a texture of this tile, or None.
    ``pixel_scale``: drawn pixels per pixel of the frame asked for (a supersampled frame's
    n; ``frame_size`` is the drawn one): a size given in the frame's pixels, such as a
    point source's PSF, is this many drawn pixels.
    """

    ctx: object
    camera: Camera
    frame_size: tuple[int, int]
    tile: tuple[int, int, int, int]
    fbo: object
    view: CameraInputs
    altitude_m: float
    basis: SpectralBasis
    behind: object = None
    behind_smooth: object = None
    smooth_map: tuple | None = None
    volume_inputs: VolumeInputs | None = None
    target: object = None
    depth_map: object = None
    pixel_scale: int = 1


class Layer:
    """Base class of the frame graph's layers (see the module docstring).

    Subclasses set ``name`` and ``stage`` and implement ``draw``; ``prepare``, ``update``,
    ``services`` and ``release`` are optional. ``enabled = False`` leaves a layer out of the
    frame.
    """

    name: ClassVar[str] = ""
    stage: ClassVar[str] = "space"
    #: A space layer whose light has no detail finer than this angle (deg) may be drawn by
    #: the graph at a reduced resolution and upsampled (diffuse glows, the Milky Way's map);
    #: None: always at full resolution (sharp sources: disks, stars).
    smooth_deg: ClassVar[float | None] = None
    #: A volume layer that reads ``frame.behind_smooth`` itself (through
    #: ``common/behind.glsl``); otherwise the graph adds that light before it draws.
    merges_smooth: ClassVar[bool] = False

    def __new__(cls, *args, **kwargs):
        layer = super().__new__(cls)
        # The constructor's arguments, to make the layer again (fresh) for another sky.
        layer._arguments = (args, kwargs)
        return layer

    def __init__(self, *, enabled: bool = True):
        self.enabled = bool(enabled)
        self.graph: LayerHost | None = None
        self._passes: dict[tuple, FullscreenPass] = {}

    def fresh(self) -> Layer:
        """A new, unprepared layer made with this one's constructor arguments (parameters,
        not GPU objects), enabled as this one is: for another sky (``Sky.at``). A layer
        whose later settings matter copies them here."""
        args, kwargs = self._arguments
        layer = type(self)(*args, **kwargs)
        layer.enabled = self.enabled
        return layer

    def full_screen_pass(
        self,
        ctx,
        shader: str,
        inputs: tuple[type[ShaderInputs], ...],
        camera: Camera | None = None,
        defines: dict | None = None,
    ) -> FullscreenPass:
        """The layer's pass ``shader`` with typed ``inputs``, compiled for ``camera``'s
        model (if any) with ``defines``, once per combination (kept until :meth:`release`)."""
        defines = dict(defines or {})
        if camera is not None:
            defines["CAMERA_MODEL"] = camera.model
        key = (shader, tuple(sorted(defines.items())), inputs)
        if key not in self._passes:
            self._passes[key] = FullscreenPass(ctx, shader, defines, inputs=inputs)
        return self._passes[key]

    def behind_inputs(self, frame: DrawContext) -> BehindInputs:
        """The light behind this volume layer in ``frame``."""
        return BehindInputs(frame.behind, frame.behind_smooth, frame.smooth_map)

    def prepare(self, host: LayerHost) -> None:
        """Create GPU resources (called once, by the graph, before the first draw)."""
        self.graph = host

    def services(self) -> tuple:
        """The typed services this layer offers the others (``skydome.core.services``)."""
        return ()

    def update(self, state: SkyState) -> None:
        """Take a new SkyState (the time or the place changed)."""

    @staticmethod
    def draw_small(frame: DrawContext, fpass, inputs: tuple, direction, radius_rad):
        """Draw ``fpass`` only over the pixels that can see a disk of angular radius
        ``radius_rad`` around ``direction`` (a scissor rectangle from the camera's inverse
        mapping): a full-screen pass costs every pixel on a CPU rasterizer even where it
        writes nothing."""
        w, h = frame.frame_size
        Layer.draw_in_rects(
            frame, fpass, inputs, disk_scissor(frame.camera, w, h, direction, radius_rad)
        )

    @staticmethod
    def draw_in_rects(frame: DrawContext, fpass, inputs: tuple, rects: list | None):
        """Draw ``fpass`` over the frame's pixel rectangles ``rects`` (``disk_scissor``'s:
        x, y, w, h in the frame; None: everywhere) that fall in this tile."""
        x0, y0, tw, th = frame.tile
        if rects is None:
            fpass.draw(frame.fbo, *inputs)
            return
        try:
            for rx, ry, rw, rh in rects:
                # In the tile's own pixels.
                ax, ay = max(rx - x0, 0), max(ry - y0, 0)
                bx, by = min(rx + rw - x0, tw), min(ry + rh - y0, th)
                if bx > ax and by > ay:
                    frame.fbo.scissor = (ax, ay, bx - ax, by - ay)
                    fpass.draw(frame.fbo, *inputs)
        finally:
            frame.fbo.scissor = None

    def inputs(self, frame: DrawContext) -> VolumeInputs | None:
        """Per-pixel inputs this volume layer gives the other volume layers of this tile
        before any of them draws (the clouds' shadow lengths for the air's light shafts)."""
        return None

    def draw(self, frame: DrawContext) -> None:
        raise NotImplementedError

    def outputs(self) -> dict:
        """Textures this layer made for the last tile beside the frame (name -> texture of
        the tile's size, read back into ``frame.info[name]``); none by default."""
        return {}

    def info(self) -> dict:
        """What the layer reports in a frame's ``info`` (its last update)."""
        return {}

    def release(self) -> None:
        """Free GPU resources (the graph calls it when the layer leaves)."""
        for p in self._passes.values():
            p.release()
        self._passes.clear()

    def __repr__(self) -> str:
        state = "" if self.enabled else ", off"
        return f"<{type(self).__name__} {self.name!r}{state}>"
