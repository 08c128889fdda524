"""The single-scattering sky renderer (Nishita 1993 with a transmittance table)."""

from __future__ import annotations

import time

import numpy as np

from skydome.atmosphere import AtmosphereParams
from skydome.atmosphere.transmittance import TransmittanceTable
from skydome.atmosphere.uniforms import M_PER_KM, geometry_uniforms, spectral_uniforms
from skydome.errors import ParameterError, check_range
from skydome.gpu import FullscreenPass, shared_context
from skydome.render.cameras import Camera, DirectionsCamera
from skydome.render.frame import Frame
from skydome.spectra import spectral_to_rgbs_matrix, wavelengths

#: Largest camera altitude accepted (m): 1e8 m is far beyond the Moon's orbit / 4.
MAX_ALTITUDE_M = 1e8
#: Cameras closer to the ground are raised to this height (m): float32 positions in km are
#: resolved to about 0.5 m at the planet radius.
MIN_ALTITUDE_M = 1.0


def camera_position_km(params: AtmosphereParams, altitude_m: float) -> tuple[float, float, float]:
    """Planet-centred camera position (km) for an altitude above the ground, ENU axes."""
    h = check_range("altitude", altitude_m, 0.0, MAX_ALTITUDE_M, "m")
    return (0.0, 0.0, (params.bottom_radius_m + max(h, MIN_ALTITUDE_M)) / M_PER_KM)


def check_sun_direction(sun_direction) -> np.ndarray:
    s = np.asarray(sun_direction, dtype=np.float64).reshape(-1)
    n = float(np.linalg.norm(s)) if s.shape == (3,) and np.all(np.isfinite(s)) else 0.0
    if n == 0.0:
        raise ParameterError(
            f"sun direction must be a finite non-zero 3-vector, got {sun_direction!r}"
        )
    return s / n


class SingleScatteringRenderer:
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
        self.params = params
        self.ctx = ctx or shared_context()
        self.wavelengths_nm = wavelengths(spectral)
        self.view_samples = int(view_samples)
        self.jitter = bool(jitter)
        self.transmittance = TransmittanceTable(self.ctx, params)
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
            "u_output_scale": 1.0,
        }
        self.groups = groups
        self._passes: dict[tuple[int, bool], FullscreenPass] = {}
        self._targets: dict[tuple[int, int], tuple] = {}

    def _pass(self, camera: Camera, directions: bool = False) -> FullscreenPass:
        key = (camera.model, directions)
        if key not in self._passes:
            defines = {
                "NUM_GROUPS": self.groups,
                "CAMERA_MODEL": camera.model,
                "PROFILE_VALUES": ", ".join(f"{v:.9e}" for v in self.uniforms["u_profile"]),
            }
            if directions:
                defines["OUTPUT_DIRECTIONS"] = 1
            self._passes[key] = FullscreenPass(self.ctx, "sky_single.glsl", defines)
        return self._passes[key]

    def _target(self, width: int, height: int):
        if (width, height) not in self._targets:
            tex = self.ctx.texture((width, height), 4, dtype="f4")
            self._targets[(width, height)] = (tex, self.ctx.framebuffer(color_attachments=[tex]))
        return self._targets[(width, height)]

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
        fpass = self._pass(camera, directions)  # compiled once per camera model
        tex, fbo = self._target(w, h)
        t0 = time.perf_counter()
        fbo.viewport = (0, 0, w, h)
        uniforms = {
            **self.uniforms,
            **camera.uniforms(w, h),
            "u_camera_position": camera_position_km(self.params, altitude_m),
            "u_sun_direction": tuple(sun),
        }
        textures = {"u_transmittance_lut": self.transmittance.texture}
        direction_map = None
        if isinstance(camera, DirectionsCamera):
            direction_map = self.ctx.texture((w, h), 3, camera.texture_data(), dtype="f4")
            textures["u_direction_map"] = direction_map
        fpass.draw(fbo, uniforms, textures)
        if direction_map is not None:
            direction_map.release()
        data = np.frombuffer(fbo.read(components=4, dtype="f4"), dtype=np.float32)
        data = data.reshape(h, w, 4)[::-1].copy()  # GL rows are bottom-up
        info = {
            "model": "single",
            "atmosphere": self.params.name,
            "camera": camera.name,
            "altitude_m": float(altitude_m),
            "sun_direction": sun.tolist(),
            "samples": self.view_samples,
            "wavelengths_nm": self.wavelengths_nm.tolist(),
            "render_ms": (time.perf_counter() - t0) * 1e3,
        }
        return Frame(data, info)

    def release(self) -> None:
        for p in self._passes.values():
            p.release()
        for tex, fbo in self._targets.values():
            fbo.release()
            tex.release()
        self.transmittance.release()
        self._passes.clear()
        self._targets.clear()
