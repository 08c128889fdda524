"""The single-scattering sky renderer (Nishita 1993 with a transmittance table)."""

from __future__ import annotations

import numpy as np

from skydome.atmosphere import AtmosphereParams
from skydome.atmosphere.transmittance import TransmittanceTable
from skydome.atmosphere.uniforms import (
    geometry_uniforms,
    mie_phase_defines,
    profile_defines,
    spectral_uniforms,
)
from skydome.errors import ParameterError
from skydome.gpu import shared_context
from skydome.render.base import PassRenderer, camera_position_km, check_sun_direction
from skydome.render.cameras import Camera
from skydome.render.frame import Frame
from skydome.spectra import spectral_to_rgbs_matrix, wavelengths

# Re-exported for callers that used them from here.
__all__ = ["SingleScatteringRenderer", "camera_position_km"]


class SingleScatteringRenderer(PassRenderer):
    """Renders frames of the single-scattering sky for one atmosphere.

    The GL context, transmittance table and compiled shaders are made once and reused; a
    frame costs one full-screen pass and one read-back.

    Args:
        params: the atmosphere.
        spectral: ``"accurate"`` (16 wavelengths), ``"fast"`` (4), or a sorted list of wavelengths
            (nm, a multiple of 4).
        view_samples: ray-march samples per view ray (16 is plenty with the transmittance table).
        jitter: per-pixel ordered sample offsets against banding (seed 000 eq. 5.14).
        ctx: a moderngl context (default: the shared headless one).
    """

    def __init__(
        self,
        params: AtmosphereParams,
        *,
        spectral="accurate",
        view_samples: int = 16,
        jitter: bool = True,
        ctx=None,
    ):
        if not isinstance(view_samples, (int, np.integer)) or not 1 <= view_samples <= 4096:
            raise ParameterError(f"samples = {view_samples} must be an integer in [1, 4096]")
        super().__init__(params, ctx or shared_context())
        self.wavelengths_nm = wavelengths(spectral)
        self.view_samples = int(view_samples)
        self.jitter = bool(jitter)
        self.transmittance = TransmittanceTable(self.ctx, params)
        self._owned.append(self.transmittance)
        matrix = spectral_to_rgbs_matrix(self.wavelengths_nm)  # (4, N)
        groups = len(self.wavelengths_nm) // 4
        # mat4 per group, column j = wavelength j of the group (column-major upload).
        mats = [matrix[:, 4 * g : 4 * g + 4].T.ravel() for g in range(groups)]
        self.uniforms = {
            **geometry_uniforms(params),
            **spectral_uniforms(params, self.wavelengths_nm),
            **self.transmittance.uniforms(),
            "u_spectral_to_rgbs": np.concatenate(mats).tolist(),
            "u_view_samples": self.view_samples,
            "u_jitter": int(self.jitter),
            "u_output_scale": params.solar_scale,  # this atmosphere's Sun vs the tabulated one
        }
        self.groups = groups

    shader = "atmosphere/sky_single.glsl"
    model = "single"

    def defines(self, camera: Camera) -> dict[str, object]:
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

    def render(
        self,
        camera: Camera,
        width: int,
        height: int,
        *,
        sun_direction,
        altitude_m: float = 0.0,
        directions: bool = False,
    ) -> Frame:
        """Render a frame (cd/m^2). ``sun_direction`` is a unit ENU vector.

        With ``directions=True`` the frame holds each pixel's view direction (xyz, w = 1 where
        the camera covers the pixel) instead of radiance: a debugging and testing aid.
        """
        w, h = camera.frame_size(width, height)
        sun = check_sun_direction(sun_direction)
        uniforms = {
            **self.uniforms,
            "u_camera_position": camera_position_km(self.params, altitude_m),
            "u_sun_direction": tuple(sun),
        }
        textures = {"u_transmittance_lut": self.transmittance.texture}
        extra = ("OUTPUT_DIRECTIONS",) if directions else ()
        (data,), ms = self._draw(camera, w, h, uniforms, textures, extra)
        info = self._info(
            camera,
            altitude_m,
            sun,
            ms,
            samples=self.view_samples,
            wavelengths_nm=self.wavelengths_nm.tolist(),
        )
        return Frame(data, info)
