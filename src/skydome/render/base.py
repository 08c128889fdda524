"""What every sky renderer shares: compiled passes per camera model, render targets, the
direction map of a DirectionsCamera, per-pixel input images and the read-back to a Frame."""

from __future__ import annotations

import time

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


def camera_position_km(params: AtmosphereParams, altitude_m: float) -> tuple[float, float, float]:
    """Planet-centred camera position (km) for an altitude above the ground, ENU axes."""
    h = check_range("altitude", altitude_m, 0.0, MAX_ALTITUDE_M, "m")
    return (0.0, 0.0, (params.bottom_radius_m + max(h, MIN_ALTITUDE_M)) / M_PER_KM)


def check_direction(name: str, direction) -> np.ndarray:
    """A finite non-zero 3-vector, normalised."""
    s = np.asarray(direction, dtype=np.float64).reshape(-1)
    n = float(np.linalg.norm(s)) if s.shape == (3,) and np.all(np.isfinite(s)) else 0.0
    if n == 0.0:
        raise ParameterError(f"{name} must be a finite non-zero 3-vector, got {direction!r}")
    return s / n


def check_sun_direction(sun_direction) -> np.ndarray:
    return check_direction("sun direction", sun_direction)


def image_texture(ctx, name: str, image, size: tuple[int, int], scale: float = 1.0):
    """An R32F texture from an (H, W) image (row 0 at the top) for texelFetch in a pass."""
    w, h = size
    a = np.asarray(image, dtype=np.float64)
    if a.shape != (h, w) or not np.all(np.isfinite(a)):
        raise ParameterError(f"{name} must be a finite ({h}, {w}) array, got shape {a.shape}")
    data = np.ascontiguousarray((a * scale)[::-1], dtype="f4")
    tex = ctx.texture((w, h), 1, data.tobytes(), dtype="f4")
    return tex


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
        inputs: dict | None = None,
        attachments: int = 1,
        surface_pass: bool = False,
        shader: str | None = None,
    ):
        """Draw the pass for ``camera`` into a (w, h) target; returns (arrays, milliseconds).

        ``inputs`` maps sampler names to textures made for this frame (released after it).
        ``shader`` replaces the renderer's shader file for this draw.
        Arrays are float32 (h, w, 4), row 0 at the top, one per attachment.
        With ``surface_pass``, the shader is drawn twice: as is (it writes a depth of 0.5 on
        the pixels that need more work), then compiled with SURFACE_PASS, added with an early
        depth test that keeps it to those pixels (CPU rasterizers otherwise run a branch's
        body for whole pixel blocks).
        """
        fpass = self._pass(camera, extra, shader)  # compiled once per camera model and variant
        second = self._pass(camera, (*extra, "SURFACE_PASS"), shader) if surface_pass else None
        texs, fbo = self._target(w, h, attachments, depth=surface_pass)
        inputs = dict(inputs or {})
        t0 = time.perf_counter()
        if isinstance(camera, DirectionsCamera):
            inputs["u_direction_map"] = self.ctx.texture(
                (w, h), 3, camera.texture_data(), dtype="f4"
            )
        fbo.viewport = (0, 0, w, h)
        ctx = self.ctx
        try:
            all_uniforms, all_textures = (
                {**uniforms, **camera.uniforms(w, h)},
                {**textures, **inputs},
            )
            if second is None:
                fpass.draw(fbo, all_uniforms, all_textures)
            else:
                fbo.clear(depth=1.0)
                ctx.enable(ctx.DEPTH_TEST)
                ctx.depth_func = "1"  # the sky pass always writes colour and depth
                fbo.depth_mask = True
                fpass.draw(fbo, all_uniforms, all_textures)
                ctx.depth_func = ">="  # the triangle's depth is 0.5: passes where 0.5 was written
                fbo.depth_mask = False
                ctx.enable(ctx.BLEND)
                ctx.blend_func = ctx.ONE, ctx.ONE
                second.draw(fbo, all_uniforms, all_textures)
                ctx.disable(ctx.BLEND | ctx.DEPTH_TEST)
                fbo.depth_mask = True
                ctx.depth_func = "<"
            # Read into a staging array kept with the target, then flip rows into the frame's
            # own array (a fresh bytes object per read costs ~5x more above glibc's 32 MB
            # mmap threshold: 1920x1080 RGBA float32 is 33 MB).
            staging = self._staging.get((w, h))
            if staging is None:
                staging = self._staging[(w, h)] = np.empty((h, w, 4), np.float32)
            out = []
            for i in range(attachments):
                fbo.read_into(staging, components=4, dtype="f4", attachment=i)
                out.append(staging[::-1].copy())
        finally:
            for tex in inputs.values():
                tex.release()
        return out, (time.perf_counter() - t0) * 1e3

    def _info(self, camera: Camera, altitude_m: float, sun: np.ndarray, ms: float, **extra) -> dict:
        return {
            "model": self.model,
            "atmosphere": self.params.name,
            "camera": camera.name,
            "altitude_m": float(altitude_m),
            "sun_direction": sun.tolist(),
            **extra,
            "render_ms": ms,
        }

    def release(self) -> None:
        for p in self._passes.values():
            p.release()
        for texs, fbo in self._targets.values():
            fbo.release()
            for tex in texs:
                tex.release()
        self._passes.clear()
        self._targets.clear()
        self._staging.clear()
