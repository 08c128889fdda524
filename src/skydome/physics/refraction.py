"""Atmospheric refraction: the laws, the weather's factor on them, their per-pixel form, and
the dip of the horizon. GLSL twin: ``shaders/common/refraction.glsl``.

Bennett (1982) gives the refraction R to subtract from an apparent altitude, Saemundsson
(1986) the one to add to a true altitude (Meeus, Astronomical Algorithms, eq. 16.3-16.4):
both R = a / tan(h + b / (h + c)) arcmin, scaled by the weather's (P / 1010 hPa)(283 K / T).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from skydome.physics.constants import (
    EARTH_MEAN_RADIUS_M,
    STANDARD_PRESSURE_HPA,
    STANDARD_TEMPERATURE_C,
    ZERO_CELSIUS_K,
)

#: (a arcmin, b deg, c deg, lowest altitude deg) of Bennett's law (apparent -> true): defined
#: for h0 >= -1 deg, accurate to 0.07' over 0-90 deg.
BENNETT = (1.0, 7.31, 4.4, -1.0)
#: The same of Saemundsson's law (true -> apparent), consistent with Bennett's to 4".
SAEMUNDSSON = (1.02, 10.3, 5.11, -1.9)
#: Nodes of the per-pixel refraction table over the sine of the apparent elevation, -1 to 1.
REFRACTION_TABLE_SIZE = 4096


def refraction_scale(pressure_hPa, temperature_C) -> np.ndarray | float:
    """The weather's factor (P / 1010 hPa)(283 K / (273 K + T)) on the refraction laws (0
    when the pressure is 0: no refraction)."""
    p = np.asarray(pressure_hPa, dtype=np.float64) / STANDARD_PRESSURE_HPA
    t = (ZERO_CELSIUS_K + STANDARD_TEMPERATURE_C) / (
        ZERO_CELSIUS_K + np.asarray(temperature_C, dtype=np.float64)
    )
    out = p * t
    return float(out) if out.ndim == 0 else out


def cot_refraction(alt_deg, law: tuple[float, float, float, float], scale=1.0) -> np.ndarray:
    """R = a / tan(h + b / (h + c)) arcmin for ``law`` = (a, b, c, lowest), 0 below the
    lowest altitude and at the zenith, times ``scale`` (the weather's factor)."""
    a, b, c, lowest = law
    h = np.asarray(alt_deg, dtype=float)
    hc = np.maximum(h, lowest)
    r = a / np.tan(np.radians(hc + b / (hc + c)))
    r = np.where(h >= lowest, r, 0.0)
    r = np.where(h >= 90.0, 0.0, np.maximum(r, 0.0))
    return r * scale


def refraction_bennett(
    apparent_alt_deg, pressure_hPa=STANDARD_PRESSURE_HPA, temperature_C=STANDARD_TEMPERATURE_C
) -> np.ndarray:
    """Refraction R (arcmin) to subtract from an apparent altitude (deg) to get the true one
    (Bennett's law; 0 below -1 deg: a body so far below the horizon is not seen).
    GLSL twin: ``refraction_bennett``."""
    scale = refraction_scale(pressure_hPa, temperature_C)
    return cot_refraction(apparent_alt_deg, BENNETT, scale)


def refraction_saemundsson(
    true_alt_deg, pressure_hPa=STANDARD_PRESSURE_HPA, temperature_C=STANDARD_TEMPERATURE_C
) -> np.ndarray:
    """Refraction R (arcmin) to add to a true (airless) altitude (deg) to get the apparent
    one (Saemundsson's law; 0 below -1.9 deg, where the apparent altitude is about -1 deg).
    GLSL twin: ``refraction_saemundsson``."""
    scale = refraction_scale(pressure_hPa, temperature_C)
    return cot_refraction(true_alt_deg, SAEMUNDSSON, scale)


def refraction_flattening(apparent_alt_deg: float, scale: float = 1.0) -> float:
    """How much the refraction compresses the sky in altitude at ``apparent_alt_deg``: the
    derivative of the apparent altitude by the true one, 1 / (1 - dR/dh) with R Bennett's
    law times ``scale`` (the weather's factor); 1 without refraction. Radiance is kept along
    a ray, so a low Sun's flattened disk gives this fraction of its irradiance (0.96 at 3.7
    deg, 0.89 at 1 deg): the drawn disk's light, as the renderer maps each pixel back to the
    airless sky. A central difference of 0.01 deg (the law is smooth there)."""
    h = float(apparent_alt_deg)
    step = 0.01
    if h >= 90.0 - step or h < BENNETT[3] + step:
        return 1.0
    dr_arcmin = cot_refraction(h + step, BENNETT, scale) - cot_refraction(h - step, BENNETT, scale)
    return float(1.0 / (1.0 - dr_arcmin / (60.0 * 2.0 * step)))


def refract_enu(
    enu, pressure_hPa=STANDARD_PRESSURE_HPA, temperature_C=STANDARD_TEMPERATURE_C
) -> tuple[np.ndarray, np.ndarray]:
    """Apparent unit ENU vectors (..., 3) of airless ones, and their apparent altitudes (rad):
    each raised towards the zenith along its vertical by Saemundsson's refraction for the
    weather, its horizontal direction (x, y) / |(x, y)| kept (no azimuth round trip). The
    zenith and the nadir stay as they are."""
    v = np.asarray(enu, dtype=np.float64)
    horizontal = np.hypot(v[..., 0], v[..., 1])
    alt0 = np.arctan2(v[..., 2], horizontal)
    alt = alt0 + np.radians(
        refraction_saemundsson(np.degrees(alt0), pressure_hPa, temperature_C) / 60.0
    )
    seen = horizontal > 0.0
    scale = np.where(seen, np.cos(alt) / np.where(seen, horizontal, 1.0), 0.0)
    out = np.stack([v[..., 0] * scale, v[..., 1] * scale, np.sin(alt)], axis=-1)
    return np.where(seen[..., None], out, v), alt


#: Nodes of the tabulated Saemundsson refraction (:func:`refract_altitudes_tabulated`), evenly
#: spaced in the airless altitude from the law's lowest (-1.9 deg) to 90 deg (0.0056 deg
#: apart): linear interpolation between them is within 0.01" of the law (tested).
SAEMUNDSSON_TABLE_SIZE = 16384


@lru_cache(maxsize=8)
def saemundsson_table(scale: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Saemundsson's refraction at SAEMUNDSSON_TABLE_SIZE airless altitudes from the law's
    lowest to 90 deg, for the weather's factor ``scale``, as linear pieces (read-only): the
    apparent altitude (rad) and cos(apparent) / cos(airless) at each node, and their steps
    to the next node: what :func:`refract_enu` computes per vector, once."""
    lowest = np.radians(SAEMUNDSSON[3])
    h0 = np.linspace(lowest, 0.5 * np.pi, SAEMUNDSSON_TABLE_SIZE)
    alt = h0 + np.radians(cot_refraction(np.degrees(h0), SAEMUNDSSON, scale) / 60.0)
    ratio = np.cos(alt) / np.maximum(np.cos(h0), 1e-300)
    ratio[-1] = 1.0  # the zenith: nothing to turn
    out = (alt, np.append(np.diff(alt), 0.0), ratio, np.append(np.diff(ratio), 0.0))
    for a in out:
        a.setflags(write=False)
    return out


def refract_altitudes_tabulated(
    enu: np.ndarray, airless_alt_rad: np.ndarray, scale: float
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`refract_enu` for many unit vectors ``enu`` (N, 3) whose airless altitudes
    ``airless_alt_rad`` (N,) are known, by linear interpolation in
    :func:`saemundsson_table` (the weather's factor ``scale``, :func:`refraction_scale`):
    (apparent unit vectors, apparent altitudes rad). Less than half the law's cost for a
    catalogue of stars."""
    alt, ratio = refraction_tabulated(airless_alt_rad, scale)
    out = enu * ratio[:, None]
    out[:, 2] = np.sin(alt)
    return out, alt


def refraction_tabulated(
    airless_alt_rad: np.ndarray, scale: float
) -> tuple[np.ndarray, np.ndarray]:
    """The apparent altitudes (rad) of airless altitudes ``airless_alt_rad`` (N,) by
    Saemundsson's law tabulated for the weather's factor ``scale``, and the factor
    cos(apparent) / cos(airless) that scales a unit vector's horizontal components
    (:func:`refract_altitudes_tabulated`; the vertical one is sin(apparent))."""
    alt0, alt_step, ratio0, ratio_step = saemundsson_table(float(scale))
    lowest = math.radians(SAEMUNDSSON[3])
    per_rad = (SAEMUNDSSON_TABLE_SIZE - 1) / (0.5 * math.pi - lowest)
    x = airless_alt_rad - lowest
    x *= per_rad
    np.clip(x, 0.0, SAEMUNDSSON_TABLE_SIZE - 1.0, out=x)
    i = x.astype(np.intp)
    f = x - i
    alt = alt_step[i]
    alt *= f
    alt += alt0[i]
    ratio = ratio_step[i]
    ratio *= f
    ratio += ratio0[i]
    below = airless_alt_rad < lowest  # the law refracts nothing there
    alt = np.where(below, airless_alt_rad, alt)
    ratio[below] = 1.0
    return alt, ratio


def airless_offset(z, scale: float = 1.0) -> np.ndarray:
    """Float64 twin of ``airless_direction`` in ``shaders/common/refraction.glsl`` (Bennett's
    law, then two Saemundsson steps), as one number per sine ``z`` of the apparent
    elevation: the airless direction of a unit apparent one ``d`` is parallel to
    ``d + k (z d - up)`` with k = tan(R) / cos(h), R the refraction (rad). ``scale`` is the
    weather's factor (:func:`refraction_scale`); 0 gives k = 0.
    GLSL twin: ``airless_direction``."""
    z = np.clip(np.asarray(z, dtype=np.float64), -1.0, 1.0)
    c = np.sqrt(np.maximum(1.0 - z * z, 0.0))
    h = np.degrees(np.arctan2(z, c))
    r = np.radians(cot_refraction(h, BENNETT, scale) / 60.0)
    for _ in range(2):
        r = np.radians(cot_refraction(h - np.degrees(r), SAEMUNDSSON, scale) / 60.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(c > 0.0, np.tan(r) / c, 0.0)


@lru_cache(maxsize=8)
def airless_offset_table(scale: float) -> np.ndarray:
    """:func:`airless_offset` at REFRACTION_TABLE_SIZE nodes z = -1 + 2 i / (n - 1), float32
    (read-only), for ``common/airless_table.glsl``: one linear fetch by the pixel's z instead
    of the refraction's trigonometry (the node at the zenith, where ``z d - up`` vanishes,
    takes its neighbour's value)."""
    n = REFRACTION_TABLE_SIZE
    k = airless_offset(np.linspace(-1.0, 1.0, n), scale)
    k[-1] = k[-2]
    out = k.astype(np.float32)
    out.setflags(write=False)
    return out


def airless_offset_lookup(z, scale: float = 1.0) -> np.ndarray:
    """Float64 twin of the shaders' fetch: :func:`airless_offset_table` interpolated linearly
    in z between its nodes.
    GLSL twin: ``airless_from_table``."""
    t = airless_offset_table(float(scale)).astype(np.float64)
    x = (np.clip(np.asarray(z, dtype=np.float64), -1.0, 1.0) + 1.0) * 0.5 * (len(t) - 1)
    i = np.clip(np.floor(x).astype(int), 0, len(t) - 2)
    f = x - i
    return (1.0 - f) * t[i] + f * t[i + 1]


def horizon_dip_sin(observer_height_m, radius_m: float = EARTH_MEAN_RADIUS_M) -> float:
    """sin of the dip of the ground's horizon below the horizontal for an observer at
    ``observer_height_m`` above a sphere of ``radius_m`` (default the Earth's mean radius):
    a ray with elevation below -dip hits it."""
    r = radius_m + max(float(observer_height_m), 0.0)
    return float(np.sqrt(max(1.0 - (radius_m / r) ** 2, 0.0)))
