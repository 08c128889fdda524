"""The single-scattering model of the atmosphere layer (Nishita 1993 with a transmittance
table): ``shaders/atmosphere/sky_single.glsl`` marches every pixel's view ray. It draws the
Sun's disk itself and writes every pixel (what lies behind is not composited): a reference
of the sky's first order, for comparisons and teaching."""

from __future__ import annotations

import numpy as np

from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.precomputed import camera_position_km
from skydome.atmosphere.transmittance import TransmittanceTable
from skydome.atmosphere.uniforms import (
    geometry_uniforms,
    mie_phase_defines,
    profile_defines,
    spectral_uniforms,
)
from skydome.core.layer import DrawContext
from skydome.core.services import AirLights
from skydome.errors import ParameterError
from skydome.gpu import FullscreenPass
from skydome.physics.packing import mat4_groups
from skydome.spectra import spectral_to_rgbs_matrix, wavelengths

#: Ray-march samples per view ray accepted.
MAX_VIEW_SAMPLES = 4096


class SingleScatteringSky:
    """The single-scattering model's transmittance table and passes for one context.

    Args:
        ctx: the moderngl context.
        params: the atmosphere.
        spectral: ``"accurate"`` (16 wavelengths), ``"fast"`` (4), or a sorted list of
            wavelengths (nm, a multiple of 4).
        view_samples: ray-march samples per view ray (16 is plenty with the transmittance
            table).
        jitter: per-pixel ordered sample offsets against banding (seed 000 eq. 5.14).
    """

    def __init__(
        self,
        ctx,
        params: AtmosphereParams,
        *,
        spectral="accurate",
        view_samples: int = 16,
        jitter: bool = True,
    ):
        self.check_samples(view_samples)
        self.ctx = ctx
        self.params = params
        self.wavelengths_nm = wavelengths(spectral)
        self.view_samples = int(view_samples)
        self.jitter = bool(jitter)
        self.transmittance = TransmittanceTable(ctx, params)
        self.groups = len(self.wavelengths_nm) // 4
        self.uniforms = {
            **geometry_uniforms(params),
            **spectral_uniforms(params, self.wavelengths_nm),
            **self.transmittance.uniforms(),
            "u_spectral_to_rgbs": mat4_groups(spectral_to_rgbs_matrix(self.wavelengths_nm)),
            "u_view_samples": self.view_samples,
            "u_jitter": int(self.jitter),
            "u_output_scale": params.solar_scale,  # this atmosphere's Sun vs the tabulated one
        }
        self._passes: dict[tuple, FullscreenPass] = {}

    @staticmethod
    def check_samples(view_samples) -> int:
        """``view_samples`` if it is an integer in [1, MAX_VIEW_SAMPLES], else ParameterError."""
        if (
            isinstance(view_samples, bool)
            or not isinstance(view_samples, (int, np.integer))
            or not 1 <= view_samples <= MAX_VIEW_SAMPLES
        ):
            raise ParameterError(
                f"samples = {view_samples} must be an integer in [1, {MAX_VIEW_SAMPLES}]"
            )
        return int(view_samples)

    def _defines(self, camera) -> dict[str, object]:
        return {
            "NUM_GROUPS": self.groups,
            "CAMERA_MODEL": camera.model,
            **profile_defines(self.params),
            **mie_phase_defines(self.params),
            "PROFILE_VALUES": ", ".join(f"{v:.9e}" for v in self.uniforms["u_profile"]),
            "PROFILE_INV_STEP_VALUES": ", ".join(
                f"{v:.9e}" for v in self.uniforms["u_profile_inv_step"]
            ),
            "PROFILE_LAST_VALUES": ", ".join(f"{v:.1f}" for v in self.uniforms["u_profile_last"]),
        }

    def pass_for(self, camera, extra: tuple[str, ...] = ()) -> FullscreenPass:
        key = (camera.model, extra)
        if key not in self._passes:
            defines = {**self._defines(camera), **{name: 1 for name in extra}}
            self._passes[key] = FullscreenPass(self.ctx, "atmosphere/sky_single.glsl", defines)
        return self._passes[key]

    def draw(self, frame: DrawContext, lights: AirLights, *, directions: bool = False) -> None:
        """Draw one tile (every pixel). ``directions``: each pixel's view direction (xyz,
        w = 1 where the camera covers the pixel) instead of radiance, a debugging aid."""
        uniforms = {
            **self.uniforms,
            **frame.uniforms,
            "u_camera_position": camera_position_km(self.params, frame.altitude_m),
            "u_sun_direction": tuple(lights.sun_direction),
        }
        textures = {**frame.textures, "u_transmittance_lut": self.transmittance.texture}
        fpass = self.pass_for(frame.camera, ("OUTPUT_DIRECTIONS",) if directions else ())
        _, _, tw, th = frame.tile
        frame.fbo.viewport = (0, 0, tw, th)
        fpass.draw(frame.fbo, uniforms, textures)

    def info(self) -> dict:
        return {
            "atmosphere": self.params.name,
            "samples": self.view_samples,
            "wavelengths_nm": self.wavelengths_nm.tolist(),
        }

    def release(self) -> None:
        for p in self._passes.values():
            p.release()
        self._passes.clear()
        self.transmittance.release()
