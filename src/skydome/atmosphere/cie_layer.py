"""The CIE standard general sky as a layer: a sky of one of the fifteen ISO 15469 / CIE S 011
luminance distributions (``skydome.atmosphere.cie``), drawn by ``shaders/atmosphere/
sky_cie.glsl``, for daylighting work where the standard's sky is wanted rather than the
physical one. It stands in for the atmosphere layer: it offers no air (no aerial
perspective, no Sun's disk, no clouds' lighting)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skydome.atmosphere.cie import cie_sky_type, horizontal_illuminance_factor, zenith_term
from skydome.core.basis import SpectralBasis
from skydome.core.cameras import CameraInputs
from skydome.core.layer import DrawContext, Layer
from skydome.errors import ParameterError, check_range
from skydome.gpu.inputs import ShaderInputs

__all__ = ["CieSkyInputs", "CieSkyLayer"]


@dataclass(frozen=True)
class CieSkyInputs(ShaderInputs):
    """``atmosphere/sky_cie.glsl``: the type's gradation (a, b) and indicatrix (c, d, e)
    parameters, the Sun's direction (east, north, up), the channels of L_z / (f(Z_s) phi(0))
    and of the ground's luminance."""

    u_cie_gradation: tuple[float, float]
    u_cie_indicatrix: tuple[float, float, float]
    u_cie_sun: tuple[float, float, float]
    u_cie_zenith: tuple[float, float, float, float]
    u_cie_ground: tuple[float, float, float, float]


class CieSkyLayer(Layer):
    """A CIE standard general sky of type ``sky_type`` (1-15), scaled by exactly one of
    ``zenith_luminance`` (cd/m^2) or ``horizontal_illuminance`` (lx: the sky's diffuse light
    on a horizontal surface), over a ground of luminance ``ground_albedo`` x that
    illuminance / pi. The Sun is the sky state's (its apparent direction); with it below the
    horizon the standard has no sky and nothing is drawn. The colour is that of sunlight
    (the standard gives luminance only).

    >>> sky = Sky(sun_elevation_deg=40, layers=[CieSkyLayer(12, horizontal_illuminance=2e4)])
    """

    name = "cie_sky"
    stage = "volume"
    shader = "atmosphere/sky_cie.glsl"

    def __init__(self, sky_type: int, *, zenith_luminance: float | None = None,
                 horizontal_illuminance: float | None = None, ground_albedo: float = 0.2,
                 enabled: bool = True):  # fmt: skip
        super().__init__(enabled=enabled)
        self.sky_type = cie_sky_type(sky_type)
        if (zenith_luminance is None) == (horizontal_illuminance is None):
            raise ParameterError(
                "give the CIE sky exactly one scale: zenith_luminance (cd/m^2) or "
                "horizontal_illuminance (lx)"
            )
        scale = zenith_luminance if zenith_luminance is not None else horizontal_illuminance
        check_range("the CIE sky's scale", scale, 0.0, 1e7)
        self.zenith_luminance = None if zenith_luminance is None else float(zenith_luminance)
        self.horizontal_illuminance = (
            None if horizontal_illuminance is None else float(horizontal_illuminance)
        )
        self.ground_albedo = check_range("ground_albedo", ground_albedo, 0.0, 1.0)
        self._sun: np.ndarray | None = None
        self._colour: tuple | None = None

    def update(self, state) -> None:
        self._sun = np.asarray(state.sun.direction, dtype=np.float64)

    @property
    def sun_zenith_deg(self) -> float | None:
        """The Sun's zenith angle (deg) at the last update, None before one."""
        if self._sun is None:
            return None
        return math.degrees(math.acos(max(-1.0, min(1.0, float(self._sun[2])))))

    def luminances(self) -> tuple[float, float]:
        """(the zenith luminance, the diffuse horizontal illuminance) of the sky at the last
        update: cd/m^2 and lx (0, 0 with the Sun below the horizon)."""
        zs = self.sun_zenith_deg
        if zs is None or zs > 90.0:
            return 0.0, 0.0
        factor = horizontal_illuminance_factor(self.sky_type, zs)
        if self.zenith_luminance is not None:
            return self.zenith_luminance, self.zenith_luminance * factor
        return self.horizontal_illuminance / factor, self.horizontal_illuminance

    def colour(self, basis: SpectralBasis) -> np.ndarray:
        """Output channels per cd/m^2 of sunlight-coloured light in ``basis``."""
        if self._colour is None or self._colour[0] is not basis:
            self._colour = (basis, basis.colour(np.ones(len(basis.wavelengths_nm))))
        return self._colour[1]

    def draw(self, frame: DrawContext) -> None:
        t = self.sky_type
        l_z, e_v = self.luminances()
        zs = self.sun_zenith_deg
        colour = self.colour(frame.basis)
        at_zenith = zenith_term(t, zs) if zs is not None and zs <= 90.0 else 1.0
        sun = self._sun / np.linalg.norm(self._sun) if self._sun is not None else (0, 0, 1)
        inputs = CieSkyInputs(
            u_cie_gradation=(t.a, t.b),
            u_cie_indicatrix=(t.c, t.d, t.e),
            u_cie_sun=tuple(float(v) for v in sun),
            u_cie_zenith=tuple(float(v) for v in colour * l_z / at_zenith),
            u_cie_ground=tuple(float(v) for v in colour * self.ground_albedo * e_v / math.pi),
        )
        fpass = self.full_screen_pass(
            frame.ctx, self.shader, (CameraInputs, CieSkyInputs), frame.camera
        )
        fpass.draw(frame.fbo, frame.view, inputs)

    def info(self) -> dict:
        l_z, e_v = self.luminances()
        return {
            "cie_sky_type": self.sky_type.number,
            "cie_zenith_luminance": l_z,
            "cie_diffuse_horizontal_lux": e_v,
        }
