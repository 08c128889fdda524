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

from skydome.atmosphere.inputs import (
    FrameMapsInputs,
    LookupInputs,
    SkyViewInputs,
    ViewTransmittanceInputs,
)
from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.precompute import behind_transmittance_weights  # noqa: F401 (its home)
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.atmosphere.sky_view import DEFAULT_SKY_VIEW_SIZE, SkyViewTables
from skydome.atmosphere.tables import load_tables, shared_tables
from skydome.core.cameras import CameraInputs, effective_altitude_m
from skydome.core.layer import BehindInputs, DrawContext
from skydome.core.services import AerialInputs, AirLights, LightInputs, LookupTables
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.textures import linear_clamped, release_all
from skydome.physics.constants import M_PER_KM
from skydome.physics.geometry import horizon_dip_rad

#: Texels of the view-transmittance table (per camera altitude, over the view cosine).
VIEW_TRANSMITTANCE_SIZE = 1024


def camera_position_km(params: AtmosphereParams, altitude_m: float) -> tuple[float, float, float]:
    """Planet-centred camera position (km) for an altitude above the ground, ENU axes."""
    return (0.0, 0.0, (params.bottom_radius_m + effective_altitude_m(altitude_m)) / M_PER_KM)


def draw_with_surface(ctx, fbo, size, fpass, second, inputs: tuple) -> None:
    """One draw over a (w, h) viewport, or a sky + surface pair: the sky pass as is (it
    writes a depth of 0.5 on the pixels that need more work), then ``second`` (compiled with
    SURFACE_PASS) added with an early depth test that keeps it to those pixels. GL's state is
    restored after, an exception included."""
    fbo.viewport = (0, 0, *size)
    if second is None:
        fpass.draw(fbo, *inputs)
        return
    try:
        fbo.clear(depth=1.0)
        ctx.enable(ctx.DEPTH_TEST)
        ctx.depth_func = "1"  # the sky pass always writes colour and depth
        fbo.depth_mask = True
        fpass.draw(fbo, *inputs)
        ctx.depth_func = ">="  # the triangle's depth is 0.5: passes where 0.5 was written
        fbo.depth_mask = False
        ctx.enable(ctx.BLEND)
        ctx.blend_func = ctx.ONE, ctx.ONE
        second.draw(fbo, *inputs)
    finally:  # an exception mid-draw must not leave the shared context changed: back to
        # GL's defaults (moderngl cannot query the previous state)
        ctx.disable(ctx.BLEND | ctx.DEPTH_TEST)
        ctx.blend_func = ctx.ONE, ctx.ZERO
        fbo.depth_mask = True
        ctx.depth_func = "<"


@dataclass(frozen=True)
class ViewTableInputs(ShaderInputs):
    """``atmosphere/view_transmittance_lut.glsl``: the table's texels, the camera's radius
    (km) and the view cosine of its horizon."""

    u_table_size: float
    u_view_radius: float
    u_view_horizon_mu: float


#: The frame passes' inputs: over the 4D tables, and from the sky-view tables.
DIRECT_INPUTS = (CameraInputs, LookupInputs, LightInputs, BehindInputs, FrameMapsInputs)
SKY_VIEW_INPUTS = (*DIRECT_INPUTS, SkyViewInputs, AerialInputs, ViewTransmittanceInputs)


@dataclass
class FramePlan:
    """One tile's pass of the precomputed model: ``shader`` compiled with ``extra`` defines,
    drawn with ``inputs`` (for the sky-view path also the tables of the camera's height)."""

    shader: str
    extra: tuple[str, ...]
    lights: LightInputs
    sky_view: SkyViewInputs | None = None
    aerial: AerialInputs | None = None


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
        self.inputs: LookupInputs = self.tables.inputs()
        self.sky_view = (
            SkyViewTables(ctx, self.tables.defines(), sky_view_size) if sky_view else None
        )
        self._passes: dict[tuple, FullscreenPass] = {}
        self._vt = None  # the view-transmittance table: [texture, framebuffer, pass, radius]
        self._path = None  # the last tile's: "sky-view" tables or "direct" 4D lookups

    @property
    def wavelengths_nm(self) -> np.ndarray:
        return self.tables.wavelengths_nm

    @property
    def ground_albedo(self) -> float:
        """The ground's albedo averaged over the wavelengths."""
        return float(np.mean(self.inputs.spectra.u_ground_albedo))

    def lookup(self) -> LookupTables:
        return LookupTables(self.tables.defines(), self.inputs)

    def pass_for(self, camera, extra: tuple[str, ...], shader: str, inputs: tuple):
        """The pass ``shader`` for ``camera``'s model with the ``extra`` defines (compiled
        once per combination)."""
        key = (shader, camera.model, tuple(extra))
        if key not in self._passes:
            defines = {
                **self.tables.defines(),
                "CAMERA_MODEL": camera.model,
                **{name: 1 for name in extra},
            }
            self._passes[key] = FullscreenPass(self.ctx, shader, defines, inputs=inputs)
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
        """What a tile needs: the shader, its variant and the lights' inputs, with the
        sky-view tables re-aimed at the lights if they moved. ``shadow``: light shafts (a
        shadow-length map); ``depth``: the aerial perspective of a user's scene."""
        position = camera_position_km(self.params, altitude_m)
        light_inputs = lights.inputs(position, self.params.solar_scale)
        extra = ["HAS_LIGHT2"] if lights.has_moon else []
        if lights.eclipse is not None:
            extra.append("HAS_ECLIPSE")
        if shadow:
            extra.append("HAS_SHADOW_MAP")
        if depth:
            extra.append("HAS_DEPTH_MAP")
        radius_km = position[2]
        if self.sky_view is None or radius_km >= self.params.top_radius_m / M_PER_KM:
            return FramePlan("atmosphere/sky_precomputed.glsl", tuple(extra), light_inputs)
        # Tables of the sky seen from this altitude, redrawn when it or a light moves.
        views = self.sky_view
        sun = views.textures("sun", radius_km, lights.sun_direction, self.inputs)
        moon = (None, None)
        if lights.has_moon:
            moon = views.textures("light2", radius_km, lights.moon_direction, self.inputs)
        mapping = views.mapping(radius_km)
        aerial = AerialInputs(mapping.u_sky_view_size, radius_km, mapping.u_aerial_size)
        if depth:
            aerial = views.aerial(radius_km, lights, self.inputs)
        elif shadow:  # the Sun's light along the shadowed part is taken off the sky
            sun_aerial = views.aerial_textures("sun", radius_km, lights.sun_direction, self.inputs)
            aerial = AerialInputs(
                aerial.u_sky_view_size, radius_km, aerial.u_aerial_size, *sun_aerial
            )
        return FramePlan(
            "atmosphere/sky_view.glsl", tuple(extra), light_inputs, SkyViewInputs(*sun, *moon),
            aerial,
        )  # fmt: skip

    def aerial_perspective(self, radius_km: float, lights: AirLights) -> AerialInputs | None:
        """The aerial-perspective tables of ``lights`` seen from ``radius_km``, or None where
        there are none (above the air, or no sky-view tables)."""
        if self.sky_view is None or radius_km >= self.params.top_radius_m / M_PER_KM:
            return None
        return self.sky_view.aerial(radius_km, lights, self.inputs)

    def draw(
        self,
        frame: DrawContext,
        lights: AirLights,
        behind: BehindInputs,
        *,
        depth_map=None,
        transmittance_fbo=None,
    ) -> None:
        """Draw one tile over the light ``behind`` into ``frame.fbo`` (or, with a user's
        ``depth_map``, into ``transmittance_fbo``: the frame's target and a transmittance
        attachment)."""
        shadow_map = frame.volume_inputs.shadow_map if frame.volume_inputs else None
        shafts = shadow_map is not None and lights.sun_scale > 0
        depth = depth_map is not None
        plan = self.frame_plan(frame.altitude_m, lights, shadow=shafts, depth=depth)
        maps = FrameMapsInputs(depth_map, shadow_map if shafts else None)
        extra = (*plan.extra, "COMPOSITE_BEHIND")
        if behind.u_behind_smooth is not None:  # the smooth space layers' light, reduced
            extra = (*extra, "BEHIND_SMOOTH")
        inputs = [frame.view, self.inputs, plan.lights, behind, maps]
        if plan.sky_view is not None:
            radius_km = plan.aerial.u_view_radius
            inputs += [plan.sky_view, plan.aerial, self._view_transmittance(radius_km)]
        kinds = SKY_VIEW_INPUTS if plan.sky_view is not None else DIRECT_INPUTS
        self._path = "sky-view" if plan.sky_view is not None else "direct"
        fpass = self.pass_for(frame.camera, extra, plan.shader, kinds)
        # Above the atmosphere the ground is shaded in a second pass; from inside it, the
        # sky-view tables hold the ground and the disk is the Sun layer's.
        second = None
        if plan.sky_view is None:
            second = self.pass_for(frame.camera, (*extra, "SURFACE_PASS"), plan.shader, kinds)
        _, _, tw, th = frame.tile
        fbo = transmittance_fbo if depth else frame.fbo
        draw_with_surface(self.ctx, fbo, (tw, th), fpass, second, tuple(inputs))

    def _horizon_mu(self, radius_km: float) -> float:
        bottom = self.params.bottom_radius_m / M_PER_KM
        return -math.sqrt(max(1.0 - (bottom / radius_km) ** 2, 0.0))

    def _view_transmittance(self, radius_km: float) -> ViewTransmittanceInputs:
        """The view-transmittance table (atmosphere/view_transmittance.glsl) of a camera at
        ``radius_km``, redrawn when the altitude changes."""
        ctx = self.ctx
        if self._vt is None:
            tex = linear_clamped(ctx.texture((VIEW_TRANSMITTANCE_SIZE, 1), 4, dtype="f4"), ctx)
            fpass = FullscreenPass(
                ctx,
                "atmosphere/view_transmittance_lut.glsl",
                {**self.tables.defines(), "COMPOSITE_BEHIND": 1},
                inputs=(LookupInputs, ViewTableInputs),
            )
            self._vt = [tex, ctx.framebuffer(color_attachments=[tex]), fpass, None]
        tex, fbo, fpass, drawn = self._vt
        if drawn != radius_km:
            fbo.viewport = (0, 0, VIEW_TRANSMITTANCE_SIZE, 1)
            table = ViewTableInputs(
                float(VIEW_TRANSMITTANCE_SIZE), radius_km, self._horizon_mu(radius_km)
            )
            fpass.draw(fbo, self.inputs, table)
            self._vt[3] = radius_km
        return ViewTransmittanceInputs(tex, self._horizon_mu(radius_km))

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
