"""The sky probe: the whole sky as it is drawn (clouds over the clear sky), seen from one
point, as an equirectangular radiance map, and the light it gives: a horizontal surface's
irradiance and the radiance's real spherical harmonics to order 2 (Ramamoorthi & Hanrahan
2001, "An efficient representation for irradiance environment maps", eqs. 3 and 12: the
irradiance of any normal from nine coefficients). ``CloudLayer.sky_probe`` makes it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skydome.core.cameras import EquirectCamera
from skydome.physics.spherical_harmonics import evaluate, irradiance_coefficients, sh9


@dataclass(frozen=True)
class SkyProbe:
    """The sky seen from one point: ``radiance`` (H, W, 4) equirectangular (R, G, B,
    scotopic; cd/m^2; azimuth 0 north at the left, zenith at the top); ``irradiance`` (4,)
    on a horizontal surface from it (lx); ``clear_irradiance`` (4,) the same for the clear
    sky (scotopic taken as the G channel's ratio); ``sh`` (9, 4) its spherical harmonics."""

    radiance: np.ndarray
    irradiance: np.ndarray
    clear_irradiance: np.ndarray
    sh: np.ndarray

    @classmethod
    def from_maps(cls, radiance: np.ndarray, clear_rgb: np.ndarray) -> SkyProbe:
        """From the equirectangular maps of the drawn sky (H, W, 4) and of the clear sky
        alone (H, W, 3), top row first."""
        h, w = radiance.shape[:2]
        camera = EquirectCamera()
        # pixel centres, the top row first (GL rows count from the bottom)
        x, y = np.meshgrid(np.arange(w) + 0.5, h - 0.5 - np.arange(h))
        d, _ = camera.directions(x, y, w, h)
        omega = camera.solid_angle(d, w, h)
        up = np.maximum(d[..., 2], 0.0) * omega
        irradiance = np.einsum("hw,hwc->c", up, radiance)
        clear = np.einsum("hw,hwc->c", up, clear_rgb)
        clear = np.append(clear, clear[1] * irradiance[3] / max(irradiance[1], 1e-30))
        sh = np.einsum("hwk,hw,hwc->kc", sh9(d), omega, radiance)
        return cls(radiance, irradiance, clear, sh)

    @property
    def ratio(self) -> tuple[float, float, float, float]:
        """The drawn sky's irradiance over the clear sky's, per channel (1 where the clear
        sky gives none)."""
        out = []
        for drawn, clear in zip(self.irradiance, self.clear_irradiance, strict=True):
            out.append(float(drawn / clear) if clear > 1e-30 else 1.0)
        return tuple(out)

    def ambient_radiance(self, ground_albedo: float) -> tuple[float, float, float, float]:
        """The mean radiance (cd/m^2 per channel) around a point near the ground: the sky's
        hemisphere E / pi above, the Lambertian ground's A E / pi below."""
        mean = (1.0 + ground_albedo) / 2.0 * self.irradiance / math.pi
        return tuple(float(v) for v in mean)

    def irradiance_towards(self, normal) -> np.ndarray:
        """The irradiance (lx per channel, (..., 4)) of surfaces facing unit ``normal``
        (..., 3), from the spherical harmonics (Ramamoorthi & Hanrahan eq. 12)."""
        n = np.asarray(normal, dtype=np.float64)
        n = n / np.linalg.norm(n, axis=-1, keepdims=True)
        return np.maximum(evaluate(irradiance_coefficients(self.sh), n), 0.0)
