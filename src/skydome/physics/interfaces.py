"""Light at the boundary of two media: Fresnel's reflectance, and a medium's refractive index
tabulated by wavelength. Used by the ray optics of water drops
(:mod:`~skydome.physics.sphere_optics`) and of ice crystals
(:mod:`~skydome.physics.crystal_optics`)."""

from __future__ import annotations

import numpy as np

from skydome.errors import ParameterError

__all__ = ["interface_reflectance", "tabulated_index"]


def tabulated_index(wavelength_nm, nodes_nm, values, medium: str) -> np.ndarray:
    """A refractive index tabulated at ``nodes_nm`` (``values``) at ``wavelength_nm``, linear
    between the nodes; a wavelength outside them raises ParameterError naming ``medium``."""
    wl = np.asarray(wavelength_nm, dtype=float)
    if np.any(wl < nodes_nm[0]) or np.any(wl > nodes_nm[-1]):
        raise ParameterError(
            f"{medium}'s refractive index is tabulated for {nodes_nm[0]:g}-{nodes_nm[-1]:g} nm"
        )
    return np.interp(wl, nodes_nm, values)


def interface_reflectance(cos_i, relative_index):
    """(R_perpendicular, R_parallel, cos_t) of light meeting an interface at an angle of
    incidence of cosine ``cos_i`` (> 0) into a medium of ``relative_index`` n2 / n1 (Fresnel's
    equations); total internal reflection gives R = 1 and cos_t = 0."""
    c = np.asarray(cos_i, dtype=float)
    m = np.asarray(relative_index, dtype=float)
    sin2_t = (1.0 - c * c) / (m * m)
    total = sin2_t >= 1.0
    cos_t = np.sqrt(np.maximum(1.0 - sin2_t, 0.0))
    perpendicular = ((c - m * cos_t) / (c + m * cos_t)) ** 2
    parallel = ((m * c - cos_t) / (m * c + cos_t)) ** 2
    return (np.where(total, 1.0, perpendicular), np.where(total, 1.0, parallel),
            np.where(total, 0.0, cos_t))  # fmt: skip
