"""A pass that draws point sources (stars, planets) into a frame, conserving their light.

Each source is an instanced quad (``shaders/celestial/point_sources_vs.glsl``) aligned to
whole frame pixels and reaching at least 4 sigma from the source's position in every
direction; the fragment stage (``shaders/celestial/point_sources.glsl``) gives each pixel
the integral of a Gaussian PSF over that pixel, divided by the PSF's integral over the whole
quad, so that a source's pixel weights sum to 1 exactly. A pixel's radiance is the source's
illuminance times its weight over the pixel's own solid angle; the flux of the image
(radiance x pixel solid angle, summed) is therefore the source's illuminance at every
resolution and field of view (``render.projection.pixel_solid_angle`` gives the solid
angles the shader uses).

Frames drawn in tiles: each tile draws every quad clipped to its own pixels, so a source on
a tile border comes out whole. Equirect frames draw a second copy of the sources near the
seam, shifted by the frame width; cubemap strips draw a source on the extended plane of each
face near it, each copy writing only its own face's pixels. Light that falls outside the
frame (off a perspective frame's edge, beyond a fisheye's horizon circle, above an equirect
frame's top row within 4 sigma of the zenith) is lost, as it would be on a sensor.

The PSF's sigma is given in frame pixels (stars look alike at every resolution); a seeing
disk (FWHM in arcsec) adds in quadrature, turned into pixels with the frame's scale at the
source along x and along y.
"""

from __future__ import annotations

import math

import moderngl
import numpy as np

from skydome.errors import ParameterError
from skydome.gpu import build_program
from skydome.render.cameras import CubemapCamera, EquirectCamera
from skydome.render.projection import has_projection

VERTEX_SHADER = "celestial/point_sources_vs.glsl"
FRAGMENT_SHADER = "celestial/point_sources.glsl"
#: Occluding disks one draw can take.
MAX_OCCLUDERS = 4
#: FWHM of a Gaussian over its sigma: 2 sqrt(2 ln 2).
FWHM_PER_SIGMA = 2.0 * math.sqrt(2.0 * math.log(2.0))
_ARCSEC = math.pi / 648_000.0
_STRIDE = 7  # floats per source: direction (3), channels (4)


def _set_uniforms(program, uniforms: dict) -> None:
    """Uniforms by name (unknown or optimised-out names ignored), as FullscreenPass does."""
    for name, value in uniforms.items():
        member = program.get(name, None)
        if member is None or isinstance(member, moderngl.Attribute):
            continue
        if isinstance(value, (list, tuple, np.ndarray)) and np.size(value) > 1:
            n = member.array_length * member.dimension
            member.write(np.asarray(value, dtype="f4").ravel()[:n].tobytes())
        else:
            member.value = value


class PointSources:
    """Draws point sources into a frame graph's tile (see the module docstring).

    One instance may serve several layers; its GPU objects are kept between draws (one
    program per camera model, one growing instance buffer) until :meth:`release`.
    """

    def __init__(self, ctx):
        self.ctx = ctx
        self._programs: dict[int, tuple] = {}  # camera model -> (program, vao)
        self._buffer = None
        self._capacity = 0

    # ------------------------------------------------------------------ resources

    def _ensure_buffer(self, n: int) -> None:
        if n <= self._capacity:
            return
        capacity = max(1024, 1 << int(math.ceil(math.log2(n))))
        for _, vao in self._programs.values():
            vao.release()
        if self._buffer is not None:
            self._buffer.release()
        self._buffer = self.ctx.buffer(reserve=capacity * _STRIDE * 4, dynamic=True)
        self._capacity = capacity
        self._programs = {
            model: (prog, self._vertex_array(prog)) for model, (prog, _) in self._programs.items()
        }

    def _vertex_array(self, program):
        return self.ctx.vertex_array(
            program, [(self._buffer, "3f 4f/i", "in_direction", "in_channels")]
        )

    def _program(self, model: int):
        if model not in self._programs:
            defines = {"CAMERA_MODEL": model, "MAX_OCCLUDERS": MAX_OCCLUDERS}
            prog = build_program(self.ctx, FRAGMENT_SHADER, defines, vertex=VERTEX_SHADER)
            self._programs[model] = (prog, self._vertex_array(prog))
        return self._programs[model]

    # ------------------------------------------------------------------ drawing

    def draw(
        self,
        frame,
        directions,
        channels,
        *,
        psf_sigma_px: float = 0.8,
        seeing_fwhm_arcsec: float = 0.0,
        occluder=None,
    ) -> None:
        """Add the sources' light to ``frame`` (a ``scene.layer.DrawContext``).

        Args:
            frame: the tile to draw into (its camera, uniforms, tile and framebuffer).
            directions: (N, 3) apparent (refracted) unit ENU directions.
            channels: (N, 4) each source's illuminance in the frame's output channels
                (lux-equivalent: for ``rgbs``, the colour per unit luminance from
                ``frame.basis.colour(...)`` times the illuminance in lux).
            psf_sigma_px: the PSF's Gaussian sigma in frame pixels (0.05-32).
            seeing_fwhm_arcsec: the seeing disk's FWHM (arcsec, 0-3600), added in
                quadrature with the frame's scale at each source.
            occluder: None or a list of up to MAX_OCCLUDERS ``(direction, radius_rad)``
                disks in front of the sources (apparent unit ENU centre, angular radius in
                radians) whose pixels get none of the sources' light.

        A ``DirectionsCamera`` (no forward mapping from a direction to its pixel) draws
        nothing: the call returns quietly.
        """
        sigma = float(psf_sigma_px)
        if not 0.05 <= sigma <= 32.0:
            raise ParameterError(f"psf_sigma_px = {psf_sigma_px!r} must lie in [0.05, 32] pixels")
        seeing = float(seeing_fwhm_arcsec)
        if not 0.0 <= seeing <= 3600.0:
            raise ParameterError(
                f"seeing_fwhm_arcsec = {seeing_fwhm_arcsec!r} must lie in [0, 3600] arcsec"
            )
        d = np.asarray(directions, dtype=np.float64)
        c = np.asarray(channels, dtype=np.float64)
        if d.ndim != 2 or d.shape[1] != 3 or c.shape != (d.shape[0], 4):
            raise ParameterError(
                f"directions must be (N, 3) and channels (N, 4), got {d.shape} and {c.shape}"
            )
        if not (np.all(np.isfinite(d)) and np.all(np.isfinite(c))):
            raise ParameterError("point-source directions and channels must be finite")
        disks = self._occluders(occluder)
        camera = frame.camera
        n = d.shape[0]
        if n == 0 or not has_projection(camera):
            return
        self._ensure_buffer(n)
        data = np.empty((n, _STRIDE), np.float32)
        data[:, :3] = d
        data[:, 3:] = c
        self._buffer.write(data.tobytes())
        program, vao = self._program(camera.model)
        x0, y0, tw, th = frame.tile
        occ = np.zeros((MAX_OCCLUDERS, 4))
        occ[: len(disks)] = disks
        uniforms = {
            **frame.uniforms,
            "u_tile_size": (float(tw), float(th)),
            "u_psf_sigma_px": sigma,
            "u_seeing_sigma_rad": seeing * _ARCSEC / FWHM_PER_SIGMA,
            "u_occluders": occ.ravel().tolist(),
            "u_num_occluders": len(disks),
        }
        _set_uniforms(program, uniforms)
        frame.fbo.use()
        if isinstance(camera, CubemapCamera):
            copies = range(6)  # each face's extended plane
        elif isinstance(camera, EquirectCamera):
            copies = range(2)  # the sources themselves, then those near the seam shifted
        else:
            copies = range(1)
        for copy in copies:
            if "u_copy" in program:
                program["u_copy"].value = copy
            vao.render(moderngl.TRIANGLES, vertices=6, instances=n)

    @staticmethod
    def _occluders(occluder) -> np.ndarray:
        if occluder is None:
            return np.zeros((0, 4))
        disks = list(occluder)
        if len(disks) > MAX_OCCLUDERS:
            raise ParameterError(
                f"{len(disks)} occluders given; a draw takes at most {MAX_OCCLUDERS}"
            )
        out = np.zeros((len(disks), 4))
        for i, disk in enumerate(disks):
            direction, radius = disk
            v = np.asarray(direction, dtype=np.float64).reshape(-1)
            norm = float(np.linalg.norm(v)) if v.shape == (3,) else 0.0
            r = float(radius)
            if not norm > 0 or not 0.0 <= r <= math.pi:
                raise ParameterError(
                    f"occluder {i}: needs a non-zero 3-vector and a radius in [0, pi] rad, "
                    f"got {direction!r}, {radius!r}"
                )
            out[i, :3] = v / norm
            out[i, 3] = math.cos(r)
        return out

    def release(self) -> None:
        """Free the programs and the instance buffer."""
        for prog, vao in self._programs.values():
            vao.release()
            prog.release()
        self._programs.clear()
        if self._buffer is not None:
            self._buffer.release()
        self._buffer = None
        self._capacity = 0
