"""The precomputed multiple-scattering renderer (Bruneton model; tables from the disk cache)."""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from skydome.atmosphere import AtmosphereParams
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.atmosphere.tables import load_tables, shared_tables
from skydome.atmosphere.uniforms import M_PER_KM
from skydome.errors import ParameterError, check_range
from skydome.gpu import shared_context
from skydome.render.base import (
    PassRenderer,
    camera_position_km,
    check_direction,
    check_sun_direction,
    input_image,
)
from skydome.render.cameras import Camera
from skydome.render.frame import Frame
from skydome.render.sky_view import DEFAULT_SKY_VIEW_SIZE, SkyViewTables


class PrecomputedRenderer(PassRenderer):
    """Renders the sky with every scattering order from precomputed tables.

    Creating one loads the tables from the cache (``$SKYDOME_CACHE``) or computes them (a few
    seconds on a CPU rasterizer, milliseconds on a GPU); frames then cost one pass.

    Args:
        params: the atmosphere.
        config: table sizes, wavelengths and orders (default: ``PrecomputeConfig()``).
        cache: use the on-disk cache, and share the tables in GPU memory with other renderers
            of the same atmosphere and config (False: compute them afresh, for this renderer).
        progress: ``progress(stage, fraction)`` during a precomputation.
        ctx: a moderngl context (default: the shared headless one).
        sky_view: draw frames from sky-view tables (render/sky_view.py), and the aerial
            perspective of a depth image or the light shafts of shadow lengths from their
            direction x distance form, for a camera inside the atmosphere. False looks every
            pixel up in the 4D tables.
        sky_view_size: (azimuth, elevation) texels of those tables.
    """

    shader = "atmosphere/sky_precomputed.glsl"
    model = "precomputed"

    def __init__(
        self,
        params: AtmosphereParams,
        config: PrecomputeConfig | None = None,
        *,
        cache: bool = True,
        progress=None,
        ctx=None,
        sky_view: bool = True,
        sky_view_size: tuple[int, int] = DEFAULT_SKY_VIEW_SIZE,
    ):
        super().__init__(params, ctx or shared_context())
        self.config = config or PrecomputeConfig()
        t0 = time.perf_counter()
        if cache:
            self.tables, self.loaded_from_cache = shared_tables(
                self.ctx, params, self.config, progress=progress
            )
        else:
            self.tables, self.loaded_from_cache = load_tables(
                self.ctx, params, self.config, cache=False, progress=progress
            )
            self._owned.append(self.tables)
        self.setup_s = time.perf_counter() - t0
        self.uniforms = self.tables.uniforms()
        self.textures = self.tables.textures()
        self.sky_view = (
            SkyViewTables(self.ctx, self.tables.defines(), sky_view_size) if sky_view else None
        )
        if self.sky_view is not None:
            self._owned.append(self.sky_view)

    @property
    def wavelengths_nm(self) -> np.ndarray:
        return self.tables.wavelengths_nm

    def defines(self, camera: Camera) -> dict[str, object]:
        return {**self.tables.defines(), "CAMERA_MODEL": camera.model}

    def render(
        self,
        camera: Camera,
        width: int,
        height: int,
        *,
        sun_direction,
        altitude_m: float = 0.0,
        sun_scale: float = 1.0,
        light2_direction=None,
        light2_scale: float = 0.0,
        shadow_length_m=None,
        depth_m=None,
    ) -> Frame:
        """Render a frame in cd/m^2.

        Args:
            sun_direction: unit ENU vector towards the Sun.
            altitude_m: camera altitude above the ground (m).
            sun_scale: the Sun's irradiance in units of the params' solar spectrum (e.g. its
                distance factor (1 AU / d)^2).
            light2_direction, light2_scale: a second light source (e.g. the Moon): its direction
                and irradiance in units of the params' solar spectrum (a number, or 4 numbers:
                one per output channel, for a light of another colour); its sky and ground
                light are added (its disk is not drawn).
            shadow_length_m: optional (H, W) image, the length (m) of each view ray, from the
                camera, that lies in an occluder's shadow (light shafts, Bruneton 2017); +inf
                for a ray in shadow all along.
            depth_m: optional (H, W) image of distances (m) to a user's scene along each ray
                (<= 0 or +inf where there is none). Where given, the frame holds the aerial perspective
                in-scattering between the camera and that point, and ``frame.info
                ["transmittance"]`` the (H, W, 3) RGB transmittance to multiply the scene by:
                composite = scene * transmittance + frame.
        """
        w, h = camera.frame_size(width, height)
        plan = self.frame_plan(
            camera,
            (w, h),
            sun_direction=sun_direction,
            altitude_m=altitude_m,
            sun_scale=sun_scale,
            light2_direction=light2_direction,
            light2_scale=light2_scale,
            shadow_length_m=shadow_length_m,
            depth_m=depth_m,
        )
        outs, ms = self._draw(
            camera,
            w,
            h,
            plan.uniforms,
            plan.textures,
            plan.extra,
            plan.inputs,
            attachments=2 if depth_m is not None else 1,
            surface_pass=True,
            shader=plan.shader,
        )
        info = self._info(
            camera,
            altitude_m,
            plan.sun,
            ms,
            orders=self.tables.orders_computed,
            wavelengths_nm=self.wavelengths_nm.tolist(),
            path="sky-view" if plan.sky_view else "direct",
        )
        if depth_m is not None:
            info["transmittance"] = outs[1][..., :3]
        return Frame(outs[0], info)

    def frame_plan(
        self,
        camera: Camera,
        size: tuple[int, int],
        *,
        sun_direction,
        altitude_m: float = 0.0,
        sun_scale: float = 1.0,
        light2_direction=None,
        light2_scale=0.0,
        shadow_length_m=None,
        depth_m=None,
    ) -> FramePlan:
        """What a frame of this camera needs (arguments as in :meth:`render`): the shader,
        its variant, uniforms and textures, with the sky-view tables re-aimed at the lights
        if they moved. ``render`` draws it; the scene's atmosphere layer draws it into the
        frame graph (skydome.atmosphere.layer)."""
        w, h = size
        sun = check_sun_direction(sun_direction)
        check_range("sun_scale", sun_scale, 0.0, 1e6)
        scales = np.broadcast_to(np.asarray(light2_scale, dtype=np.float64), (4,))
        for s in scales:
            check_range("light2_scale", float(s), 0.0, 1e6)
        has_light2 = bool(np.any(scales > 0))
        light2 = (
            np.array([0.0, 0.0, 1.0])
            if light2_direction is None
            else check_direction("light2 direction", light2_direction)
        )
        if light2_direction is None and has_light2:
            raise ParameterError("light2_scale > 0 needs a light2_direction")
        uniforms = {
            **self.uniforms,
            "u_camera_position": camera_position_km(self.params, altitude_m),
            "u_sun_direction": tuple(sun),
            # The tables are for the tabulated solar spectrum: scale to this atmosphere's Sun.
            "u_sun_scale": float(sun_scale) * self.params.solar_scale,
            "u_light2_direction": tuple(light2),
            "u_light2_scale": tuple(float(s) * self.params.solar_scale for s in scales),
        }
        extra, inputs = (["HAS_LIGHT2"] if has_light2 else []), {}
        if shadow_length_m is not None:
            extra.append("HAS_SHADOW_MAP")
            # +inf: the whole ray is in shadow (1e30 km is past the end of any ray).
            inputs["u_shadow_map"] = input_image(
                "shadow_length_m", shadow_length_m, (w, h), 1 / M_PER_KM, posinf=1e30
            )
        if depth_m is not None:
            extra.append("HAS_DEPTH_MAP")
            inputs["u_depth_map"] = input_image("depth_m", depth_m, (w, h), 1 / M_PER_KM)
        radius_km = uniforms["u_camera_position"][2]
        use_sky_view = self.sky_view is not None and radius_km < self.params.top_radius_m / M_PER_KM
        textures = dict(self.textures)
        if use_sky_view:
            # Tables of the sky seen from this altitude, redrawn when it or a light moves.
            uniforms.update(self.sky_view.uniforms(radius_km))
            lights = [("sun", sun)] + ([("light2", light2)] if has_light2 else [])
            for slot, direction in lights:
                args = (slot, radius_km, tuple(direction), uniforms, self.textures)
                textures.update(self.sky_view.textures(*args))
                if depth_m is not None or (slot == "sun" and shadow_length_m is not None):
                    textures.update(self.sky_view.aerial_textures(*args))
        shader = "atmosphere/sky_view.glsl" if use_sky_view else self.shader
        return FramePlan(shader, tuple(extra), uniforms, textures, inputs, sun, use_sky_view)


@dataclass
class FramePlan:
    """One frame's pass of the precomputed renderer: ``shader`` compiled with ``extra``
    defines, drawn with ``uniforms``, ``textures`` and per-pixel ``inputs`` (sampler name ->
    (H, W) float32 image)."""

    shader: str
    extra: tuple[str, ...]
    uniforms: dict
    textures: dict
    inputs: dict
    sun: np.ndarray
    sky_view: bool
