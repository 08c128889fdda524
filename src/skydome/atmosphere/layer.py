"""The atmosphere layer: the scene's volume of air, from the precomputed tables.

It draws ``shaders/atmosphere/sky_view.glsl`` (camera inside the atmosphere) or
``sky_precomputed.glsl`` (above it) compiled with COMPOSITE_BEHIND: the light the space
layers drew (the Sun's and the Moon's disks, later the stars) is multiplied by the
transmittance of each pixel's ray, per output channel, and the sky's in-scattered light of
the Sun and of the Moon (its second light) is added; the ground hides what lies beyond.

Per-channel transmittance is exact for light with the solar spectrum's shape (each output
channel is a linear functional of the spectrum) and close for the Moon's and the stars'
smooth spectra. The moonlit sky is the sunlit sky's tables lit from the Moon's direction,
scaled by the Moon's illuminance and coloured per channel by the Moon's spectrum relative to
the Sun's (the same approximation).
"""

from __future__ import annotations

import math

import numpy as np

from skydome.atmosphere.params import AtmosphereParams
from skydome.scene.layer import DrawContext, Layer, SpectralBasis
from skydome.scene.state import AU_KM, SkyState

#: Texels of the view-transmittance table (per camera altitude, over the view cosine).
VIEW_TRANSMITTANCE_SIZE = 1024


class AtmosphereLayer(Layer):
    """The air of a preset or of ``AtmosphereParams``, with every scattering order.

    Args:
        atmosphere: a preset name or AtmosphereParams.
        config: the tables (``PrecomputeConfig``; default: 16 wavelengths, 4 orders).
        moonlight: light the sky by the Moon too (when the scene has one).
        sky_view_size: (azimuth, elevation) texels of the sky-view tables (default 256 x
            256; 128 x 128 costs a quarter to re-aim and differs by <= 0.16 % RMS at 640 x
            360, measured at Sun 30 to -8 deg: time-lapses use it).
        progress: ``progress(stage, fraction)`` during a table precomputation.
    """

    name = "atmosphere"
    stage = "volume"
    merges_smooth = True  # its composite reads the reduced smooth light (common/behind.glsl)

    def __init__(
        self,
        atmosphere: str | AtmosphereParams = "earth",
        *,
        config=None,
        moonlight: bool = True,
        sky_view_size: tuple[int, int] | None = None,
        progress=None,
        enabled: bool = True,
    ):
        from skydome.atmosphere import preset

        super().__init__(enabled=enabled)
        self.params = preset(atmosphere) if isinstance(atmosphere, str) else atmosphere
        self.config = config
        self.sky_view_size = sky_view_size
        self.moonlight = bool(moonlight)
        self._progress = progress
        self.renderer = None
        self.spectral_basis: SpectralBasis | None = None
        self._lights: dict = {}
        self._solar: float | None = None
        self._last_sun = None
        self._vt = None  # the view-transmittance table: [texture, framebuffer, pass, radius]
        self._tint: np.ndarray | None = None

    def prepare(self, graph) -> None:
        from skydome.render.precomputed import PrecomputedRenderer

        super().prepare(graph)
        if self.renderer is None:
            extra = {} if self.sky_view_size is None else {"sky_view_size": self.sky_view_size}
            self.renderer = PrecomputedRenderer(
                self.params, self.config, ctx=graph.ctx, progress=self._progress, **extra
            )
        tables = self.renderer.tables
        self.spectral_basis = SpectralBasis.for_wavelengths(
            tables.wavelengths_nm, self.renderer.config.output
        )
        weights = behind_transmittance_weights(self.spectral_basis.to_output)
        groups = weights.shape[1] // 4
        self._behind = {
            "u_behind_transmittance": np.concatenate(
                [weights[:, 4 * g : 4 * g + 4].T.ravel() for g in range(groups)]
            ).tolist()
        }

    def update(self, state: SkyState) -> None:
        sun = state.sun
        lights = {
            # The tables' light paths are straight: the air is lit from the airless direction
            # (the apparent one is for the disk, which the Sun layer draws refracted). It is
            # also continuous: the refraction laws stop at the horizon.
            "sun_direction": sun.direction_true,
            # The tables hold the Sun at 1 au: scale by the true distance.
            "sun_scale": (AU_KM / sun.distance_km) ** 2,
            "light2_direction": None,
            "light2_scale": 0.0,
        }
        if self.moonlight and state.moon is not None:
            ratio = state.moon.illuminance_lux / self._solar_lux() / self.params.solar_scale
            lights["light2_direction"] = state.moon.direction_true
            lights["light2_scale"] = tuple(ratio * self._moon_tint())
        self._lights = lights
        self._state = state

    @property
    def lights(self) -> dict:
        """The lights of the last update as the tables see them: ``sun_direction`` (the
        airless direction), ``sun_scale`` (irradiance relative to the tables' Sun at 1 au),
        ``light2_direction`` and ``light2_scale`` (the Moon: per output channel, or 0)."""
        return dict(self._lights)

    def _solar_lux(self) -> float:
        """Illuminance (lx) of the tabulated solar spectrum at 1 au, as the tables see it."""
        if self._solar is None:
            from skydome.atmosphere.precompute import conversion_matrix
            from skydome.spectra import SRGB_LUMINANCE

            wl = self.spectral_basis.wavelengths_nm
            self._solar = float(SRGB_LUMINANCE @ (conversion_matrix(wl) @ np.ones(len(wl)))[:3])
        return self._solar

    def _moon_tint(self) -> np.ndarray:
        """Per output channel: the Moon's light relative to the Sun's at equal luminance."""
        if self._tint is None:
            from skydome.celestial.moon_albedo import moon_spectral_albedo

            basis = self.spectral_basis
            wl = basis.wavelengths_nm
            self._tint = basis.colour(moon_spectral_albedo(wl)) / basis.colour(np.ones(len(wl)))
        return self._tint

    def dark_below_deg(self, altitude_m: float) -> float:
        """The light elevation (deg) below which a light adds nothing to the tables' sky seen
        from ``altitude_m``: every lookup fades it out below mu_s_min - 0.05 (Bruneton's
        cut-off, precomputed_params.glsl sun_cutoff_fade), and a point of the atmosphere
        seen from the camera has its vertical turned by at most acos(R / r) + acos(R / R_top)
        from the camera's (to the horizon, then on to the top of the air)."""
        import math

        p = self.params
        r = p.bottom_radius_m + max(altitude_m, 0.0)
        if r >= p.top_radius_m:
            return -90.0
        tilt = math.acos(p.bottom_radius_m / r) + math.acos(p.bottom_radius_m / p.top_radius_m)
        cutoff = math.asin(max(self.renderer.tables.mu_s_min - 0.05, -1.0))
        return math.degrees(cutoff - tilt)

    def draw(self, frame: DrawContext) -> None:
        r = self.renderer
        lights = dict(self._lights)
        # A light far enough below the horizon adds exactly nothing: its sky-view table is
        # left as it is (not re-aimed) and its light out.
        dark = self.dark_below_deg(frame.altitude_m)
        if _elevation_deg(lights["sun_direction"]) < dark:
            lights["sun_scale"] = 0.0
            if self._last_sun is not None:
                lights["sun_direction"] = self._last_sun
        self._last_sun = lights["sun_direction"]
        moon = lights["light2_direction"]
        if moon is not None and _elevation_deg(moon) < dark:
            lights["light2_direction"], lights["light2_scale"] = None, 0.0
        plan = r.frame_plan(frame.camera, frame.frame_size, altitude_m=frame.altitude_m, **lights)
        behind = dict(self._behind)
        textures = {**plan.textures, **frame.textures, "u_behind": frame.behind}
        shafts = plan.sky_view and "u_shadow_map" in frame.textures and lights["sun_scale"] > 0
        if shafts:  # another layer's shadow lengths (the clouds' light shafts)
            radius_km = plan.uniforms["u_view_radius"]
            textures.update(
                r.sky_view.aerial_textures(
                    "sun", radius_km, tuple(plan.uniforms["u_sun_direction"]), r.uniforms,
                    r.textures,
                )
            )  # fmt: skip
        if plan.sky_view:
            radius_km = plan.uniforms["u_view_radius"]
            behind.update(self._view_transmittance_uniforms(radius_km))
            textures["u_view_transmittance"] = self._view_transmittance(radius_km, plan)
        extra = (*plan.extra, "COMPOSITE_BEHIND", *(("HAS_SHADOW_MAP",) if shafts else ()))
        if frame.behind_smooth is not None:  # the smooth space layers' light, reduced
            extra = (*extra, "BEHIND_SMOOTH")
            textures["u_behind_smooth"] = frame.behind_smooth
            behind["u_smooth_map"] = frame.smooth_map
        fpass = r._pass(frame.camera, extra, plan.shader)
        # Above the atmosphere the ground is shaded in a second pass (see render/base.py);
        # from inside it, the sky-view tables hold the ground and the disk is the Sun layer's.
        second = (
            None if plan.sky_view else r._pass(frame.camera, (*extra, "SURFACE_PASS"), plan.shader)
        )
        _, _, tw, th = frame.tile
        r._draw_tile(
            fpass,
            second,
            frame.fbo,
            (tw, th),
            {**plan.uniforms, **frame.uniforms, **behind},
            textures,
        )

    def _view_transmittance_uniforms(self, radius_km: float) -> dict:
        bottom = self.params.bottom_radius_m / 1e3
        horizon_mu = -math.sqrt(max(1.0 - (bottom / radius_km) ** 2, 0.0))
        return {"u_view_horizon_mu": horizon_mu, "u_view_radius": radius_km}

    def _view_transmittance(self, radius_km: float, plan):
        """The view-transmittance table (atmosphere/view_transmittance.glsl) of a camera at
        ``radius_km``, redrawn when the altitude changes."""
        from skydome.gpu import FullscreenPass
        from skydome.gpu.textures import linear_clamped

        ctx = self.graph.ctx
        if self._vt is None:
            tex = linear_clamped(ctx.texture((VIEW_TRANSMITTANCE_SIZE, 1), 4, dtype="f4"), ctx)
            fpass = FullscreenPass(
                ctx,
                "atmosphere/view_transmittance_lut.glsl",
                {**self.renderer.tables.defines(), "COMPOSITE_BEHIND": 1},
            )
            self._vt = [tex, ctx.framebuffer(color_attachments=[tex]), fpass, None]
        tex, fbo, fpass, drawn = self._vt
        if drawn != radius_km:
            fbo.viewport = (0, 0, VIEW_TRANSMITTANCE_SIZE, 1)
            uniforms = {
                **plan.uniforms,
                **self._behind,
                **self._view_transmittance_uniforms(radius_km),
                "u_table_size": float(VIEW_TRANSMITTANCE_SIZE),
            }
            fpass.draw(fbo, uniforms, self.renderer.textures)
            self._vt[3] = radius_km
        return tex

    def info(self) -> dict:
        r = self.renderer
        if r is None:
            return {}
        return {
            "atmosphere": self.params.name,
            "orders": r.tables.orders_computed,
            "wavelengths_nm": r.wavelengths_nm.tolist(),
        }

    def release(self) -> None:
        super().release()
        if self._vt is not None:
            for obj in self._vt[:3]:
                obj.release()
            self._vt = None
        if self.renderer is not None:
            self.renderer.release()
            self.renderer = None


def behind_transmittance_weights(to_output: np.ndarray) -> np.ndarray:
    """(4, N) weights W with T_c = sum_l W[c, l] T(l) the transmittance of output channel c
    for light of the solar spectrum's shape: M[c, l] / sum_l M[c, l], M = ``to_output`` (the
    signed sRGB rows included: exact, since each channel is linear in the spectrum)."""
    m = np.asarray(to_output, dtype=np.float64)
    return m / m.sum(axis=1, keepdims=True)


def _elevation_deg(direction) -> float:
    import math

    return math.degrees(math.asin(max(-1.0, min(1.0, float(direction[2])))))
