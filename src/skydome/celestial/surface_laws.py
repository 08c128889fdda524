"""Photometric laws of the sunlit spheres (the Moon, the planets), and their integrals over a
sphere's disk seen from far away. mu0 and mu are the cosines of the incidence and emission
angles at a point of the surface. GLSL twins: ``shaders/celestial/surface_laws.glsl``.

- **Lambert**, L = k mu0: a surface that scatters light many times (cloud decks);
- **Lommel-Seeliger**, L = k mu0 / (mu0 + mu): single scattering in a dark, porous regolith
  (Hapke 2012, "Theory of reflectance and emittance spectroscopy", eq. 9.4).
"""

from __future__ import annotations

import math

import numpy as np


def lambert_law(mu0) -> np.ndarray:
    """The Lambert law mu0 where the point is sunlit (mu0 > 0), else 0.
    GLSL twin: ``lambert_law``."""
    return np.maximum(np.asarray(mu0, dtype=np.float64), 0.0)


def lommel_seeliger_law(mu0, mu) -> np.ndarray:
    """The Lommel-Seeliger law mu0 / (mu0 + mu) where the point is sunlit (mu0 > 0), else 0
    (``mu`` >= 0: the point faces the observer).
    GLSL twin: ``lommel_seeliger_law``."""
    mu0 = np.asarray(mu0, dtype=np.float64)
    return np.where(mu0 > 0.0, mu0 / np.maximum(mu0 + mu, 1e-300), 0.0)


def lambert_phase_function(phase_angle_rad) -> np.ndarray:
    """Disk-integrated Lambert sphere at phase angle a (rad), 1 at a = 0:
    (sin a + (pi - a) cos a) / pi (Russell 1916, ApJ 43, 173)."""
    a = np.clip(np.asarray(phase_angle_rad, dtype=np.float64), 0.0, math.pi)
    return (np.sin(a) + (math.pi - a) * np.cos(a)) / math.pi


def lommel_seeliger_phase_function(phase_angle_rad) -> np.ndarray:
    """Disk-integrated Lommel-Seeliger sphere at phase angle a (rad), 1 at a = 0:
    1 - sin(a/2) tan(a/2) ln(cot(a/4)) (Fairbairn 2005, "Planetary photometry: the
    Lommel-Seeliger law", JRASC 99, 92). At phase 0 the law is 1/2 everywhere, so the
    integral over a disk of solid angle Omega is (Omega / 2) times this."""
    a = np.clip(np.asarray(phase_angle_rad, dtype=np.float64), 1e-9, math.pi - 1e-9)
    phi = 1.0 - np.sin(a / 2) * np.tan(a / 2) * np.log(1.0 / np.tan(a / 4))
    return np.maximum(phi, 0.0)
