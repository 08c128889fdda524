"""The Sun layer: the solar disk beyond the atmosphere, limb darkened and refracted.

Its GLSL is ``shaders/celestial/sun.glsl``. Drawn in the frame graph's space stage; the
atmosphere layer applies each pixel's transmittance. The disk's angular size comes from the
true Earth-Sun distance, and so does its irradiance (the atmosphere's sunlight scales the
same way, in the atmosphere layer).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from skydome.celestial.limb_darkening import disk_normalisation, limb_coefficients
from skydome.core.cameras import CameraInputs, disk_samples, disk_scissor
from skydome.core.layer import DrawContext, Layer
from skydome.core.lights import SkyState
from skydome.gpu.inputs import ShaderInputs
from skydome.physics.constants import AU_KM


@dataclass(frozen=True)
class SunInputs(ShaderInputs):
    """``celestial/sun.glsl``: the disk's airless centre (unit ENU) and angular radius, its
    irradiance relative to the tabulated spectrum at 1 au, the spectral conversion (one mat4
    per wavelength group), the limb darkening's coefficients and normalisations, the
    weather's factor on the refraction, the points a pixel averages per side
    (``disk_samples``)."""

    u_sun_direction_true: tuple[float, float, float]
    u_sin_angular_radius: float
    u_sun_scale: float
    u_spectral_to_rgbs: list[float]
    u_limb: list[float]
    u_limb_norm: list[float]
    u_refraction_scale: float
    u_moon_direction_true: tuple[float, float, float] = (0.0, 0.0, 1.0)
    u_moon_sin_radius: float = 0.0
    u_corona_scale: float = 0.0
    u_disk_samples: float = 1.0


def limb_uniforms(wavelengths_nm, angular_radius_rad: float, darkened: bool = True) -> dict:
    """``u_limb`` (the polynomial coefficients A_k of I(mu)/I(1) of each group's 4
    wavelengths, vec4 6 g + k) and ``u_limb_norm`` (1 / the disk integral of I/I(1), 1/sr) of
    ``shaders/celestial/sun.glsl`` for a disk of ``angular_radius_rad``; ``darkened=False``:
    a uniform disk (I = I(1))."""
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    if darkened:
        coeffs = limb_coefficients(wl)  # (N, 6)
        norm = 1.0 / disk_normalisation(angular_radius_rad, wl)
    else:
        coeffs = np.zeros((len(wl), 6))
        coeffs[:, 0] = 1.0
        norm = np.full(len(wl), 1.0 / (2.0 * np.pi * (1.0 - np.cos(angular_radius_rad))))
    groups = len(wl) // 4
    limb = [coeffs[4 * g : 4 * g + 4, k] for g in range(groups) for k in range(6)]
    return {"u_limb": np.concatenate(limb).tolist(), "u_limb_norm": norm.tolist()}


class SunLayer(Layer):
    """The Sun's disk. ``limb_darkening=False`` draws a uniform disk of the same irradiance."""

    name = "sun"
    stage = "space"
    shader = "celestial/sun.glsl"

    def __init__(self, *, limb_darkening: bool = True, enabled: bool = True):
        super().__init__(enabled=enabled)
        self.limb_darkening = bool(limb_darkening)
        self._inputs: SunInputs | None = None
        self._reach = 1.1
        self._hidden: float | None = None
        self._key = None

    def update(self, state: SkyState) -> None:
        sun = state.sun
        basis = self.graph.basis
        key = (id(state), id(basis))
        if key == self._key:
            return
        alpha = float(sun.angular_radius_rad)
        eclipse = {}
        self._reach = 1.1  # the pass's reach, in the disk's radii
        self._hidden = None if state.solar_eclipse is None else state.solar_eclipse.hidden_fraction
        if state.solar_eclipse is not None and state.moon is not None:
            # The Moon hides the disk; the corona shows (out to 6 radii, where it is 1e-4 of
            # its value at the limb).
            eclipse = {
                "u_moon_direction_true": tuple(float(v) for v in state.moon.direction_true),
                "u_moon_sin_radius": float(np.sin(state.moon.angular_radius_rad)),
                "u_corona_scale": 1.0 / (2.0 * np.pi * (1.0 - np.cos(alpha))),
            }
            self._reach = 6.0
        self._inputs = SunInputs(
            u_sun_direction_true=tuple(float(v) for v in sun.direction_true),
            u_sin_angular_radius=float(np.sin(alpha)),
            # The tables' spectrum is the Sun's at 1 au: scale by the true distance.
            u_sun_scale=(AU_KM / sun.distance_km) ** 2 * self.graph.solar_scale,
            u_spectral_to_rgbs=basis.group_matrices(),
            **limb_uniforms(basis.wavelengths_nm, alpha, self.limb_darkening),
            u_refraction_scale=state.refraction_scale,
            **eclipse,
        )
        self._key = key
        self._sun = sun

    def draw(self, frame: DrawContext) -> None:
        fpass = self.full_screen_pass(
            frame.ctx, self.shader, (CameraInputs, SunInputs), frame.camera,
            {"NUM_GROUPS": frame.basis.groups},
        )  # fmt: skip
        # The apparent disk lies within its true radius of the apparent centre (refraction
        # only flattens it); 10 % spare.
        radius = self._sun.angular_radius_rad
        size = frame.frame_size
        rects = disk_scissor(frame.camera, *size, self._sun.direction, self._reach * radius)
        samples = disk_samples(frame.camera, *size, radius, rects)
        inputs = (frame.view, replace(self._inputs, u_disk_samples=float(samples)))
        self.draw_in_rects(frame, fpass, inputs, rects)

    def info(self) -> dict:
        if self._inputs is None:
            return {}
        out = {
            "sun_angular_diameter_deg": float(np.degrees(2 * self._sun.angular_radius_rad)),
            "sun_distance_au": self._sun.distance_km / AU_KM,
        }
        if self._hidden is not None:  # a solar eclipse: the part of the Sun's flux hidden
            out["sun_eclipse_fraction"] = float(self._hidden)
        return out
