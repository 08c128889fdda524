"""What every sky renderer shares: compiled passes per camera model, render targets, the
direction map of a DirectionsCamera, per-pixel input images and the read-back to a Frame."""

from __future__ import annotations

import time
import weakref

import numpy as np

from skydome.atmosphere import AtmosphereParams
from skydome.atmosphere.uniforms import M_PER_KM
from skydome.errors import ParameterError, check_range
from skydome.gpu import FullscreenPass
from skydome.render.cameras import Camera, DirectionsCamera

#: Largest camera altitude accepted (m).
MAX_ALTITUDE_M = 1e8
#: Cameras closer to the ground are raised to this height (m): float32 positions in km are
#: resolved to about 0.5 m at the planet radius.
MIN_ALTITUDE_M = 1.0


def effective_altitude_m(altitude_m: float) -> float:
    """The camera altitude (m) the renderers use: ``altitude_m`` checked, and raised to
    MIN_ALTITUDE_M when below it (frames report this value as ``info["altitude_m"]``)."""
    h = check_range("altitude", altitude_m, 0.0, MAX_ALTITUDE_M, "m")
    return max(h, MIN_ALTITUDE_M)


def camera_position_km(params: AtmosphereParams, altitude_m: float) -> tuple[float, float, float]:
    """Planet-centred camera position (km) for an altitude above the ground, ENU axes."""
    return (0.0, 0.0, (params.bottom_radius_m + effective_altitude_m(altitude_m)) / M_PER_KM)


def check_direction(name: str, direction) -> np.ndarray:
    """A finite non-zero 3-vector, normalised."""
    s = np.asarray(direction, dtype=np.float64).reshape(-1)
    n = float(np.linalg.norm(s)) if s.shape == (3,) and np.all(np.isfinite(s)) else 0.0
    if n == 0.0:
        raise ParameterError(f"{name} must be a finite non-zero 3-vector, got {direction!r}")
    return s / n


def check_sun_direction(sun_direction) -> np.ndarray:
    return check_direction("sun direction", sun_direction)


def input_image(
    name: str, image, size: tuple[int, int], scale: float = 1.0, posinf: float = 0.0
) -> np.ndarray:
    """A per-pixel input: an (H, W) float32 image (row 0 at the top) scaled by ``scale``.

    +inf becomes ``posinf`` (for a depth image 0: no scene along that ray, as values <= 0;
    for shadow lengths a length past any ray's end). NaN and -inf are refused.
    """
    w, h = size
    a = np.asarray(image, dtype=np.float64)
    if a.shape != (h, w):
        raise ParameterError(f"{name} must be a ({h}, {w}) array for this frame, got {a.shape}")
    if np.isnan(a).any() or np.isneginf(a).any():
        raise ParameterError(f"{name} must hold finite numbers or +inf (no scene), not NaN/-inf")
    return np.where(np.isposinf(a), posinf, a * scale).astype(np.float32)


def input_texture(ctx, image: np.ndarray):
    """A float32 texture (texelFetch) of one tile of a per-pixel input (H, W) or (H, W, C),
    row 0 at the top, in GL row order. The caller releases it."""
    th, tw = image.shape[:2]
    channels = 1 if image.ndim == 2 else image.shape[2]
    data = np.ascontiguousarray(image[::-1], dtype="f4")
    return ctx.texture((tw, th), channels, data.tobytes(), dtype="f4")


#: Frames larger than this on a side are drawn in tiles of this size (GL's framebuffer limit
#: is 16384 on llvmpipe and most GPUs; a tile's float targets cost 64 MB per attachment).
TILE_SIZE = 2048


def frame_tiles(width: int, height: int, tile: int = TILE_SIZE):
    """(x0, y0, w, h) of the tiles covering a frame, in GL pixel coordinates (y up)."""
    for y0 in range(0, height, tile):
        for x0 in range(0, width, tile):
            yield x0, y0, min(tile, width - x0), min(tile, height - y0)


def _release_all(passes: dict, targets: dict, owned: list) -> None:
    for p in passes.values():
        p.release()
    for texs, fbo in targets.values():
        fbo.release()
        for tex in texs:
            tex.release()
    for obj in owned:
        obj.release()
    passes.clear()
    targets.clear()
    owned.clear()


class PassRenderer:
    """Base of the renderers: subclasses give the shader file and its defines and uniforms."""

    shader = ""
    model = ""

    def __init__(self, params: AtmosphereParams, ctx):
        self.params = params
        self.ctx = ctx
        self._passes: dict[tuple, FullscreenPass] = {}
        self._targets: dict[tuple, tuple] = {}
        self._staging: dict[tuple[int, int], np.ndarray] = {}
        #: GL objects this renderer owns besides its passes and targets (released with it).
        self._owned: list = []
        # GL objects go when the renderer is released or garbage collected, not at exit (the
        # context may be gone by then).
        self._finalizer = weakref.finalize(
            self, _release_all, self._passes, self._targets, self._owned
        )
        self._finalizer.atexit = False

    def defines(self, camera: Camera) -> dict[str, object]:
        raise NotImplementedError

    def _pass(
        self, camera: Camera, extra: tuple[str, ...] = (), shader: str | None = None
    ) -> FullscreenPass:
        shader = shader or self.shader
        key = (shader, camera.model, extra)
        if key not in self._passes:
            defines = {**self.defines(camera), **{name: 1 for name in extra}}
            self._passes[key] = FullscreenPass(self.ctx, shader, defines)
        return self._passes[key]

    def _target(self, width: int, height: int, attachments: int = 1, depth: bool = False):
        key = (width, height, attachments, depth)
        if key not in self._targets:
            texs = [self.ctx.texture((width, height), 4, dtype="f4") for _ in range(attachments)]
            rb = self.ctx.depth_renderbuffer((width, height)) if depth else None
            self._targets[key] = (
                texs,
                self.ctx.framebuffer(color_attachments=texs, depth_attachment=rb),
            )
        return self._targets[key]

    def _draw(
        self,
        camera: Camera,
        w: int,
        h: int,
        uniforms: dict,
        textures: dict,
        extra: tuple[str, ...] = (),
        inputs: dict[str, np.ndarray] | None = None,
        attachments: int = 1,
        surface_pass: bool = False,
        shader: str | None = None,
    ):
        """Draw the pass for ``camera`` into a (w, h) frame; returns (arrays, milliseconds).

        ``inputs`` maps sampler names to per-pixel float32 images (H, W) or (H, W, C), row 0
        at the top, made into textures tile by tile. ``shader`` replaces the renderer's shader
        file for this draw. Arrays are float32 (h, w, 4), row 0 at the top, one per attachment.
        Frames wider or taller than TILE_SIZE are drawn tile by tile (the shaders see the
        whole frame through ``u_resolution`` and the tile's place through ``u_tile_offset``),
        so their size is bounded by memory only, not by GL's framebuffer limit.
        With ``surface_pass``, the shader is drawn twice: as is (it writes a depth of 0.5 on
        the pixels that need more work), then compiled with SURFACE_PASS, added with an early
        depth test that keeps it to those pixels (CPU rasterizers otherwise run a branch's
        body for whole pixel blocks).
        """
        fpass = self._pass(camera, extra, shader)  # compiled once per camera model and variant
        second = self._pass(camera, (*extra, "SURFACE_PASS"), shader) if surface_pass else None
        inputs = dict(inputs or {})
        if isinstance(camera, DirectionsCamera):
            inputs["u_direction_map"] = camera.directions.astype(np.float32)
        tile = min(TILE_SIZE, max(w, h))
        single = w <= tile and h <= tile
        texs, fbo = self._target(w if single else tile, h if single else tile, attachments,
                                 depth=surface_pass)  # fmt: skip
        t0 = time.perf_counter()
        out = [np.empty((h, w, 4), np.float32) for _ in range(attachments)]
        frame_uniforms = {**uniforms, **camera.uniforms(w, h)}
        for x0, y0, tw, th in frame_tiles(w, h, tile):
            rows = slice(h - y0 - th, h - y0)  # the tile's rows in the top-first frame
            tile_inputs = {
                name: input_texture(self.ctx, image[rows, x0 : x0 + tw])
                for name, image in inputs.items()
            }
            try:
                self._draw_tile(
                    fpass, second, fbo, (tw, th),
                    {**frame_uniforms, "u_tile_offset": (float(x0), float(y0))},
                    {**textures, **tile_inputs},
                )  # fmt: skip
                # Read into a staging array kept with the target, then flip rows into the
                # frame (a fresh bytes object per read costs ~5x more above glibc's 32 MB
                # mmap threshold: 1920x1080 RGBA float32 is 33 MB).
                staging = self._staging.get((tw, th))
                if staging is None:
                    staging = self._staging[(tw, th)] = np.empty((th, tw, 4), np.float32)
                for i in range(attachments):
                    fbo.read_into(
                        staging, viewport=(0, 0, tw, th), components=4, dtype="f4", attachment=i
                    )
                    out[i][rows, x0 : x0 + tw] = staging[::-1]
            finally:
                for tex in tile_inputs.values():
                    tex.release()
        return out, (time.perf_counter() - t0) * 1e3

    def _draw_tile(self, fpass, second, fbo, size, uniforms: dict, textures: dict) -> None:
        """One draw (or sky + surface pair) over a (w, h) viewport; GL state restored after."""
        ctx = self.ctx
        fbo.viewport = (0, 0, *size)
        if second is None:
            fpass.draw(fbo, uniforms, textures)
            return
        try:
            fbo.clear(depth=1.0)
            ctx.enable(ctx.DEPTH_TEST)
            ctx.depth_func = "1"  # the sky pass always writes colour and depth
            fbo.depth_mask = True
            fpass.draw(fbo, uniforms, textures)
            ctx.depth_func = ">="  # the triangle's depth is 0.5: passes where 0.5 was written
            fbo.depth_mask = False
            ctx.enable(ctx.BLEND)
            ctx.blend_func = ctx.ONE, ctx.ONE
            second.draw(fbo, uniforms, textures)
        finally:  # an exception mid-draw must not leave the shared context changed: back to
            # GL's defaults (moderngl cannot query the previous state)
            ctx.disable(ctx.BLEND | ctx.DEPTH_TEST)
            ctx.blend_func = ctx.ONE, ctx.ZERO
            fbo.depth_mask = True
            ctx.depth_func = "<"

    def _info(self, camera: Camera, altitude_m: float, sun: np.ndarray, ms: float, **extra) -> dict:
        used = effective_altitude_m(altitude_m)
        if used != float(altitude_m):  # raised to the lowest camera height
            extra = {"altitude_requested_m": float(altitude_m), **extra}
        return {
            "model": self.model,
            "atmosphere": self.params.name,
            "camera": camera.name,
            "altitude_m": used,
            "sun_direction": sun.tolist(),
            **extra,
            "render_ms": ms,
        }

    def release(self) -> None:
        """Release this renderer's GL objects now (also done when it is garbage collected)."""
        self._finalizer()
        self._staging.clear()
