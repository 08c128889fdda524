"""The CIE standard general sky (ISO 15469:2004 / CIE S 011/E:2003): fifteen relative
luminance distributions of the sky, from a heavy overcast to a turbid cloudless sky, for
daylighting work and as references for the rendered sky (float64, NumPy only).

Each type is a gradation function of the zenith angle Z of the sky element and an
indicatrix function of its angular distance chi from the Sun:

    phi(Z)   = 1 + a exp(b / cos Z)              (phi = 1 at the horizon, Z = 90 deg)
    f(chi)   = 1 + c (exp(d chi) - exp(d pi / 2)) + e cos^2 chi
    L / L_z  = f(chi) phi(Z) / (f(Z_s) phi(0))    (L_z the zenith luminance, Z_s the Sun's
                                                   zenith angle)

with the parameters a ... e of :data:`CIE_SKY_TYPES` (the standard's table; type 12 is the
CIE standard clear sky of 1973, type 1 close to the traditional overcast sky of Moon &
Spencer 1942). The luminances are scaled by a zenith luminance or by the horizontal
illuminance of the sky alone (the diffuse illuminance, the Sun's beam excluded), the
latter through :func:`horizontal_illuminance_factor` (E_v / L_z in sr, by quadrature).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np
from numpy.typing import ArrayLike

from skydome.errors import ParameterError

__all__ = [
    "CIE_SKY_TYPES",
    "CIESkyType",
    "cie_sky_type",
    "horizontal_illuminance_factor",
    "relative_luminance",
    "sky_luminance",
    "zenith_term",
]


@dataclass(frozen=True)
class CIESkyType:
    """One CIE standard general sky: its number (1-15), the gradation parameters ``a``,
    ``b`` and indicatrix parameters ``c``, ``d``, ``e`` (d in 1/rad), the standard's
    gradation group (I-VI) and indicatrix group (1-6), and its description."""

    number: int
    a: float
    b: float
    c: float
    d: float
    e: float
    gradation_group: str
    indicatrix_group: int
    description: str


_ROWS = (
    (1, 4.0, -0.70, 0.0, -1.0, 0.00, "I", 1,
     "overcast, steep gradation towards the zenith, azimuthal uniformity"),
    (2, 4.0, -0.70, 2.0, -1.5, 0.15, "I", 2,
     "overcast, steep gradation, slight brightening towards the Sun"),
    (3, 1.1, -0.80, 0.0, -1.0, 0.00, "II", 1,
     "overcast, moderate gradation, azimuthal uniformity"),
    (4, 1.1, -0.80, 2.0, -1.5, 0.15, "II", 2,
     "overcast, moderate gradation, slight brightening towards the Sun"),
    (5, 0.0, -1.00, 0.0, -1.0, 0.00, "III", 1, "sky of uniform luminance"),
    (6, 0.0, -1.00, 2.0, -1.5, 0.15, "III", 2,
     "partly cloudy, no gradation towards the zenith, slight brightening towards the Sun"),
    (7, 0.0, -1.00, 5.0, -2.5, 0.30, "III", 3,
     "partly cloudy, no gradation towards the zenith, brighter circumsolar region"),
    (8, 0.0, -1.00, 10.0, -3.0, 0.45, "III", 4,
     "partly cloudy, no gradation towards the zenith, distinct solar corona"),
    (9, -1.0, -0.55, 2.0, -1.5, 0.15, "IV", 2, "partly cloudy, with the Sun obscured"),
    (10, -1.0, -0.55, 5.0, -2.5, 0.30, "IV", 3,
     "partly cloudy, with a brighter circumsolar region"),
    (11, -1.0, -0.55, 10.0, -3.0, 0.45, "IV", 4,
     "white-blue sky with a distinct solar corona"),
    (12, -1.0, -0.32, 10.0, -3.0, 0.45, "V", 4,
     "CIE standard clear sky, low luminance turbidity"),
    (13, -1.0, -0.32, 16.0, -3.0, 0.30, "V", 5, "CIE standard clear sky, polluted atmosphere"),
    (14, -1.0, -0.15, 16.0, -3.0, 0.30, "VI", 5, "cloudless turbid sky with a broad solar corona"),
    (15, -1.0, -0.15, 24.0, -2.8, 0.15, "VI", 6, "white-blue turbid sky with a broad solar corona"),
)  # fmt: skip

#: The fifteen types of ISO 15469:2004 / CIE S 011/E:2003, table 1 (type n at index n - 1).
CIE_SKY_TYPES: tuple[CIESkyType, ...] = tuple(CIESkyType(*row) for row in _ROWS)


def cie_sky_type(sky_type: int | CIESkyType) -> CIESkyType:
    """The type of number ``sky_type`` (1-15), or ``sky_type`` itself."""
    if isinstance(sky_type, CIESkyType):
        return sky_type
    if isinstance(sky_type, bool) or not isinstance(sky_type, (int, np.integer)):
        raise ParameterError(f"a CIE sky type is a number from 1 to 15, got {sky_type!r}")
    if not 1 <= int(sky_type) <= 15:
        raise ParameterError(f"a CIE sky type is a number from 1 to 15, got {sky_type}")
    return CIE_SKY_TYPES[int(sky_type) - 1]


def _gradation(t: CIESkyType, zenith_rad: np.ndarray) -> np.ndarray:
    """phi(Z); at and below the horizon (cos Z <= 0) its horizon value 1 (b < 0)."""
    cos_z = np.cos(zenith_rad)
    safe = np.where(cos_z > 0.0, cos_z, 1.0)
    return np.where(cos_z > 0.0, 1.0 + t.a * np.exp(t.b / safe), 1.0)


def _indicatrix(t: CIESkyType, chi_rad: np.ndarray) -> np.ndarray:
    """f(chi)."""
    return (
        1.0
        + t.c * (np.exp(t.d * chi_rad) - math.exp(t.d * math.pi / 2.0))
        + t.e * np.cos(chi_rad) ** 2
    )


def _check_sun(sun_zenith_deg: float) -> float:
    z = float(sun_zenith_deg)
    if not (math.isfinite(z) and 0.0 <= z <= 90.0):
        raise ParameterError(
            f"the CIE skies are for a Sun above the horizon: its zenith angle must be 0-90 "
            f"deg, got {sun_zenith_deg}"
        )
    return z


def zenith_term(sky_type: int | CIESkyType, sun_zenith_deg: float) -> float:
    """f(Z_s) phi(0): the product the zenith's luminance has (L / L_z divides by it)."""
    t = cie_sky_type(sky_type)
    zs = math.radians(_check_sun(sun_zenith_deg))
    return float(_indicatrix(t, np.asarray(zs)) * _gradation(t, np.asarray(0.0)))


def relative_luminance(
    sky_type: int | CIESkyType,
    zenith_deg: ArrayLike,
    azimuth_deg: ArrayLike,
    sun_zenith_deg: float,
    sun_azimuth_deg: float = 0.0,
) -> np.ndarray:
    """L / L_z of the sky element at zenith angle ``zenith_deg`` (0-90) and azimuth
    ``azimuth_deg`` under a Sun at ``sun_zenith_deg`` (0-90) and ``sun_azimuth_deg`` (any
    azimuth convention, the same for both), for a CIE type (1-15). Arrays broadcast; the
    zenith gives 1."""
    t = cie_sky_type(sky_type)
    zs = math.radians(_check_sun(sun_zenith_deg))
    z = np.radians(np.asarray(zenith_deg, dtype=np.float64))
    if np.any(~np.isfinite(z)) or np.any(z < 0.0) or np.any(z > math.pi / 2 + 1e-12):
        raise ParameterError("zenith angles of sky elements must be within 0-90 deg")
    da = np.radians(np.asarray(azimuth_deg, dtype=np.float64) - float(sun_azimuth_deg))
    cos_chi = math.cos(zs) * np.cos(z) + math.sin(zs) * np.sin(z) * np.cos(da)
    chi = np.arccos(np.clip(cos_chi, -1.0, 1.0))
    return _indicatrix(t, chi) * _gradation(t, z) / zenith_term(t, math.degrees(zs))


@cache
def _illuminance_factor(number: int, sun_zenith_deg: float) -> float:
    # Gauss-Legendre in cos Z on (0, 1) and the periodic trapezoid rule in azimuth; the
    # indicatrix has a cusp at the Sun (exp(d chi)), so convergence is algebraic: 256 x 512
    # nodes agree with 1024 x 2048 within 3e-7 (types 12 and 15, the Sun at 0-60 deg)
    x, w = np.polynomial.legendre.leggauss(256)
    mu, w = 0.5 * (x + 1.0), 0.5 * w
    az = np.arange(512) * (360.0 / 512)
    rel = relative_luminance(number, np.degrees(np.arccos(mu))[:, None], az[None, :],
                             sun_zenith_deg)  # fmt: skip
    return float(np.sum(w * mu * rel.mean(axis=1)) * 2.0 * math.pi)


def horizontal_illuminance_factor(sky_type: int | CIESkyType, sun_zenith_deg: float) -> float:
    """E_v / L_z (sr): the horizontal illuminance of the sky (its diffuse light, the Sun's
    beam excluded) per unit zenith luminance, the integral of L / L_z cos Z over the
    hemisphere (pi for the uniform sky, type 5)."""
    t = cie_sky_type(sky_type)
    return _illuminance_factor(t.number, _check_sun(sun_zenith_deg))


def sky_luminance(
    sky_type: int | CIESkyType,
    zenith_deg: ArrayLike,
    azimuth_deg: ArrayLike,
    sun_zenith_deg: float,
    sun_azimuth_deg: float = 0.0,
    *,
    zenith_luminance: float | None = None,
    horizontal_illuminance: float | None = None,
) -> np.ndarray:
    """Sky luminance (cd/m^2) of a CIE type, scaled by exactly one of ``zenith_luminance``
    (cd/m^2) or ``horizontal_illuminance`` (lx, of the sky alone on a horizontal surface:
    the diffuse illuminance); the arguments as :func:`relative_luminance`'s."""
    if (zenith_luminance is None) == (horizontal_illuminance is None):
        raise ParameterError(
            "give the CIE sky exactly one scale: zenith_luminance (cd/m^2) or "
            "horizontal_illuminance (lx)"
        )
    scale = zenith_luminance if zenith_luminance is not None else horizontal_illuminance
    if not (math.isfinite(float(scale)) and float(scale) >= 0.0):
        raise ParameterError(f"the CIE sky's scale must be finite and >= 0, got {scale}")
    rel = relative_luminance(sky_type, zenith_deg, azimuth_deg, sun_zenith_deg, sun_azimuth_deg)
    if zenith_luminance is not None:
        return float(zenith_luminance) * rel
    return (
        float(horizontal_illuminance)
        / horizontal_illuminance_factor(sky_type, sun_zenith_deg)
        * rel
    )
