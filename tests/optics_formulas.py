"""Textbook optics the optics tests hold the code to (the code itself computes none of it):

- a prism of apex angle A and index n deviates light least by D = 2 asin(n sin(A / 2)) - A
  (60 deg: the 22 deg halo; 90 deg: the 46 deg halo); horizontal plates see the light at
  elevation e through Bravais' effective index sqrt(n^2 - sin^2 e) / cos e (the sun dogs'
  azimuth; Tape 1994, "Atmospheric Halos", ch. 2);
- Airy (1838; van de Hulst 1957 sec. 13.22): near the primary bow the rays' deviation is a
  parabola in the impact parameter b, theta = theta_R + D'' (b - b_R)^2 / 2, so the light goes
  as Ai^2(-z), z = (theta - theta_R) x^(2/3) / (D'' / 2)^(1/3) for size parameter x: maxima at
  AIRY_MAXIMA, the geometric bow (z = 0) at AIRY_EDGE of the first maximum.
"""

from __future__ import annotations

import math

AIRY_MAXIMA = (1.01879, 3.24820)
AIRY_EDGE = 0.4407  # Ai(0)^2 / Ai(-1.01879)^2


def minimum_deviation_deg(n: float, apex_deg: float) -> float:
    """A prism's minimum deviation (deg)."""
    a = math.radians(apex_deg)
    return math.degrees(2.0 * math.asin(n * math.sin(a / 2.0)) - a)


def sun_dog_deg(n: float, sun_deg: float) -> float:
    """The sun dogs' inner edge in azimuth from the Sun (deg), plates, the Sun ``sun_deg`` up."""
    e = math.radians(sun_deg)
    return minimum_deviation_deg(math.sqrt(n * n - math.sin(e) ** 2) / math.cos(e), 60.0)


def airy_unit_deg(n: float, x: float) -> float:
    """One unit of Airy's z about the primary bow (deg): (D'' / 2)^(1/3) / x^(2/3), with D''
    the rays' d^2 theta / d b^2 (rad) at their stationary impact parameter (numerical)."""
    b = math.sqrt((4.0 - n * n) / 3.0)  # cos^2 i = (n^2 - 1) / 3

    def theta(bb):
        i, r = math.asin(bb), math.asin(bb / n)
        return 2.0 * (i - r) + math.pi - 2.0 * r

    h = 1e-4
    curvature = abs(theta(b + h) - 2.0 * theta(b) + theta(b - h)) / h**2
    return math.degrees((curvature / 2.0) ** (1.0 / 3.0) / x ** (2.0 / 3.0))
