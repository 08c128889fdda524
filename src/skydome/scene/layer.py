"""The layer interface of the scene, and what the frame graph hands a layer when it draws.

A layer owns its parameters, its GLSL files (``shaders/<its folder>/``) and its passes, in
three stages:

- ``prepare(graph)``: once, when its parameters change (tables, textures: may be cached);
- ``update(state)``: when the time or the place changes (light directions, irradiances);
- ``draw(frame)``: every frame, for one camera, into the frame graph's float target.

Layers of the ``"space"`` stage draw light from beyond the atmosphere (the Sun's and the
Moon's disks, later the stars) additively and unattenuated; layers of the ``"volume"``
stage (the atmosphere, later clouds and fog) composite over what lies behind them: they
read it from ``frame.behind`` and write ``behind * transmittance + in-scattered light`` over
their own segment of each ray. A layer never edits another.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from skydome.errors import ParameterError
from skydome.render.cameras import Camera

STAGES = ("space", "volume")


@dataclass(frozen=True)
class SpectralBasis:
    """How spectral values become a frame's four channels.

    ``to_output`` (4, N) takes N transfer values (per unit of the tabulated solar spectral
    irradiance, at ``wavelengths_nm``) to the output channels: (R, G, B, scotopic) in cd/m^2
    for ``output="rgbs"`` (``spectral_to_rgbs_matrix``), or the 4 wavelengths themselves for
    ``output="spectral"`` (the identity). Every layer of one graph uses the same basis, the
    atmosphere's when it has one.
    """

    wavelengths_nm: np.ndarray
    to_output: np.ndarray
    output: str = "rgbs"

    @classmethod
    def for_wavelengths(cls, wavelengths_nm, output: str = "rgbs") -> SpectralBasis:
        from skydome.atmosphere.precompute import conversion_matrix

        wl = np.asarray(wavelengths_nm, dtype=np.float64)
        return cls(wl, conversion_matrix(wl, output), output)

    @property
    def groups(self) -> int:
        return len(self.wavelengths_nm) // 4

    def group_matrices(self) -> list[float]:
        """``to_output`` as one GLSL mat4 per group of 4 wavelengths (column j = wavelength
        j of the group), flattened for a ``uniform mat4 u_spectral_to_rgbs[NUM_GROUPS]``."""
        m = self.to_output
        return np.concatenate(
            [m[:, 4 * g : 4 * g + 4].T.ravel() for g in range(self.groups)]
        ).tolist()

    def colour(self, relative_spectrum) -> np.ndarray:
        """Output channels per unit luminance of light with this spectral shape relative to
        the solar spectrum (e.g. the Moon's albedo): for ``rgbs``, RGB with Y = 1 and the
        scotopic-to-photopic ratio; for ``spectral``, the shape itself per unit luminance."""
        from skydome.atmosphere.precompute import conversion_matrix
        from skydome.spectra import SRGB_LUMINANCE

        f = np.asarray(relative_spectrum, dtype=np.float64)
        rgbs = conversion_matrix(self.wavelengths_nm, "rgbs") @ f
        y = float(SRGB_LUMINANCE @ rgbs[:3])
        if not y > 0:
            raise ParameterError("a light's spectrum must have a positive luminance")
        return (self.to_output @ f) / y


@dataclass
class DrawContext:
    """What a layer's ``draw`` gets for one tile of one frame.

    ``fbo``: the target, viewport set to the tile; ``behind``: for a volume layer, the
    texture (same size, GL rows) of the light arriving from behind it, else None;
    ``uniforms``: the camera's and the tile's (``u_resolution``, ``u_tile_offset``, ...);
    ``textures``: per-pixel inputs of this tile (``u_direction_map`` for a
    DirectionsCamera); ``altitude_m``: the camera's height above the ground.
    ``behind_smooth``: for the first volume layer when it ``merges_smooth``, the smooth
    space layers' light at a reduced resolution (read it with ``common/behind.glsl``'s
    ``light_behind`` compiled with BEHIND_SMOOTH, uniform ``u_smooth_map``), else None.
    """

    ctx: object
    camera: Camera
    frame_size: tuple[int, int]
    tile: tuple[int, int, int, int]
    fbo: object
    uniforms: dict
    textures: dict
    altitude_m: float
    basis: SpectralBasis
    behind: object = None
    behind_smooth: object = None
    smooth_map: tuple = (0.0, 0.0, 0.0, 0.0)


class Layer:
    """Base class of the scene's layers (see the module docstring).

    Subclasses set ``name`` and ``stage`` and implement ``draw``; ``prepare``, ``update``
    and ``release`` are optional. ``enabled = False`` leaves a layer out of the frame.
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

    def __init__(self, *, enabled: bool = True):
        self.enabled = bool(enabled)
        self.graph = None
        self._passes: dict[tuple, object] = {}

    def full_screen_pass(self, ctx, shader: str, camera: Camera, defines: dict | None = None):
        """The layer's pass ``shader`` compiled for ``camera``'s model with ``defines``, once
        per combination (kept until :meth:`release`)."""
        from skydome.gpu import FullscreenPass

        defines = {**(defines or {}), "CAMERA_MODEL": camera.model}
        key = (shader, tuple(sorted(defines.items())))
        if key not in self._passes:
            self._passes[key] = FullscreenPass(ctx, shader, defines)
        return self._passes[key]

    def prepare(self, graph) -> None:
        """Create GPU resources (called once, by the graph, before the first draw)."""
        self.graph = graph

    def update(self, state) -> None:
        """Take a new SkyState (the time or the place changed)."""

    @staticmethod
    def draw_small(
        frame: DrawContext, fpass, uniforms: dict, textures: dict, direction, radius_rad
    ):
        """Draw ``fpass`` only over the pixels that can see a disk of angular radius
        ``radius_rad`` around ``direction`` (a scissor rectangle from the camera's inverse
        mapping, render.cameras.disk_scissor): a full-screen pass costs every pixel on a
        CPU rasterizer even where it writes nothing."""
        from skydome.render.cameras import disk_scissor

        w, h = frame.frame_size
        x0, y0, tw, th = frame.tile
        rects = disk_scissor(frame.camera, w, h, direction, radius_rad)
        if rects is None:
            fpass.draw(frame.fbo, uniforms, textures)
            return
        try:
            for rx, ry, rw, rh in rects:
                # In the tile's own pixels.
                ax, ay = max(rx - x0, 0), max(ry - y0, 0)
                bx, by = min(rx + rw - x0, tw), min(ry + rh - y0, th)
                if bx > ax and by > ay:
                    frame.fbo.scissor = (ax, ay, bx - ax, by - ay)
                    fpass.draw(frame.fbo, uniforms, textures)
        finally:
            frame.fbo.scissor = None

    def inputs(self, frame: DrawContext) -> dict:
        """Per-pixel textures this layer provides to the volume layers of this tile before
        any of them draws (sampler name -> texture, e.g. the clouds' shadow lengths for the
        atmosphere's light shafts, ``u_shadow_map``); called for the volume layers only."""
        return {}

    def draw(self, frame: DrawContext) -> None:
        raise NotImplementedError

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
