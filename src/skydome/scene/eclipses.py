"""Eclipses in a sky's state: how much sunlight the Moon hides, and the Earth's shadow on the
Moon with the light its atmosphere refracts into it.

Solar: :func:`luminous_hidden_fraction` is the fraction of the Sun's luminous flux (the
solar spectrum times V(lambda)) the Moon hides, each wavelength's disk limb darkened with
its own law (``skydome.celestial.limb_darkening``, Neckel 2005) and occulted exactly
(``skydome.astro.eclipses.occulted_fraction``).

Lunar: the umbra is lit by sunlight bent into it by the Earth's atmosphere. A ray from the
Sun's centre grazing the Earth at tangent height h is bent by delta(h) = 2 R_0 rho(h) /
rho(0) (twice the astronomical refraction at the horizon, R_0 = 34.5' at sea level for the
standard weather, Bennett; proportional to the air's density at the tangent point, the
Rayleigh profile of the ``earth`` preset) and reaches the Moon's distance D at
d(h) = (R_E + h) - D delta(h) from the shadow's axis (negative: across it). Its light has
passed the whole limb path: the transmittance of the tangent ray through the ``earth``
preset (``skydome.atmosphere.columns``: Rayleigh, aerosol and ozone, the same coefficients
as the sky's tables), times a cloud factor (rays below ``CLOUD_TOP_KM`` cross the global
cloud deck: a fraction ``CLOUD_COVER`` is blocked, an assumption). The ring of the limb of
width dh spreads over the ring of radius |d| and width |dd/dh| dh at the Moon, so the
irradiance relative to direct sunlight is

    F_point(d) = sum over the h with |d(h)| = d of (R_E + h) T(h) / (d |dd/dh|),

and the Sun's finite disk (radius s_s, D s_s ~ 1800 km at the Moon) smooths it: F is the
mean of F_point over the points of the Sun's disk, each shifting the pattern by D times its
offset (a grid of 112 points, limb darkened at 550 nm).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from skydome.astro.eclipses import (
    DANJON_EARTH_ENLARGEMENT,
    disk_overlap_fraction,
    occulted_fraction,
)
from skydome.atmosphere import columns
from skydome.atmosphere.presets import preset
from skydome.celestial.limb_darkening import limb_coefficients, limb_darkening
from skydome.core.lights import Light, LunarEclipseView, SolarEclipseView
from skydome.physics.constants import EARTH_MEAN_RADIUS_M
from skydome.spectra.tables import photopic_efficiency, solar_irradiance

__all__ = [
    "CLOUD_COVER",
    "CLOUD_TOP_KM",
    "luminous_hidden_fraction",
    "solar_eclipse_view",
    "umbra_light",
    "lunar_eclipse_view",
]

#: Global cloud deck for the limb rays: rays with tangent heights below CLOUD_TOP_KM lose
#: CLOUD_COVER of their light (ISCCP global mean cloud amount ~0.66, of which the low and
#: middle clouds under ~10 km cover about half the globe; an assumption of this model).
CLOUD_TOP_KM = 10.0
CLOUD_COVER = 0.5
#: Horizontal refraction at sea level for the standard weather (Bennett, 0 deg): 34.5'.
HORIZONTAL_REFRACTION_RAD = math.radians(34.5 / 60.0)
_LUMINOUS_WL = np.arange(380.0, 781.0, 10.0)


@functools.cache
def _luminous_weights() -> tuple[np.ndarray, np.ndarray]:
    w = solar_irradiance(_LUMINOUS_WL) * photopic_efficiency(_LUMINOUS_WL)
    return w / w.sum(), limb_coefficients(_LUMINOUS_WL)


def luminous_hidden_fraction(separation_rad, sun_radius_rad, moon_radius_rad) -> np.ndarray:
    """Fraction of the Sun's luminous flux hidden by the Moon (angles in radians, broadcast
    together): the per-wavelength limb-darkened fractions weighted by the solar spectrum
    times V(lambda), 380-780 nm."""
    w, coeffs = _luminous_weights()
    f = occulted_fraction(separation_rad, sun_radius_rad, moon_radius_rad, coeffs)
    return np.asarray(f @ w)


def solar_eclipse_view(sun: Light, moon: Light) -> SolarEclipseView | None:
    """The eclipse of ``sun`` by ``moon`` (the observer's Lights), None when the disks do
    not overlap."""
    cross = np.linalg.norm(np.cross(sun.direction_true, moon.direction_true))
    sep = math.atan2(cross, float(np.dot(sun.direction_true, moon.direction_true)))
    if sep >= sun.angular_radius_rad + moon.angular_radius_rad:
        return None
    hidden = float(luminous_hidden_fraction(sep, sun.angular_radius_rad, moon.angular_radius_rad))
    return SolarEclipseView(
        hidden_fraction=hidden,
        moon_km=np.asarray(moon.direction_true, dtype=np.float64) * moon.distance_km,
        moon_radius_km=moon.distance_km * math.sin(moon.angular_radius_rad),
    )


@functools.cache
def _limb_transmittance(wavelengths: tuple[float, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Tangent heights (km) and the transmittance (H, W) of the whole limb path through the
    ``earth`` preset, with the cloud factor."""
    params = preset("earth")
    h_km = np.linspace(0.0, 40.0, 161)
    r = params.bottom_radius_m + h_km * 1000.0
    half = columns.distance_to_top(params, r, np.zeros_like(r))
    col = columns.column(params, r, np.zeros_like(r), half, intervals=200) * 2.0
    tau = columns.optical_depth(params.coefficients(np.asarray(wavelengths)), col)
    cloud = np.where(h_km < CLOUD_TOP_KM, 1.0 - CLOUD_COVER, 1.0)
    density = params.rayleigh_density.density(h_km * 1000.0)
    return h_km, np.exp(-tau) * cloud[:, None], density


def umbra_light(
    wavelengths_nm, moon_distance_km: float, sun_radius_rad: float, distances_km
) -> np.ndarray:
    """Irradiance of the sunlight refracted by the Earth's atmosphere at ``distances_km``
    from the shadow's axis at the Moon's distance, relative to direct sunlight, per
    wavelength: shape (len(distances_km), W). The module's docstring gives the model."""
    wl = tuple(float(x) for x in np.asarray(wavelengths_nm, dtype=float))
    h_km, trans, density = _limb_transmittance(wl)
    re_km = EARTH_MEAN_RADIUS_M / 1000.0
    dist = float(moon_distance_km)
    delta = 2.0 * HORIZONTAL_REFRACTION_RAD * density  # bending at each tangent height
    d = re_km + h_km - dist * delta  # signed arrival distance from the axis
    # The Sun's disk: points on a grid, limb darkened at 550 nm, shifting the arrival.
    g = (np.arange(12) + 0.5) / 12 * 2.0 - 1.0
    gx, gy = np.meshgrid(g, g)
    inside = gx * gx + gy * gy < 1.0
    px, py = gx[inside], gy[inside]
    wsun = limb_darkening(np.sqrt(np.maximum(1.0 - px * px - py * py, 0.0)), 550.0)
    wsun = wsun / wsun.sum()
    shift = dist * sun_radius_rad
    # Each limb ring element lands on a ring of radius |d| (energy conserved between rings):
    # deposited into radial bins around the target distances, for each point of the Sun's
    # disk (which shifts it by D times the point's offset), averaged over the azimuth.
    q = np.asarray(distances_km, dtype=float)
    edges = np.concatenate([[0.0], 0.5 * (q[1:] + q[:-1]), [q[-1] + 0.5 * (q[-1] - q[-2])]])
    ring_area = np.pi * (edges[1:] ** 2 - edges[:-1] ** 2)
    hf = np.linspace(h_km[0], h_km[-1], 801)  # finer than a bin's width in d
    df = np.interp(hf, h_km, d)
    tf = np.stack([np.interp(hf, h_km, trans[:, k]) for k in range(len(wl))], axis=-1)
    energy = 2.0 * np.pi * (re_km + hf) * (hf[1] - hf[0])  # km^2 of the limb's ring elements
    phi = (np.arange(32) + 0.5) / 32 * 2.0 * np.pi
    cphi, sphi = np.cos(phi), np.sin(phi)
    rows = np.repeat(np.arange(len(hf))[:, None], len(phi), axis=1).ravel()
    spread = np.zeros(len(q) * len(hf))  # how much of each ring element lands in each bin
    for sx, sy, ws in zip(px, py, wsun, strict=True):
        x = df[:, None] * cphi - sx * shift
        y = df[:, None] * sphi - sy * shift
        rad = np.hypot(x, y).ravel()
        k = np.searchsorted(edges, rad) - 1
        ok = (k >= 0) & (k < len(q))
        spread += np.bincount(k[ok] * len(hf) + rows[ok], minlength=spread.size) * (ws / len(phi))
    out = spread.reshape(len(q), len(hf)) @ (energy[:, None] * tf)
    return out / ring_area[:, None]


def lunar_eclipse_view(
    sun: Light, moon: Light, earth_km: np.ndarray, wavelengths_nm
) -> LunarEclipseView | None:
    """The Earth's shadow on ``moon`` (None when the Moon is clear of the penumbra).
    ``earth_km``: the Earth's centre from the observer (ENU, km)."""
    sun_km = np.asarray(sun.direction_true) * sun.distance_km
    moon_km = np.asarray(moon.direction_true) * moon.distance_km
    earth = np.asarray(earth_km, dtype=np.float64)
    axis = (earth - sun_km) / np.linalg.norm(earth - sun_km)  # Sun -> Earth, the shadow's axis
    rel = moon_km - earth
    along = float(rel @ axis)
    if along <= 0:
        return None
    perp = float(np.linalg.norm(rel - along * axis))
    r_earth = EARTH_MEAN_RADIUS_M / 1000.0 * DANJON_EARTH_ENLARGEMENT
    sun_r = sun.angular_radius_rad
    penumbra_km = r_earth + along * (sun_r + r_earth / float(np.linalg.norm(earth - sun_km)))
    moon_r_km = moon.distance_km * math.sin(moon.angular_radius_rad)
    if perp > penumbra_km + moon_r_km:
        return None
    q = np.linspace(0.0, penumbra_km * 1.05, 48)
    light = umbra_light(wavelengths_nm, along, sun_r, q)
    # the disk-mean brightness factor (direct + refracted), luminance-weighted, on a grid
    g = (np.arange(24) + 0.5) / 24 * 2.0 - 1.0
    gx, gy = np.meshgrid(g, g)
    inside = gx * gx + gy * gy < 1.0
    side = np.cross(axis, [0.0, 0.0, 1.0] if abs(axis[2]) < 0.9 else [1.0, 0.0, 0.0])
    side /= np.linalg.norm(side)
    up = np.cross(axis, side)
    c = rel - along * axis
    pts = c + moon_r_km * (gx[inside][:, None] * side + gy[inside][:, None] * up)
    d_pts = np.linalg.norm(pts, axis=-1)
    vis = _sun_visible_from_moon(
        d_pts, along, sun_r, r_earth, float(np.linalg.norm(earth - sun_km))
    )
    w = solar_irradiance(np.asarray(wavelengths_nm)) * photopic_efficiency(
        np.asarray(wavelengths_nm)
    )
    w = w / w.sum() if w.sum() > 0 else np.full(len(w), 1.0 / len(w))
    refr = np.stack([np.interp(d_pts, q, light[:, k]) for k in range(light.shape[1])], -1) @ w
    factor = float(np.mean(vis + refr))
    return LunarEclipseView(
        sun_km=sun_km,
        earth_km=earth,
        earth_radius_km=r_earth,
        umbra_distances_km=q,
        umbra_light=light,
        wavelengths_nm=np.asarray(wavelengths_nm, dtype=np.float64),
        moon_light_factor=factor,
    )


def _sun_visible_from_moon(d_km, along_km, sun_r, r_earth_km, sun_earth_km) -> np.ndarray:
    """Fraction of the Sun's uniform disk seen from points ``d_km`` off the shadow's axis,
    ``along_km`` behind the Earth: the Earth (radius r_earth_km) in front of it."""
    earth_r = np.arcsin(np.minimum(r_earth_km / along_km, 1.0))
    d = np.asarray(d_km)
    sep = d / along_km - d / (sun_earth_km + along_km)  # both seen off the axis, same side
    return 1.0 - disk_overlap_fraction(sep, sun_r, earth_r)
