"""A pass that draws point sources (stars, planets) into a frame, conserving their light.

Each source is an instanced quad (``shaders/celestial/point_sources_vs.glsl``) aligned to
whole frame pixels and reaching at least ceil(3 sigma) pixels beyond the source's pixel in
every direction; the fragment stage (``shaders/celestial/point_sources.glsl``) gives each
pixel the integral of a Gaussian PSF over that pixel, divided by the PSF's integral over the
whole quad, so that a source's pixel weights sum to 1 exactly. A pixel's radiance is the
source's illuminance times its weight over the pixel's own solid angle; the flux of the image
(radiance x pixel solid angle, summed) is therefore the source's illuminance at every
resolution and field of view (``render.projection.pixel_solid_angle`` gives the solid
angles the shader uses).

PSF truncation: the quad holds the Gaussian out to >= 3 sigma from the source along x and
along y (a square box). The light of a 2D Gaussian outside a box of half side 3 sigma is
1 - erf(3 / sqrt 2)^2 = 0.54 %; the normalisation over the quad puts it back into the core,
so the flux stays exact and the image's variance is that of the truncated Gaussian (at most
2.7 % below sigma^2, for a quad edge exactly at 3 sigma; the quad's edges lie 3-4 sigma out
for sigma = 0.8 px).

The CPU side (float64, ``render.projection``) places every source: its frame position, its
PSF's sigma in pixels (with the seeing), its quad; it uploads only the quads that touch the
tile being drawn (a source behind a perspective camera, below a fisheye's horizon or off the
tile costs nothing on the GPU). Frames drawn in tiles: each tile draws the quads clipped to
its own pixels, so a source on a tile border comes out whole. Equirect frames add a copy of
each source near the seam, shifted by the frame width, as one more instance; cubemap strips
draw a source on the extended plane of each face near it (one instance per face), each copy
writing only its own face's pixels. Light that falls outside the frame (off a perspective
frame's edge, beyond a fisheye's horizon circle, above an equirect frame's top row within
3 sigma of the zenith) is lost, as it would be on a sensor.

Cost on a CPU rasterizer (llvmpipe), where every pixel of a quad and every primitive
count: a quad of at most TABLE_SIZE pixels a side (the default sigma of 0.8 px gives 7 x 7)
gets its 8 column and 8 row weights from the vertex stage, so that its pixels compute no
erf at all (``WEIGHT_TABLE`` 1), and is drawn as one point sprite where its square lies
inside the tile (two triangles cost about 2.5 times as much); larger quads integrate the
PSF per pixel (A&S 7.1.26, from the normal's tails, without branches). A pixel's solid
angle comes from its frame position in closed form. Occluding disks (the Moon in front of
the stars) cost a per-pixel test only for the quads that may touch one (``OCCLUDERS`` 1);
the rest never compute their pixels' directions. With a ``cache_key``, drawing the same
sources into the same camera, frame and tile again re-issues the last draws from the
instance buffers already on the GPU.

The PSF's sigma is given in frame pixels (stars look alike at every resolution); a seeing
disk (FWHM in arcsec) adds in quadrature, turned into pixels with the frame's scale at the
source along x and along y.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import moderngl
import numpy as np

from skydome.core.cameras import (
    CameraInputs,
    CubemapCamera,
    EquirectCamera,
    FisheyeCamera,
    PerspectiveCamera,
)
from skydome.errors import ParameterError
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.passes import ShaderProgram
from skydome.physics.constants import ARCSEC_RAD

VERTEX_SHADER = "celestial/point_sources_vs.glsl"
FRAGMENT_SHADER = "celestial/point_sources.glsl"
#: Occluding disks one draw can take.
MAX_OCCLUDERS = 4
#: FWHM of a Gaussian over its sigma: 2 sqrt(2 ln 2).
FWHM_PER_SIGMA = 2.0 * math.sqrt(2.0 * math.log(2.0))
#: The quad reaches ceil(PSF_EXTENT_SIGMA x sigma) pixels beyond the source's pixel.
PSF_EXTENT_SIGMA = 3.0
#: Largest PSF sigma in pixels (bounds the quad: a seeing disk near an equirect pole).
MAX_SIGMA_PX = 64.0
#: Quads up to this many pixels a side get their weights per column and row from the
#: vertex stage, once per quad, instead of per pixel.
TABLE_SIZE = 8
_STEP_RAD = 1e-3  # finite-difference step of the seeing's pixel scale
# Floats per instance: the quad's corners (4), the source's position from the lower-left
# corner and 1 / sigma (4), the cube face (1), the channels (4).
_STRIDE = 13
_FORMAT = "4f 4f 1f 4f/i"
_ATTRIBUTES = ("in_rect", "in_centre_inv_sigma", "in_face", "in_channels")
# Program variants, one instance buffer each: (near an occluder, weights from the table,
# drawn as a point sprite). A sprite (one vertex, one primitive; two triangles cost llvmpipe
# about 2.5x as much) needs its square whole inside the tile: GL drops a point whose centre
# leaves the viewport, so quads that reach beyond the tile's edge stay triangles.
_VARIANTS = (
    (False, True, True),
    (False, True, False),
    (False, False, False),
    (True, True, False),
    (True, False, False),
)
# Cube faces in camera.glsl's order: the axis, and the face-plane coordinates (p.x, p.y) of a
# direction q on the plane at unit distance (the inverse of cube_face_direction).
_CUBE_AXES = np.array(
    [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64
)


def _cube_plane(q: np.ndarray, face: int) -> tuple[np.ndarray, np.ndarray]:
    x, y, z = q[:, 0], q[:, 1], q[:, 2]
    return [(-y, z), (y, z), (x, z), (-x, z), (-x, y), (x, y)][face]


def _max_rad_per_px(camera, w: float, h: float) -> float:
    """An upper bound on the angle (rad) one pixel spans anywhere in the frame."""
    if isinstance(camera, PerspectiveCamera):
        return 2.0 * math.tan(math.radians(camera.fov_deg) / 2.0) / w  # at the centre
    if isinstance(camera, FisheyeCamera):
        return math.pi / min(w, h)  # radially; across, sin(z) / z times that
    if isinstance(camera, EquirectCamera):
        return max(2.0 * math.pi / w, math.pi / h)
    return 2.0 / h  # a cube face's centre (its extended plane: smaller beyond)


@dataclass(frozen=True)
class PointInputs(ShaderInputs):
    """``celestial/point_sources*.glsl``: the tile's size (px), the disks hiding the sources
    (centre xyz, angular radius; up to MAX_OCCLUDERS), their count, the sprites' size (px)."""

    u_tile_size: tuple[float, float]
    u_occluders: list[float]
    u_num_occluders: int
    u_point_size: float


class PointSources:
    """Draws point sources into a frame graph's tile (see the module docstring).

    One instance may serve several layers; its GPU objects are kept between draws (one
    program per camera model and occluder variant, two growing instance buffers) until
    :meth:`release`.
    """

    def __init__(self, ctx):
        self.ctx = ctx
        self._programs: dict[tuple, object] = {}  # (camera model, variant) -> program
        self._buffers: list = [None] * len(_VARIANTS)
        self._capacity = [0] * len(_VARIANTS)
        self._vaos: dict[tuple, object] = {}  # (camera model, variant) -> vao
        self.instances_drawn = 0  # quads drawn by the last draw (all variants)
        self._plan: tuple | None = None  # (cache key, the draws) of the last draw
        try:  # sprites up to the driver's largest point (GL guarantees only 1 px)
            self._max_point_px = float(ctx.info["GL_POINT_SIZE_RANGE"][1])
        except (KeyError, TypeError, IndexError, AttributeError):
            self._max_point_px = 1.0

    # ------------------------------------------------------------------ resources

    def _program(self, model: int, slot: int):
        key = (model, slot)
        if key not in self._programs:
            occluded, tabled, sprite = _VARIANTS[slot]
            defines = {
                "CAMERA_MODEL": model,
                "MAX_OCCLUDERS": MAX_OCCLUDERS,
                "OCCLUDERS": int(occluded),
                "WEIGHT_TABLE": int(tabled),
                "SPRITE": int(sprite),
            }
            self._programs[key] = ShaderProgram(
                self.ctx, FRAGMENT_SHADER, defines, inputs=(CameraInputs, PointInputs),
                vertex=VERTEX_SHADER,
            )  # fmt: skip
        return self._programs[key]

    def _upload(self, slot: int, data: np.ndarray) -> None:
        n = len(data)
        if n > self._capacity[slot]:
            capacity = max(1024, 1 << int(math.ceil(math.log2(n))))
            for key in [k for k in self._vaos if k[1] == slot]:
                self._vaos.pop(key).release()
            if self._buffers[slot] is not None:
                self._buffers[slot].release()
            self._buffers[slot] = self.ctx.buffer(reserve=capacity * _STRIDE * 4, dynamic=True)
            self._capacity[slot] = capacity
        self._buffers[slot].write(np.ascontiguousarray(data, dtype=np.float32).tobytes())

    def _vao(self, model: int, slot: int):
        key = (model, slot)
        if key not in self._vaos:
            program = self._program(model, slot).program
            # The attributes a variant does not use are skipped (padding in the format).
            fmt, names = [], []
            for part, name in zip(_FORMAT.split(), _ATTRIBUTES, strict=True):
                used = name in program
                fmt.append(part if used else f"{4 * int(part[0])}x" + part[2:])
                names += [name] if used else []
            if _VARIANTS[slot][2]:  # sprites: one vertex each, not instanced
                fmt[-1] = fmt[-1].replace("/i", "")
            self._vaos[key] = self.ctx.vertex_array(
                program, [(self._buffers[slot], " ".join(fmt), *names)]
            )
        return self._vaos[key]

    # ------------------------------------------------------------------ placing

    @staticmethod
    def _in_view(camera, d: np.ndarray, w: int, h: int, bound: float) -> np.ndarray:
        """Indices of the unit directions ``d`` that may light the frame, by one dot product:
        for a perspective camera, those within the frame's half-diagonal angle plus a quad
        of ``bound`` pixels (each pixel spans at most the centre's angle); for a fisheye,
        those above the horizon; every direction for the other models."""
        if isinstance(camera, PerspectiveCamera):
            t = math.tan(math.radians(camera.fov_deg) / 2.0)
            diagonal = math.atan(t * math.hypot(1.0, h / w))
            margin = (bound + 2.0) * math.sqrt(2.0) * _max_rad_per_px(camera, w, h)
            cone = diagonal + margin
            if cone < 0.5 * math.pi:
                return np.flatnonzero(d @ camera.basis()[:, 2] > math.cos(cone))
        if isinstance(camera, FisheyeCamera):
            return np.flatnonzero(d[:, 2] >= 0.0)
        return np.arange(len(d))

    @staticmethod
    def _positions(camera, d: np.ndarray, w: int, h: int):
        """Frame positions of every copy of the sources: (source index, x, y, face, seen);
        face -1 writes any pixel; for a cubemap one copy per face plane near the source."""
        n = len(d)
        if not isinstance(camera, CubemapCamera):
            x, y, seen = camera.project(d, w, h)
            return np.arange(n), x, y, np.full(n, -1.0), seen
        idx, xs, ys, faces = [], [], [], []
        side = float(h)
        for f in range(6):
            m = d @ _CUBE_AXES[f]
            near = np.flatnonzero(m >= 0.5)  # within 60 deg of the face's axis
            px, py = _cube_plane(d[near] / m[near, None], f)
            idx.append(near)
            xs.append(f * side + (px + 1.0) * 0.5 * side)
            ys.append((py + 1.0) * 0.5 * side)
            faces.append(np.full(len(near), float(f)))
        idx = np.concatenate(idx)
        return idx, np.concatenate(xs), np.concatenate(ys), np.concatenate(faces), None

    @staticmethod
    def _project_copy(camera, d: np.ndarray, faces: np.ndarray, w: int, h: int):
        """Frame positions of directions ``d`` on the planes of ``faces`` (cubemap) or by
        the camera's own mapping."""
        if not isinstance(camera, CubemapCamera):
            x, y, _ = camera.project(d, w, h)
            return x, y
        side = float(h)
        x, y = np.empty(len(d)), np.empty(len(d))
        for f in range(6):
            sel = faces == f
            m = d[sel] @ _CUBE_AXES[f]
            px, py = _cube_plane(d[sel] / m[:, None], f)
            x[sel] = f * side + (px + 1.0) * 0.5 * side
            y[sel] = (py + 1.0) * 0.5 * side
        return x, y

    def _sigmas(self, camera, d, faces, x, y, w, h, sigma_px, seeing_sigma_rad):
        """(N, 2) PSF sigma along x and y (pixels): the PSF's own, and the seeing's angle
        through the mapping's pixel scale at the source along two tangent directions."""
        sigma = np.full((len(d), 2), sigma_px)
        if seeing_sigma_rad > 0.0 and len(d):
            ref = np.where(np.abs(d[:, 2:3]) < 0.9, [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])
            t1 = np.cross(ref, d)
            t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
            t2 = np.cross(d, t1)
            jac = np.zeros((len(d), 2))
            for t in (t1, t2):
                q = d + _STEP_RAD * t
                qx, qy = self._project_copy(
                    camera, q / np.linalg.norm(q, axis=1)[:, None], faces, w, h
                )
                dx, dy = qx - x, qy - y
                if isinstance(camera, EquirectCamera):
                    dx -= w * np.round(dx / w)  # across the seam the difference jumps by w
                jac[:, 0] += dx * dx
                jac[:, 1] += dy * dy
            # Marginal variances of an isotropic Gaussian of sigma s mapped by J = [d1 d2]/H:
            # (J J^T)_xx s^2 and (J J^T)_yy s^2 (the correlation is dropped: the quad's PSF
            # is separable; the weights still sum to 1).
            sigma = np.sqrt(sigma * sigma + jac / _STEP_RAD**2 * seeing_sigma_rad**2)
        return np.clip(sigma, 1e-3, MAX_SIGMA_PX)

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
        cache_key=None,
    ) -> None:
        """Add the sources' light to ``frame`` (a ``skydome.core.layer.DrawContext``).

        Args:
            frame: the tile to draw into (its camera, frame size, tile and framebuffer).
            directions: (N, 3) apparent (refracted) unit ENU directions.
            channels: (N, 4) each source's illuminance in the frame's output channels
                (lux-equivalent: for ``rgbs``, the colour per unit luminance from
                ``frame.basis.colour(...)`` times the illuminance in lux).
            psf_sigma_px: the PSF's Gaussian sigma in frame pixels (0.05-32): in a
                supersampled frame, pixels of the frame asked for (``frame.pixel_scale``
                drawn pixels each), so that its stars look as at one ray a pixel.
            seeing_fwhm_arcsec: the seeing disk's FWHM (arcsec, 0-3600), added in
                quadrature with the frame's scale at each source.
            occluder: None or a list of up to MAX_OCCLUDERS ``(direction, radius_rad)``
                disks in front of the sources (apparent unit ENU centre, angular radius in
                radians) whose pixels get none of the sources' light.
            cache_key: None, or a value the caller changes whenever it changes
                ``directions`` or ``channels``: a draw with the previous draw's key, camera,
                frame, tile and parameters re-issues that draw from the instance buffers
                already on the GPU (no placement, no upload).

        A ``DirectionsCamera`` (no forward mapping from a direction to its pixel) draws
        nothing: the call returns quietly.
        """
        sigma = float(psf_sigma_px)
        if not 0.05 <= sigma <= 32.0:
            raise ParameterError(f"psf_sigma_px = {psf_sigma_px!r} must lie in [0.05, 32] pixels")
        if frame is not None:
            sigma *= frame.pixel_scale  # in drawn pixels
        seeing = float(seeing_fwhm_arcsec)
        if not 0.0 <= seeing <= 3600.0:
            raise ParameterError(
                f"seeing_fwhm_arcsec = {seeing_fwhm_arcsec!r} must lie in [0, 3600] arcsec"
            )
        disks = self._occluders(occluder)
        key = None
        if cache_key is not None and frame is not None:
            key = (cache_key, frame.camera, tuple(frame.frame_size), tuple(frame.tile))
            key += (sigma, seeing, disks.tobytes())
            if self._plan is not None and self._plan[0] == key:
                self._render(frame, disks, self._plan[1])  # the same sources as last time
                return
        d = np.asarray(directions, dtype=np.float64)
        c = np.asarray(channels, dtype=np.float64)
        if d.ndim != 2 or d.shape[1] != 3 or c.shape != (d.shape[0], 4):
            raise ParameterError(
                f"directions must be (N, 3) and channels (N, 4), got {d.shape} and {c.shape}"
            )
        if not (np.all(np.isfinite(d)) and np.all(np.isfinite(c))):
            raise ParameterError("point-source directions and channels must be finite")
        length = np.sqrt(np.einsum("ij,ij->i", d, d))
        if not np.all(length > 0.0):
            raise ParameterError("point-source directions must be non-zero vectors")
        d = d / length[:, None]
        camera = frame.camera
        self._plan = None
        self.instances_drawn = 0
        if d.shape[0] == 0 or not camera.has_projection:
            return
        w, h = frame.frame_size
        x0, y0, tw, th = frame.tile
        seeing_sigma_rad = seeing * ARCSEC_RAD / FWHM_PER_SIGMA
        # Every copy's frame position (float64); then a first cull with the largest quad the
        # PSF can have (its own sigma, or MAX_SIGMA_PX with a seeing disk), so that the
        # rest of the work is done for the sources near the tile only.
        bound = math.ceil(PSF_EXTENT_SIGMA * (sigma if seeing_sigma_rad == 0.0 else MAX_SIGMA_PX))
        ahead = self._in_view(camera, d, w, h, bound)
        # (rows gathered by np.take: 4-8x a fancy index of an (N, 3) array)
        idx, x, y, faces, seen = self._positions(camera, np.take(d, ahead, axis=0), w, h)
        idx = ahead[idx]
        if isinstance(camera, EquirectCamera):
            # The seam: a quad that may cross x = 0 or x = w gets a copy one frame width
            # over (copies whose quad stays clear of the frame are culled with the rest).
            left = x - bound - 1.0 < 0.0
            right = ~left & (x + bound + 1.0 > w)
            extra = np.flatnonzero(left | right)
            idx, y = np.concatenate([idx, idx[extra]]), np.concatenate([y, y[extra]])
            x = np.concatenate([x, x[extra] + np.where(left[extra], float(w), -float(w))])
            faces = np.concatenate([faces, faces[extra]])
            if seen is not None:
                seen = np.concatenate([seen, seen[extra]])
        cx, cy = np.floor(x), np.floor(y)
        near = (cx + (1.0 + bound) > x0) & (cx - bound < x0 + tw)
        near &= (cy + (1.0 + bound) > y0) & (cy - bound < y0 + th)
        if seen is not None:  # behind a perspective camera, below a fisheye's horizon
            near &= seen
        near = np.flatnonzero(near)
        idx, x, y, faces, cx, cy = (a[near] for a in (idx, x, y, faces, cx, cy))
        du = np.take(d, idx, axis=0)
        sig = self._sigmas(camera, du, faces, x, y, w, h, sigma, seeing_sigma_rad)
        hx, hy = np.ceil(PSF_EXTENT_SIGMA * sig[:, 0]), np.ceil(PSF_EXTENT_SIGMA * sig[:, 1])
        # The quad, in tile pixels: whole pixels from the source's pixel +- half.
        cx, cy = cx - x0, cy - y0
        keep = (cx + hx + 1.0 > 0.0) & (cx - hx < tw) & (cy + hy + 1.0 > 0.0) & (cy - hy < th)
        if isinstance(camera, CubemapCamera):
            # A face's copy draws only if its quad reaches the face's own pixels.
            f0 = faces * h
            keep &= (x + hx + 1.0 >= f0) & (x - hx - 1.0 <= f0 + h)
        keep = np.flatnonzero(keep)
        if keep.size == 0:
            if key is not None:
                self._plan = (key, [])
            return
        cx, cy, hx, hy = cx[keep], cy[keep], hx[keep], hy[keep]
        data = np.empty((keep.size, _STRIDE), np.float64)
        data[:, 0], data[:, 1], data[:, 2], data[:, 3] = (
            cx - hx,
            cy - hy,
            cx + hx + 1.0,
            cy + hy + 1.0,
        )
        # The source's position from the quad's corner (small numbers: float32 keeps them to
        # 1e-6 px, and a seam copy gets the very same weights as the source).
        data[:, 4], data[:, 5] = x[keep] - x0 - data[:, 0], y[keep] - y0 - data[:, 1]
        data[:, 6:8] = 1.0 / np.take(sig, keep, axis=0)
        data[:, 8] = faces[keep]
        data[:, 9:13] = np.take(c, idx[keep], axis=0)
        table = (hx <= (TABLE_SIZE - 1) // 2) & (hy <= (TABLE_SIZE - 1) // 2)
        # Quads that may touch an occluder: within its radius plus the quad's half diagonal.
        near = np.zeros(keep.size, bool)
        if len(disks):
            reach = (float(max(hx.max(), hy.max())) + 1.0) * math.sqrt(2.0)
            reach *= _max_rad_per_px(camera, w, h)
            dk = np.take(du, keep, axis=0)
            for u, cos_r in zip(disks[:, :3], disks[:, 3], strict=True):
                r = math.acos(min(max(float(cos_r), -1.0), 1.0))
                near |= dk @ u > math.cos(min(r + reach, math.pi))
        # Sprites: the square of side 2 max(hx, hy) + 1 around the source's pixel (the
        # table's weights are 0 beyond the quad), whole inside the tile.
        hs = np.maximum(hx, hy)
        side = 2.0 * hs + 1.0
        sprite = table & (cx - hs >= 0.0) & (cy - hs >= 0.0)
        sprite &= (cx + hs + 1.0 <= tw) & (cy + hs + 1.0 <= th) & (side <= self._max_point_px)
        plan = []  # (slot, number of instances, sprite runs (size, first, count))
        for slot, (occluded, tabled, as_sprite) in enumerate(_VARIANTS):
            sel = (near == occluded) & (table == tabled) & (sprite == as_sprite)
            if not np.any(sel):
                continue
            part, sizes = data[sel], side[sel]
            runs = ()
            if as_sprite:
                if np.any(sizes != sizes[0]):
                    order = np.argsort(sizes, kind="stable")
                    part, sizes = part[order], sizes[order]
                # One draw per sprite size (glPointSize), the runs of the sorted buffer.
                cuts = np.r_[0, np.flatnonzero(np.diff(sizes)) + 1, len(sizes)]
                runs = tuple(
                    (float(sizes[a]), int(a), int(b - a))
                    for a, b in zip(cuts[:-1], cuts[1:], strict=True)
                )
            self._upload(slot, part)
            plan.append((slot, len(part), runs))
        self._render(frame, disks, plan)
        if key is not None:
            self._plan = (key, plan)

    def _render(self, frame, disks: np.ndarray, plan: list) -> None:
        """Issue the draws of ``plan`` from the instance buffers."""
        occ = np.zeros((MAX_OCCLUDERS, 4))
        occ[: len(disks)] = disks
        _, _, tw, th = frame.tile
        inputs = PointInputs(
            u_tile_size=(float(tw), float(th)),
            u_occluders=occ.ravel().tolist(),
            u_num_occluders=len(disks),
            u_point_size=1.0,
        )
        frame.fbo.use()
        self.instances_drawn = 0
        for slot, count, runs in plan:
            program = self._program(frame.camera.model, slot)
            vao = self._vao(frame.camera.model, slot)
            program.apply(frame.view, inputs)
            if runs:
                old_size = self.ctx.point_size
                try:
                    for size, first, n in runs:
                        # glPointSize, and gl_PointSize in case GL_PROGRAM_POINT_SIZE is on.
                        self.ctx.point_size = size
                        program.apply(frame.view, replace(inputs, u_point_size=size))
                        vao.render(moderngl.POINTS, vertices=n, first=first)
                finally:
                    self.ctx.point_size = old_size
            else:
                vao.render(moderngl.TRIANGLES, vertices=6, instances=count)
            self.instances_drawn += count

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
        """Free the programs and the instance buffers."""
        for vao in self._vaos.values():
            vao.release()
        self._vaos.clear()
        for prog in self._programs.values():
            prog.release()
        self._programs.clear()
        for buf in self._buffers:
            if buf is not None:
                buf.release()
        self._buffers = [None] * len(_VARIANTS)
        self._capacity = [0] * len(_VARIANTS)
        self._plan = None
