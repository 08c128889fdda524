"""The precomputed model of the atmosphere layer: every scattering order from tables.

:class:`PrecomputedSky` holds the tables (loaded from the disk cache or precomputed, and
shared in GPU memory with every other holder of the same atmosphere and configuration), the
sky-view and aerial-perspective tables of the current camera height and lights
(``atmosphere/sky_view.py``), the view-transmittance table, and the compiled passes. It draws
one tile of the frame graph (``draw``):

- camera inside the atmosphere: ``shaders/atmosphere/sky_view.glsl``, two bilinear fetches
  per pixel and light from the sky-view tables (False ``sky_view``: the 4D tables for every
  pixel, ``sky_precomputed.glsl``);
- above it: ``sky_precomputed.glsl`` with a second pass that shades the ground where the
  first marked it (CPU rasterizers run a branch's body for whole pixel blocks).

Both are compiled with COMPOSITE_BEHIND: the light the space layers drew is seen through the
air along each ray that leaves it. Per-channel transmittance is exact for light with the
solar spectrum's shape (each output channel is a linear functional of the spectrum) and
close for the Moon's and the stars' smooth spectra.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.atmosphere.sky_view import DEFAULT_SKY_VIEW_SIZE, SkyViewTables
from skydome.atmosphere.tables import load_tables, shared_tables
from skydome.core.cameras import effective_altitude_m
from skydome.core.layer import DrawContext
from skydome.core.services import AirLights, LookupTables
from skydome.gpu import FullscreenPass
from skydome.gpu.textures import linear_clamped, release_all
from skydome.physics.constants import M_PER_KM
from skydome.physics.geometry import horizon_dip_rad
from skydome.physics.packing import mat4_groups

#: Texels of the view-transmittance table (per camera altitude, over the view cosine).
VIEW_TRANSMITTANCE_SIZE = 1024


def camera_position_km(params: AtmosphereParams, altitude_m: float) -> tuple[float, float, float]:
    """Planet-centred camera position (km) for an altitude above the ground, ENU axes."""
    return (0.0, 0.0, (params.bottom_radius_m + effective_altitude_m(altitude_m)) / M_PER_KM)


def behind_transmittance_weights(to_output: np.ndarray) -> np.ndarray:
    """(4, N) weights W with T_c = sum_l W[c, l] T(l) the transmittance of output channel c
    for light of the solar spectrum's shape: M[c, l] / sum_l M[c, l], M = ``to_output`` (the
    signed sRGB rows included: exact, since each channel is linear in the spectrum)."""
    m = np.asarray(to_output, dtype=np.float64)
    return m / m.sum(axis=1, keepdims=True)


def draw_with_surface(ctx, fbo, size, fpass, second, uniforms: dict, textures: dict) -> None:
    """One draw over a (w, h) viewport, or a sky + surface pair: the sky pass as is (it
    writes a depth of 0.5 on the pixels that need more work), then ``second`` (compiled with
    SURFACE_PASS) added with an early depth test that keeps it to those pixels. GL's state is
    restored after, an exception included."""
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


@dataclass
class FramePlan:
    """One tile's pass of the precomputed model: ``shader`` compiled with ``extra`` defines,
    drawn with ``uniforms`` and ``textures``."""

    shader: str
    extra: tuple[str, ...]
    uniforms: dict
    textures: dict
    sky_view: bool


class PrecomputedSky:
    """The precomputed model's tables and passes for one context (see the module docstring).

    Args:
        ctx: the moderngl context.
        params: the atmosphere.
        config: table sizes, wavelengths and orders (default: ``PrecomputeConfig()``).
        cache: use the on-disk cache, and share the tables in GPU memory with other holders
            of the same atmosphere and config (False: compute them afresh, for this one).
        progress: ``progress(stage, fraction)`` during a precomputation.
        sky_view: draw from sky-view tables for a camera inside the atmosphere (False looks
            every pixel up in the 4D tables).
        sky_view_size: (azimuth, elevation) texels of those tables.
    """

    def __init__(
        self,
        ctx,
        params: AtmosphereParams,
        config: PrecomputeConfig | None = None,
        *,
        cache: bool = True,
        progress=None,
        sky_view: bool = True,
        sky_view_size: tuple[int, int] = DEFAULT_SKY_VIEW_SIZE,
    ):
        self.ctx = ctx
        self.params = params
        self.config = config or PrecomputeConfig()
        t0 = time.perf_counter()
        self._owned: list = []
        if cache:
            self.tables, self.loaded_from_cache = shared_tables(
                ctx, params, self.config, progress=progress
            )
        else:
            self.tables, self.loaded_from_cache = load_tables(
                ctx, params, self.config, cache=False, progress=progress
            )
            self._owned.append(self.tables)
        self.setup_s = time.perf_counter() - t0
        self.uniforms = self.tables.uniforms()
        self.textures = self.tables.textures()
        self.sky_view = (
            SkyViewTables(ctx, self.tables.defines(), sky_view_size) if sky_view else None
        )
        self._passes: dict[tuple, FullscreenPass] = {}
        self._vt = None  # the view-transmittance table: [texture, framebuffer, pass, radius]
        self._behind: dict | None = None
        self._path = None  # the last tile's: "sky-view" tables or "direct" 4D lookups

    @property
    def wavelengths_nm(self) -> np.ndarray:
        return self.tables.wavelengths_nm

    def lookup(self) -> LookupTables:
        return LookupTables(self.tables.defines(), dict(self.uniforms), dict(self.textures))

    def pass_for(self, camera, extra: tuple[str, ...], shader: str) -> FullscreenPass:
        """The pass ``shader`` for ``camera``'s model with the ``extra`` defines (compiled
        once per combination)."""
        key = (shader, camera.model, tuple(extra))
        if key not in self._passes:
            defines = {
                **self.tables.defines(),
                "CAMERA_MODEL": camera.model,
                **{name: 1 for name in extra},
            }
            self._passes[key] = FullscreenPass(self.ctx, shader, defines)
        return self._passes[key]

    # ------------------------------------------------------------------ one tile

    def frame_plan(
        self,
        altitude_m: float,
        lights: AirLights,
        *,
        shadow: bool = False,
        depth: bool = False,
    ) -> FramePlan:
        """What a tile needs: the shader, its variant, uniforms and textures, with the
        sky-view tables re-aimed at the lights if they moved. ``shadow``: light shafts (a
        shadow-length map); ``depth``: the aerial perspective of a user's scene."""
        solar = self.params.solar_scale
        has_light2 = lights.has_moon
        light2 = lights.moon_direction if has_light2 else (0.0, 0.0, 1.0)
        uniforms = {
            **self.uniforms,
            "u_camera_position": camera_position_km(self.params, altitude_m),
            "u_sun_direction": tuple(lights.sun_direction),
            # The tables are for the tabulated solar spectrum: scale to this atmosphere's Sun.
            "u_sun_scale": float(lights.sun_scale) * solar,
            "u_light2_direction": tuple(light2),
            "u_light2_scale": tuple(float(s) * solar for s in lights.moon_scale)
            if has_light2
            else (0.0,) * 4,
        }
        extra = ["HAS_LIGHT2"] if has_light2 else []
        if shadow:
            extra.append("HAS_SHADOW_MAP")
        if depth:
            extra.append("HAS_DEPTH_MAP")
        radius_km = uniforms["u_camera_position"][2]
        use_sky_view = self.sky_view is not None and radius_km < self.params.top_radius_m / M_PER_KM
        textures = dict(self.textures)
        if use_sky_view:
            # Tables of the sky seen from this altitude, redrawn when it or a light moves.
            uniforms.update(self.sky_view.uniforms(radius_km))
            slots = [("sun", lights.sun_direction)] + ([("light2", light2)] if has_light2 else [])
            for slot, direction in slots:
                args = (slot, radius_km, tuple(direction), self.uniforms, self.textures)
                textures.update(self.sky_view.textures(*args))
                if depth or (slot == "sun" and shadow):
                    textures.update(self.sky_view.aerial_textures(*args))
        shader = "atmosphere/sky_view.glsl" if use_sky_view else "atmosphere/sky_precomputed.glsl"
        return FramePlan(shader, tuple(extra), uniforms, textures, use_sky_view)

    def aerial_perspective(self, radius_km: float, lights: AirLights) -> tuple[dict, dict] | None:
        """(uniforms, textures) of the aerial-perspective tables of ``lights`` seen from
        ``radius_km``, or None where there are none (above the air, or no sky-view tables)."""
        if self.sky_view is None or radius_km >= self.params.top_radius_m / M_PER_KM:
            return None
        views = self.sky_view
        args = (radius_km, tuple(lights.sun_direction), self.uniforms, self.textures)
        textures = views.aerial_textures("sun", *args)
        if lights.has_moon:
            args = (radius_km, tuple(lights.moon_direction), self.uniforms, self.textures)
            textures.update(views.aerial_textures("light2", *args))
        return views.uniforms(radius_km), textures

    def behind_uniforms(self, to_output: np.ndarray) -> dict:
        """``u_behind_transmittance``: the per-channel weights of the spectral transmittance
        for the light behind the air (:func:`behind_transmittance_weights`)."""
        if self._behind is None:
            weights = behind_transmittance_weights(to_output)
            self._behind = {"u_behind_transmittance": mat4_groups(weights)}
        return self._behind

    def draw(
        self,
        frame: DrawContext,
        lights: AirLights,
        to_output: np.ndarray,
        *,
        depth_map=None,
        transmittance_fbo=None,
    ) -> None:
        """Draw one tile over ``frame.behind`` into ``frame.fbo`` (or, with a user's
        ``depth_map``, into ``transmittance_fbo``: the frame's target and a transmittance
        attachment)."""
        shadow_map = frame.volume_inputs.shadow_map if frame.volume_inputs else None
        shafts = shadow_map is not None and lights.sun_scale > 0
        depth = depth_map is not None
        plan = self.frame_plan(frame.altitude_m, lights, shadow=shafts, depth=depth)
        behind = dict(self.behind_uniforms(to_output))
        textures = {**plan.textures, **frame.textures, "u_behind": frame.behind}
        if shafts:
            textures["u_shadow_map"] = shadow_map
        if depth:
            textures["u_depth_map"] = depth_map
        if plan.sky_view:
            radius_km = plan.uniforms["u_view_radius"]
            behind.update(self._view_transmittance_uniforms(radius_km))
            textures["u_view_transmittance"] = self._view_transmittance(radius_km, plan)
        extra = (*plan.extra, "COMPOSITE_BEHIND")
        if frame.behind_smooth is not None:  # the smooth space layers' light, reduced
            extra = (*extra, "BEHIND_SMOOTH")
            textures["u_behind_smooth"] = frame.behind_smooth
            behind["u_smooth_map"] = frame.smooth_map
        self._path = "sky-view" if plan.sky_view else "direct"
        fpass = self.pass_for(frame.camera, extra, plan.shader)
        # Above the atmosphere the ground is shaded in a second pass; from inside it, the
        # sky-view tables hold the ground and the disk is the Sun layer's.
        second = (
            None
            if plan.sky_view
            else self.pass_for(frame.camera, (*extra, "SURFACE_PASS"), plan.shader)
        )
        _, _, tw, th = frame.tile
        fbo = transmittance_fbo if depth else frame.fbo
        uniforms = {**plan.uniforms, **frame.uniforms, **behind}
        draw_with_surface(self.ctx, fbo, (tw, th), fpass, second, uniforms, textures)

    def _view_transmittance_uniforms(self, radius_km: float) -> dict:
        bottom = self.params.bottom_radius_m / M_PER_KM
        horizon_mu = -math.sqrt(max(1.0 - (bottom / radius_km) ** 2, 0.0))
        return {"u_view_horizon_mu": horizon_mu, "u_view_radius": radius_km}

    def _view_transmittance(self, radius_km: float, plan: FramePlan):
        """The view-transmittance table (atmosphere/view_transmittance.glsl) of a camera at
        ``radius_km``, redrawn when the altitude changes."""
        ctx = self.ctx
        if self._vt is None:
            tex = linear_clamped(ctx.texture((VIEW_TRANSMITTANCE_SIZE, 1), 4, dtype="f4"), ctx)
            fpass = FullscreenPass(
                ctx,
                "atmosphere/view_transmittance_lut.glsl",
                {**self.tables.defines(), "COMPOSITE_BEHIND": 1},
            )
            self._vt = [tex, ctx.framebuffer(color_attachments=[tex]), fpass, None]
        tex, fbo, fpass, drawn = self._vt
        if drawn != radius_km:
            fbo.viewport = (0, 0, VIEW_TRANSMITTANCE_SIZE, 1)
            uniforms = {
                **plan.uniforms,
                **(self._behind or {}),
                **self._view_transmittance_uniforms(radius_km),
                "u_table_size": float(VIEW_TRANSMITTANCE_SIZE),
            }
            fpass.draw(fbo, uniforms, self.textures)
            self._vt[3] = radius_km
        return tex

    def dark_below_deg(self, altitude_m: float) -> float:
        """The light elevation (deg) below which a light adds nothing to the tables' sky seen
        from ``altitude_m``: every lookup fades it out below mu_s_min - 0.05 (Bruneton's
        cut-off, precomputed_params.glsl sun_cutoff_fade), and a point of the atmosphere
        seen from the camera has its vertical turned by at most acos(R / r) + acos(R / R_top)
        from the camera's (to the horizon, then on to the top of the air)."""
        p = self.params
        r = p.bottom_radius_m + max(altitude_m, 0.0)
        if r >= p.top_radius_m:
            return -90.0
        tilt = horizon_dip_rad(r, p.bottom_radius_m) + horizon_dip_rad(
            p.top_radius_m, p.bottom_radius_m
        )
        cutoff = math.asin(max(self.tables.mu_s_min - 0.05, -1.0))
        return math.degrees(cutoff - tilt)

    def info(self) -> dict:
        out = {
            "atmosphere": self.params.name,
            "orders": self.tables.orders_computed,
            "wavelengths_nm": self.wavelengths_nm.tolist(),
        }
        if self._path is not None:
            out["path"] = self._path
        return out

    def release(self) -> None:
        for p in self._passes.values():
            p.release()
        self._passes.clear()
        if self._vt is not None:
            release_all(self._vt[1], self._vt[0], self._vt[2])
            self._vt = None
        if self.sky_view is not None:
            self.sky_view.release()
            self.sky_view = None
        for obj in self._owned:
            obj.release()
        self._owned.clear()
