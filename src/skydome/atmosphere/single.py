"""The single-scattering model of the atmosphere layer (Nishita 1993 with a transmittance
table): ``shaders/atmosphere/sky_single.glsl`` marches every pixel's view ray. It draws the
Sun's disk itself and writes every pixel (what lies behind is not composited): a reference
of the sky's first order, for comparisons and teaching."""

from __future__ import annotations

from dataclasses import dataclass

from skydome.atmosphere.inputs import (
    AirGeometry,
    AirSpectra,
    TransmittanceInputs,
    geometry_inputs,
    mie_phase_defines,
    profile_defines,
    spectra_inputs,
)
from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.precomputed import camera_position_km
from skydome.atmosphere.transmittance import TransmittanceTable
from skydome.core.cameras import CameraInputs
from skydome.core.layer import DrawContext
from skydome.core.services import AirLights
from skydome.errors import check_integer
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.spectra import wavelengths

#: Ray-march samples per view ray accepted.
MAX_VIEW_SAMPLES = 4096


@dataclass(frozen=True)
class SingleInputs(ShaderInputs):
    """``atmosphere/sky_single.glsl``: the camera's planet-centred position (km), the Sun's
    direction, the samples per view ray, the ordered offsets on or off, the Sun's
    irradiance relative to the tabulated spectrum."""

    u_camera_position: tuple[float, float, float]
    u_sun_direction: tuple[float, float, float]
    u_view_samples: int
    u_jitter: int
    u_output_scale: float


INPUTS = (CameraInputs, AirGeometry, AirSpectra, TransmittanceInputs, SingleInputs)


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
        self.geometry = geometry_inputs(params)
        self.spectra = spectra_inputs(params, self.wavelengths_nm)
        self._passes: dict[tuple, FullscreenPass] = {}

    @staticmethod
    def check_samples(view_samples) -> int:
        """``view_samples`` if it is an integer in [1, MAX_VIEW_SAMPLES], else ParameterError."""
        return check_integer("samples", view_samples, 1, MAX_VIEW_SAMPLES)

    def _defines(self, camera) -> dict[str, object]:
        return {
            "NUM_GROUPS": self.groups,
            "CAMERA_MODEL": camera.model,
            **profile_defines(self.params),
            **mie_phase_defines(self.params),
            "PROFILE_VALUES": ", ".join(f"{v:.9e}" for v in self.geometry.u_profile),
            "PROFILE_INV_STEP_VALUES": ", ".join(
                f"{v:.9e}" for v in self.geometry.u_profile_inv_step
            ),
            "PROFILE_LAST_VALUES": ", ".join(f"{v:.1f}" for v in self.geometry.u_profile_last),
        }

    def pass_for(self, camera, extra: tuple[str, ...] = ()) -> FullscreenPass:
        key = (camera.model, extra)
        if key not in self._passes:
            defines = {**self._defines(camera), **{name: 1 for name in extra}}
            self._passes[key] = FullscreenPass(
                self.ctx, "atmosphere/sky_single.glsl", defines, inputs=INPUTS
            )
        return self._passes[key]

    def draw(self, frame: DrawContext, lights: AirLights, *, directions: bool = False) -> None:
        """Draw one tile (every pixel). ``directions``: each pixel's view direction (xyz,
        w = 1 where the camera covers the pixel) instead of radiance, a debugging aid."""
        single = SingleInputs(
            u_camera_position=camera_position_km(self.params, frame.altitude_m),
            u_sun_direction=tuple(lights.sun_direction),
            u_view_samples=self.view_samples,
            u_jitter=int(self.jitter),
            u_output_scale=self.params.solar_scale,  # this atmosphere's Sun vs the tabulated
        )
        transmittance = TransmittanceInputs(self.transmittance.texture, self.transmittance.size)
        fpass = self.pass_for(frame.camera, ("OUTPUT_DIRECTIONS",) if directions else ())
        _, _, tw, th = frame.tile
        frame.fbo.viewport = (0, 0, tw, th)
        fpass.draw(frame.fbo, frame.view, self.geometry, self.spectra, transmittance, single)

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
