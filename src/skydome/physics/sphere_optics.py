"""Geometric optics of a water sphere: rain drops' phase function from their rays.

A drop much larger than the wavelength scatters as its rays do (van de Hulst 1957, "Light
Scattering by Small Particles", ch. 12), plus the diffraction around its edge, which removes
as much light again into a peak a fraction of a degree wide (extinction efficiency 2:
skydome.physics.droplets). A ray meeting the drop at impact parameter b = sin i (i its angle
of incidence; sin i = n sin r inside) leaves after p chords (p = 0: reflected outside; 1:
straight through; 2: one internal reflection, the primary rainbow; 3: the secondary ...),
deviated by

    D_0 = pi - 2 i,    D_p = 2 (i - r) + (p - 1) (pi - 2 r)    (p >= 1)

carrying, for each polarisation with Fresnel reflectance R, the share R (p = 0) or
(1 - R)^2 R^(p - 1). Where D_p is stationary in i (p >= 2) the rays pile up at the bows'
angles (Descartes), whose minimum deviation the supernumeraries and the bow's width refine
(Airy theory, beyond rays). Water's refractive index is Hale & Querry (1973)'s.
"""

from __future__ import annotations

import math

import numpy as np

from skydome.errors import ParameterError
from skydome.physics.interfaces import interface_reflectance, tabulated_index

#: Water's real refractive index at 25 C (Hale & Querry 1973, Appl. Opt. 12, 555, table 1)
#: at wavelengths (nm); absorption is negligible in the visible (k < 1e-8).
WATER_INDEX_NM = (350.0, 375.0, 400.0, 425.0, 450.0, 475.0, 500.0, 525.0, 550.0, 575.0,
                  600.0, 625.0, 650.0, 675.0, 700.0, 725.0, 750.0, 775.0, 800.0)  # fmt: skip
WATER_INDEX = (1.343, 1.341, 1.339, 1.338, 1.337, 1.336, 1.335, 1.334, 1.333, 1.333, 1.332,
               1.332, 1.331, 1.331, 1.331, 1.330, 1.330, 1.330, 1.329)  # fmt: skip
#: Ray orders followed: reflection, transmission and up to six internal reflections (the
#: rest carries R^7 ~ 1e-9 of the light except in grazing rays; it is renormalised away).
MAX_ORDER = 7


def water_index(wavelength_nm) -> np.ndarray:
    """Water's refractive index (real part) at ``wavelength_nm`` (350-800 nm, linear between
    Hale & Querry's nodes)."""
    return tabulated_index(wavelength_nm, WATER_INDEX_NM, WATER_INDEX, "water")


def fresnel_reflectance(cos_i, n: float) -> tuple[np.ndarray, np.ndarray]:
    """(R_perpendicular, R_parallel) of a ray entering water of index ``n`` (> 1) from air at
    an angle of incidence of cosine ``cos_i``; the same for the ray leaving at the refracted
    angle (Stokes' relations)."""
    perpendicular, parallel, _ = interface_reflectance(cos_i, n)
    return perpendicular, parallel


def ray_orders(impact, n: float, max_order: int = MAX_ORDER):
    """For rays at impact parameters ``impact`` (b = sin i, 0-1; any shape): the scattering
    angles (rad, 0-pi) of orders p = 0..max_order (axis 0) and each order's share of the
    ray's light (unpolarised: the mean of the two polarisations'). The shares of all orders
    add up to 1 as the order grows (no absorption)."""
    b = np.asarray(impact, dtype=float)
    i = np.arcsin(np.clip(b, 0.0, 1.0))
    r = np.arcsin(np.clip(b / n, 0.0, 1.0))
    r_perp, r_par = fresnel_reflectance(np.cos(i), n)
    angles, shares = [], []
    for p in range(max_order + 1):
        deviation = math.pi - 2.0 * i if p == 0 else 2.0 * (i - r) + (p - 1) * (math.pi - 2.0 * r)
        angles.append(np.arccos(np.cos(deviation)))
        if p == 0:
            shares.append(0.5 * (r_perp + r_par))
        else:
            shares.append(
                0.5 * ((1 - r_perp) ** 2 * r_perp ** (p - 1) + (1 - r_par) ** 2 * r_par ** (p - 1))
            )
    return np.array(angles), np.array(shares)


def descartes_angle_deg(n: float, order: int) -> float:
    """The scattering angle (deg) of the bow of ``order`` (2: primary, 3: secondary) for
    index ``n``: where the deviation is stationary, cos^2 i = (n^2 - 1) / (p^2 - 1) with p the
    order's chords (Descartes 1637; van de Hulst eq. 12.43)."""
    p = int(order)
    if p < 2:
        raise ParameterError("bows are of order 2 (primary) or more")
    i = math.acos(math.sqrt((n * n - 1.0) / (p * p - 1.0)))
    r = math.asin(math.sin(i) / n)
    deviation = 2.0 * (i - r) + (p - 1) * (math.pi - 2.0 * r)
    return math.degrees(math.acos(math.cos(deviation)))


def geometric_phase(n: float, theta_edges_deg, rays: int = 2_000_000) -> np.ndarray:
    """The phase function (1/sr, normalised over the sphere) of the light a water sphere of
    index ``n`` refracts and reflects (diffraction apart), averaged over bins of scattering
    angle with edges ``theta_edges_deg`` (0 to 180): ``rays`` rays spread evenly over the
    drop's cross-section (midpoints in b^2), each order's share binned at its angle."""
    edges = np.radians(np.asarray(theta_edges_deg, dtype=float))
    if edges[0] != 0.0 or abs(edges[-1] - math.pi) > 1e-12 or np.any(np.diff(edges) <= 0):
        raise ParameterError("the bins' edges must rise from 0 to 180 deg")
    b = np.sqrt((np.arange(rays) + 0.5) / rays)
    angles, shares = ray_orders(b, n)
    light = np.zeros(edges.size - 1)
    for a, s in zip(angles, shares, strict=True):
        light += np.histogram(a, bins=edges, weights=s)[0]
    solid_angle = 2.0 * math.pi * (np.cos(edges[:-1]) - np.cos(edges[1:]))
    return light / light.sum() / solid_angle
