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

#: The band-limited cosine lobe's factors per order (Ramamoorthi & Hanrahan eq. 12 / pi).
_COSINE_LOBE = (math.pi, 2.0 * math.pi / 3.0, math.pi / 4.0)


def sh_basis(directions: np.ndarray) -> np.ndarray:
    """The nine real spherical harmonics Y_00, Y_1-1, Y_10, Y_11, Y_2-2 ... Y_22 at unit
    ``directions`` (..., 3) (x east, y north, z up): (..., 9)."""
    x, y, z = directions[..., 0], directions[..., 1], directions[..., 2]
    return np.stack([
        np.full_like(x, 0.282095),
        0.488603 * y, 0.488603 * z, 0.488603 * x,
        1.092548 * x * y, 1.092548 * y * z, 0.315392 * (3.0 * z * z - 1.0),
        1.092548 * x * z, 0.546274 * (x * x - y * y),
    ], axis=-1)  # fmt: skip


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
        sh = np.einsum("hwk,hw,hwc->kc", sh_basis(d), omega, radiance)
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
        basis = sh_basis(n / np.linalg.norm(n, axis=-1, keepdims=True))
        lobe = np.array([_COSINE_LOBE[0]] + [_COSINE_LOBE[1]] * 3 + [_COSINE_LOBE[2]] * 5)
        return np.maximum(basis @ (lobe[:, None] * self.sh), 0.0)
