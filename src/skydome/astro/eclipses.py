"""Solar and lunar eclipses: occulted fractions, shadow cones and contact times (NumPy).

Solar eclipses, seen from a place
---------------------------------
The Moon's disk (topocentric semidiameter ``r_m``) and the Sun's (``r_s``) with centres
``sep`` apart (all angles, radians). The fraction of the Sun's flux the Moon hides is

    F = int_0^1 I(mu(r)) a(r) 2 pi r dr / int_0^1 I(mu(r)) 2 pi r dr,

``r`` the radius on the Sun's disk in units of its radius, ``mu = sqrt(1 - r^2)``, ``I`` the
limb-darkening law (a polynomial sum_k A_k mu^k; ``skydome.celestial.limb_darkening`` gives
the Sun's, Neckel 2005) and ``a(r)`` the fraction of the circle of radius ``r`` that lies
inside the Moon's disk, acos((r^2 + z^2 - p^2) / (2 r z)) / pi with z = sep / r_s and
p = r_m / r_s (exact for two circles; the disks are small enough to be flat to 1e-9).
:func:`occulted_fraction` integrates it with Gauss-Legendre on the pieces of ``r`` between
the kinks of ``a`` (|z - p| and z + p) in the variable psi (r = sin psi), where ``mu`` is
smooth: 1e-9 against a brute-force sum for the Sun's law (``tests/test_solar_eclipse.py``).

Contacts (C1..C4): the topocentric separation of the apparent centres equals r_s + r_m
(C1, C4) and |r_s - r_m| (C2, C3; total when r_m > r_s, annular otherwise), found as the
roots of ``sep - (r_s +- r_m)`` by bisection on a sampled grid (:func:`solar_contacts`).

Lunar eclipses (geocentric)
---------------------------
The Earth's shadow at the Moon's distance, Danjon's rule (the Earth's radius enlarged by
1/85 for its atmosphere; Danjon 1951, used by the Astronomical Almanac and by Espenak &
Meeus for the eclipse canon since 2016): with pi_m, pi_s the Moon's and the Sun's
horizontal parallaxes and s_s the Sun's semidiameter,

    penumbra radius rho_p = 1.01176 pi_m + pi_s + s_s,   umbra rho_u = 1.01176 pi_m + pi_s - s_s.

Contacts: P1/P4 when the Moon's centre is rho_p + s_m from the shadow's axis (the apparent
antisolar point), U1/U4 at rho_u + s_m, U2/U3 at rho_u - s_m (:func:`lunar_contacts`).

Danjon scale (Danjon 1921; Sky & Telescope's wording): L = 0 very dark, the Moon almost
invisible at mid-totality; 1 dark, grey or brownish; 2 deep red or rust, a very dark central
shadow; 3 brick red, the umbra often rimmed by a bright yellow edge; 4 very bright copper red
or orange. The scale is visual; :func:`danjon_from_luminance_ratio` reads it from the
mid-totality Moon's brightness relative to the full Moon (dm = 2.5 log10(1 / q) magnitudes)
by a linear rule of our own between two anchors: totally eclipsed Moons are observed from
about V = -3.5 (bright, L = 4, dm ~ 9) down to V ~ +2.5 (L = 0, dm ~ 15) against the full
Moon's -12.7, so L = (15 - dm) / 1.5 clipped to 0..4; a guide, not a calibration.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from skydome.astro import moon as moon_mod
from skydome.astro import sun as sun_mod
from skydome.astro.frames import AU_KM
from skydome.astro.observer import Observer
from skydome.astro.time import to_time
from skydome.physics.constants import EARTH_EQUATORIAL_RADIUS_KM

__all__ = [
    "DANJON_EARTH_ENLARGEMENT",
    "SolarContacts",
    "LunarContacts",
    "occulted_fraction",
    "disk_overlap_fraction",
    "solar_geometry",
    "solar_contacts",
    "find_solar_eclipses",
    "earth_shadow_radii",
    "lunar_geometry",
    "lunar_contacts",
    "find_lunar_eclipses",
    "danjon_from_luminance_ratio",
    "umbra_penumbra_on_ground_km",
]

#: Danjon's enlargement of the Earth's radius for the shadow (1/85).
DANJON_EARTH_ENLARGEMENT = 1.0 + 1.0 / 85.0
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(48)
_UNIFORM = np.array([1.0])


def _circle_fraction_inside(r: np.ndarray, z: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Fraction of the circle of radius ``r`` (centre 0) inside the disk of radius ``p``
    centred ``z`` away (all in the same units)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        c = (r * r + z * z - p * p) / (2.0 * r * z)
    c = np.where(z * r > 0.0, c, np.where(r < p - z, -1.0, 1.0))
    return np.arccos(np.clip(c, -1.0, 1.0)) / math.pi


def occulted_fraction(
    separation_rad: Any,
    sun_radius_rad: Any,
    moon_radius_rad: Any,
    limb_coefficients: Any = None,
) -> np.ndarray:
    """Fraction (0..1) of the Sun's flux hidden by the Moon's disk.

    ``separation_rad``: angle between the disks' centres; ``sun_radius_rad``,
    ``moon_radius_rad``: their angular radii (radians, broadcast together).
    ``limb_coefficients``: A_k of the limb-darkening law I(mu)/I(1) = sum_k A_k mu^k, shape
    (K,) or (..., K) broadcasting with the angles plus a last axis (e.g. one row per
    wavelength); None: a uniform disk. Returns the broadcast shape (plus the coefficients'
    leading axes).
    """
    z0 = np.asarray(separation_rad, dtype=float) / np.asarray(sun_radius_rad, dtype=float)
    p0 = np.asarray(moon_radius_rad, dtype=float) / np.asarray(sun_radius_rad, dtype=float)
    z, p = np.broadcast_arrays(np.abs(z0), p0)
    a = np.asarray(_UNIFORM if limb_coefficients is None else limb_coefficients, dtype=float)
    # pieces in r: [0, r1], [r1, r2], [r2, 1] with r1 = |z - p|, r2 = z + p (clipped to 1)
    r1 = np.clip(np.abs(z - p), 0.0, 1.0)
    r2 = np.clip(z + p, 0.0, 1.0)
    edges = np.stack([np.zeros_like(z), r1, r2, np.ones_like(z)], axis=-1)
    psi = np.arcsin(edges)  # r = sin(psi): mu = cos(psi) is smooth in psi
    lo, hi = psi[..., :-1], psi[..., 1:]  # (..., 3)
    half = 0.5 * (hi - lo)
    x = 0.5 * (hi + lo)[..., None] + half[..., None] * _NODES  # (..., 3, n)
    w = half[..., None] * _WEIGHTS
    r, mu = np.sin(x), np.cos(x)
    inside = _circle_fraction_inside(r, z[..., None, None], p[..., None, None])
    powers = mu[..., None] ** np.arange(a.shape[-1])  # (..., 3, n, K)
    dflux = r * mu * w  # r dr = sin(psi) cos(psi) dpsi
    if a.ndim == 1:
        law = powers @ a
        hidden = np.sum(law * inside * dflux, axis=(-1, -2))
        total = float(np.sum(a / (np.arange(a.shape[-1]) + 2.0)))  # int_0^1 mu^k r dr
        return np.clip(hidden / total, 0.0, 1.0)
    law = np.einsum("...sk,wk->...ws", powers.reshape(*powers.shape[:-3], -1, a.shape[-1]), a)
    flat = (inside * dflux).reshape(*inside.shape[:-2], -1)
    hidden = np.einsum("...ws,...s->...w", law, flat)
    total = np.sum(a / (np.arange(a.shape[-1]) + 2.0), axis=-1)
    return np.clip(hidden / total, 0.0, 1.0)


def disk_overlap_fraction(separation: Any, radius_a: Any, radius_b: Any) -> np.ndarray:
    """Fraction of the uniform disk of radius ``radius_a`` covered by the disk of radius
    ``radius_b`` whose centre is ``separation`` away (closed form, the lens area of two
    circles over pi a^2). GLSL twin: ``disk_overlap_fraction`` in
    ``shaders/common/eclipse.glsl``."""
    d, a, b = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (separation, radius_a, radius_b))
    )
    d = np.abs(d)
    with np.errstate(divide="ignore", invalid="ignore"):
        ca = np.clip((d * d + a * a - b * b) / (2.0 * d * a), -1.0, 1.0)
        cb = np.clip((d * d + b * b - a * a) / (2.0 * d * b), -1.0, 1.0)
        lens = (
            a * a * np.arccos(ca)
            + b * b * np.arccos(cb)
            - 0.5 * np.sqrt(np.maximum((-d + a + b) * (d + a - b) * (d - a + b) * (d + a + b), 0.0))
        )
    full = np.minimum(a, b) ** 2 * math.pi
    out = np.where(d >= a + b, 0.0, np.where(d <= np.abs(a - b), full, lens))
    return np.clip(out / (math.pi * a * a), 0.0, 1.0)


# ---------------------------------------------------------------------- solar, topocentric


def solar_geometry(observer: Observer, times: Any) -> dict[str, np.ndarray]:
    """Topocentric apparent separation of the Sun's and the Moon's centres and their angular
    radii (radians, arrays shaped like ``times``), with the Sun's and the Moon's airless
    altitudes (radians)."""
    sky = observer.sky(times, bodies=("sun", "moon"))
    s, m = sky["sun"], sky["moon"]
    cross = np.linalg.norm(np.cross(s.enu_unrefracted, m.enu_unrefracted), axis=-1)
    dot = np.sum(s.enu_unrefracted * m.enu_unrefracted, axis=-1)
    return {
        "separation": np.arctan2(cross, dot),
        "sun_radius": 0.5 * s.angular_diameter,
        "moon_radius": 0.5 * m.angular_diameter,
        "sun_alt": s.alt_unrefracted,
        "moon_alt": m.alt_unrefracted,
        "time": sky.time,
    }


def _bisect(f, lo: np.ndarray, hi: np.ndarray, iterations: int = 30) -> np.ndarray:
    """Roots of f (vectorized over brackets [lo, hi] with a sign change), Julian Dates UTC."""
    flo = f(lo)
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        fm = f(mid)
        same = np.sign(fm) == np.sign(flo)
        lo = np.where(same, mid, lo)
        flo = np.where(same, fm, flo)
        hi = np.where(same, hi, mid)
    return 0.5 * (lo + hi)


@dataclass
class SolarContacts:
    """A solar eclipse seen from one place: contact times (UTC Julian Dates, NaN where a
    contact does not happen there, e.g. C2/C3 of a partial eclipse), the kind (``partial``,
    ``total`` or ``annular``), the greatest eclipse's time, magnitude (the fraction of the
    Sun's diameter covered) and obscuration (the fraction of its limb-darkened flux hidden,
    None without coefficients: of its area), and the Sun's altitude (deg, airless) at each
    contact and at the greatest eclipse."""

    kind: str
    c1: float
    c2: float
    c3: float
    c4: float
    greatest: float
    magnitude: float
    obscuration: float
    sun_alt_deg: dict[str, float] = field(default_factory=dict)

    def contacts(self) -> dict[str, float]:
        """The contacts that happen, name -> UTC Julian Date."""
        out = {"C1": self.c1, "C2": self.c2, "max": self.greatest, "C3": self.c3, "C4": self.c4}
        return {k: v for k, v in out.items() if np.isfinite(v)}


def _jd_utc(t: Any) -> float:
    return float(np.ravel(to_time(t).jd_utc)[0])


def solar_contacts(
    observer: Observer,
    around: Any,
    *,
    hours: float = 4.0,
    step_s: float = 60.0,
    limb_coefficients: Any = None,
) -> SolarContacts | None:
    """The solar eclipse seen from ``observer`` within ``hours`` of ``around`` (a time), or
    None when the disks do not touch there. Contacts by bisection to < 1 ms (whether the Sun
    is up or not: see ``sun_alt_deg``)."""
    jd0 = _jd_utc(around)
    n = int(2 * hours * 3600 / step_s) + 1
    jd = jd0 + np.linspace(-hours, hours, n) / 24.0
    g = solar_geometry(observer, jd)
    outer = g["separation"] - (g["sun_radius"] + g["moon_radius"])
    if not np.any(outer < 0):
        return None

    def fn(kind):
        def f(x):
            gg = solar_geometry(observer, x)
            if kind == "outer":
                return gg["separation"] - (gg["sun_radius"] + gg["moon_radius"])
            return gg["separation"] - np.abs(gg["sun_radius"] - gg["moon_radius"])

        return f

    def crossings(values, f):
        i = np.flatnonzero(np.diff(np.sign(values)) != 0)
        if i.size == 0:
            return np.nan, np.nan
        roots = _bisect(f, jd[i], jd[i + 1])
        down = values[i] > 0
        first = roots[down][0] if np.any(down) else np.nan
        last = roots[~down][-1] if np.any(~down) else np.nan
        return float(first), float(last)

    c1, c4 = crossings(outer, fn("outer"))
    inner = g["separation"] - np.abs(g["sun_radius"] - g["moon_radius"])
    c2, c3 = crossings(inner, fn("inner"))
    # greatest eclipse: the separation's minimum (golden-section on the sampled minimum)
    k = int(np.argmin(g["separation"]))
    a, b = jd[max(k - 1, 0)], jd[min(k + 1, n - 1)]
    for _ in range(40):
        m1, m2 = a + 0.382 * (b - a), a + 0.618 * (b - a)
        s1, s2 = solar_geometry(observer, np.array([m1, m2]))["separation"]
        if s1 < s2:
            b = m2
        else:
            a = m1
    tmax = 0.5 * (a + b)
    gm = solar_geometry(observer, tmax)
    sep, rs, rm = (float(gm[key]) for key in ("separation", "sun_radius", "moon_radius"))
    magnitude = (rs + rm - sep) / (2.0 * rs)
    if np.isfinite(c2):
        kind = "total" if rm > rs else "annular"
    else:
        kind = "partial"
    obscuration = float(occulted_fraction(sep, rs, rm, limb_coefficients))
    names = {"C1": c1, "C2": c2, "max": tmax, "C3": c3, "C4": c4}
    alts = {}
    for key, jdv in names.items():
        if np.isfinite(jdv):
            alts[key] = float(np.degrees(solar_geometry(observer, jdv)["sun_alt"]))
    return SolarContacts(kind, c1, c2, c3, c4, tmax, magnitude, obscuration, alts)


def _geocentric_sun_moon(jd_utc: np.ndarray) -> tuple[np.ndarray, np.ndarray, dict, dict]:
    t = to_time(np.asarray(jd_utc, dtype=float))
    s = sun_mod.sun_apparent_geocentric(t)
    m = moon_mod.moon_apparent_geocentric(t)

    def unit(ra, dec):
        return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], -1)

    return unit(s["ra"], s["dec"]), unit(m["ra"], m["dec"]), s, m


def find_solar_eclipses(
    observer: Observer, start: Any, days: float, limb_coefficients: Any = None
) -> list[SolarContacts]:
    """Solar eclipses whose partial phase touches ``observer`` (Sun up or not: see each
    result's ``sun_alt_deg``) in ``days`` from ``start``. New Moons are found from the
    geocentric elongation (hourly samples); the topocentric contacts around each one whose
    geocentric separation is within 1.6 deg (the Moon's parallax, < 1.03 deg, plus both
    radii)."""
    jd0 = _jd_utc(start)
    jd = jd0 + np.arange(0.0, days + 1.0 / 24.0, 1.0 / 24.0)
    su, mu_, _, _ = _geocentric_sun_moon(jd)
    sep = np.arccos(np.clip(np.sum(su * mu_, axis=-1), -1.0, 1.0))
    close = np.flatnonzero(
        (sep[1:-1] <= sep[:-2]) & (sep[1:-1] <= sep[2:]) & (sep[1:-1] < np.radians(1.6))
    )
    out = []
    for i in close + 1:
        found = solar_contacts(observer, jd[i], hours=5.0, limb_coefficients=limb_coefficients)
        if found is not None and not any(abs(found.greatest - e.greatest) < 0.1 for e in out):
            out.append(found)
    return out


def umbra_penumbra_on_ground_km(
    sun_distance_km: float, moon_distance_km: float, sun_radius_km: float, moon_radius_km: float
) -> tuple[float, float]:
    """Radii (km, perpendicular to the shadow's axis) of the Moon's umbra (negative: the
    antumbra of an annular eclipse) and penumbra at the observer, ``moon_distance_km`` from
    the Moon's centre and ``sun_distance_km`` from the Sun's (similar triangles of the two
    cones' tangents)."""
    ds, dm = float(sun_distance_km), float(moon_distance_km)
    d_sm = ds - dm  # Sun-Moon distance along the axis
    umbra = moon_radius_km - (sun_radius_km - moon_radius_km) * dm / d_sm
    penumbra = moon_radius_km + (sun_radius_km + moon_radius_km) * dm / d_sm
    return umbra, penumbra


# ---------------------------------------------------------------------- lunar, geocentric


def earth_shadow_radii(
    moon_distance_km: Any, sun_distance_km: Any
) -> tuple[np.ndarray, np.ndarray]:
    """Angular radii (rad, seen from the Earth's centre) of the Earth's umbra and penumbra at
    the Moon's distance, by Danjon's rule (see the module's docstring)."""
    dm = np.asarray(moon_distance_km, dtype=float)
    ds = np.asarray(sun_distance_km, dtype=float)
    pi_m = np.arcsin(EARTH_EQUATORIAL_RADIUS_KM * DANJON_EARTH_ENLARGEMENT / dm)
    pi_s = np.arcsin(EARTH_EQUATORIAL_RADIUS_KM / ds)
    s_s = sun_mod.sun_angular_diameter(ds) / 2.0
    return pi_m + pi_s - s_s, pi_m + pi_s + s_s


def lunar_geometry(times: Any) -> dict[str, np.ndarray]:
    """Geocentric distance of the Moon's centre from the shadow's axis (the apparent
    antisolar point), the Moon's geocentric semidiameter and the umbra's and penumbra's
    radii (all radians, shaped like ``times``, UTC Julian Dates or anything ``to_time``
    takes)."""
    t = to_time(times)
    su, mu_, s, m = _geocentric_sun_moon(t.jd_utc)
    dist = np.arccos(np.clip(np.sum(-su * mu_, axis=-1), -1.0, 1.0))
    umbra, penumbra = earth_shadow_radii(m["distance_km"], s["distance_au"] * AU_KM)
    return {
        "axis_distance": dist,
        "moon_radius": m["angular_diameter"] / 2.0,
        "umbra": umbra,
        "penumbra": penumbra,
    }


@dataclass
class LunarContacts:
    """A lunar eclipse: contact times (UTC Julian Dates; NaN where it does not happen),
    kind (``penumbral``, ``partial`` or ``total``), the greatest eclipse's time and its
    umbral and penumbral magnitudes, and the Moon's altitude (deg, airless, when an observer
    was given) at each contact."""

    kind: str
    p1: float
    u1: float
    u2: float
    greatest: float
    u3: float
    u4: float
    p4: float
    umbral_magnitude: float
    penumbral_magnitude: float
    moon_alt_deg: dict[str, float] = field(default_factory=dict)

    def contacts(self) -> dict[str, float]:
        """The contacts that happen, name -> UTC Julian Date."""
        out = {
            "P1": self.p1, "U1": self.u1, "U2": self.u2, "max": self.greatest,
            "U3": self.u3, "U4": self.u4, "P4": self.p4,
        }  # fmt: skip
        return {k: v for k, v in out.items() if np.isfinite(v)}


def lunar_contacts(
    around: Any, *, hours: float = 5.0, step_s: float = 120.0, observer: Observer | None = None
) -> LunarContacts | None:
    """The lunar eclipse within ``hours`` of ``around``, or None when the Moon misses the
    penumbra. ``observer``: also the Moon's altitude at the contacts."""
    jd0 = _jd_utc(around)
    n = int(2 * hours * 3600 / step_s) + 1
    jd = jd0 + np.linspace(-hours, hours, n) / 24.0
    g = lunar_geometry(jd)

    def edge(kind):
        def f(x):
            gg = lunar_geometry(x)
            r = {"P": gg["penumbra"] + gg["moon_radius"], "U": gg["umbra"] + gg["moon_radius"],
                 "T": gg["umbra"] - gg["moon_radius"]}[kind]  # fmt: skip
            return gg["axis_distance"] - r

        return f

    def crossings(kind):
        values = edge(kind)(jd)
        i = np.flatnonzero(np.diff(np.sign(values)) != 0)
        if i.size == 0:
            return np.nan, np.nan
        roots = _bisect(edge(kind), jd[i], jd[i + 1])
        down = values[i] > 0
        first = roots[down][0] if np.any(down) else np.nan
        last = roots[~down][-1] if np.any(~down) else np.nan
        return float(first), float(last)

    p1, p4 = crossings("P")
    if not np.isfinite(p1) and not np.isfinite(p4):
        return None
    u1, u4 = crossings("U")
    u2, u3 = crossings("T")
    k = int(np.argmin(g["axis_distance"]))
    a, b = jd[max(k - 1, 0)], jd[min(k + 1, n - 1)]
    for _ in range(40):
        m1, m2 = a + 0.382 * (b - a), a + 0.618 * (b - a)
        d1, d2 = lunar_geometry(np.array([m1, m2]))["axis_distance"]
        if d1 < d2:
            b = m2
        else:
            a = m1
    tmax = 0.5 * (a + b)
    gm = {k2: float(v) for k2, v in lunar_geometry(tmax).items()}
    umag = (gm["umbra"] + gm["moon_radius"] - gm["axis_distance"]) / (2 * gm["moon_radius"])
    pmag = (gm["penumbra"] + gm["moon_radius"] - gm["axis_distance"]) / (2 * gm["moon_radius"])
    kind = "total" if np.isfinite(u2) else "partial" if np.isfinite(u1) else "penumbral"
    out = LunarContacts(kind, p1, u1, u2, tmax, u3, u4, p4, umag, pmag)
    if observer is not None:
        names = out.contacts()
        jds = np.array(list(names.values()))
        alts = np.degrees(observer.sky(jds, bodies=("moon",))["moon"].alt_unrefracted)
        out.moon_alt_deg = {k2: float(a2) for k2, a2 in zip(names, alts, strict=True)}
    return out


def find_lunar_eclipses(
    start: Any, days: float, observer: Observer | None = None
) -> list[LunarContacts]:
    """Lunar eclipses (penumbral ones included) in ``days`` from ``start``: full Moons
    (hourly samples of the geocentric elongation) within 1.8 deg of the shadow's axis,
    refined by :func:`lunar_contacts`."""
    jd0 = _jd_utc(start)
    jd = jd0 + np.arange(0.0, days + 1.0 / 24.0, 1.0 / 24.0)
    su, mu_, _, _ = _geocentric_sun_moon(jd)
    d = np.arccos(np.clip(np.sum(-su * mu_, axis=-1), -1.0, 1.0))
    close = np.flatnonzero((d[1:-1] <= d[:-2]) & (d[1:-1] <= d[2:]) & (d[1:-1] < np.radians(1.8)))
    out = []
    for i in close + 1:
        found = lunar_contacts(jd[i], observer=observer)
        if found is not None and not any(abs(found.greatest - e.greatest) < 0.1 for e in out):
            out.append(found)
    return out


def danjon_from_luminance_ratio(ratio: Any) -> np.ndarray:
    """Danjon's L (0..4, continuous) from the mid-totality Moon's brightness over the
    uneclipsed full Moon's: L = (15 - dm) / 1.5 with dm the eclipse's depth in magnitudes,
    clipped to 0..4 (the module's docstring says where the anchors come from)."""
    q = np.asarray(ratio, dtype=float)
    dm = -2.5 * np.log10(np.maximum(q, 1e-30))
    return np.clip((15.0 - dm) / 1.5, 0.0, 4.0)


# ---------------------------------------------------------------------- the sky in an eclipse


def sun_visible_at(
    points_km: Any, moon_km: Any, moon_radius_km: float, sun_dir: Any, sun_radius_rad: float
) -> np.ndarray:
    """Fraction (0..1) of the Sun's uniform disk seen past the Moon from ``points_km`` (...,
    3; km, any origin), the Moon's centre at ``moon_km`` and the Sun towards ``sun_dir``
    (unit) in the same axes. The float64 twin of atmosphere/eclipse_sky.glsl's function of
    the same name."""
    m = np.asarray(moon_km, dtype=float) - np.asarray(points_km, dtype=float)
    d = np.linalg.norm(m, axis=-1)
    u = m / d[..., None]
    s = np.asarray(sun_dir, dtype=float)
    sep = np.arctan2(np.linalg.norm(np.cross(u, s), axis=-1), np.sum(u * s, axis=-1))
    moon_r = np.arcsin(np.minimum(moon_radius_km / d, 1.0))
    return 1.0 - disk_overlap_fraction(sep, sun_radius_rad, moon_r)


def sky_sunlit_weight(
    radius_km: float,
    dirs: Any,
    moon_km: Any,
    moon_radius_km: float,
    sun_dir: Any,
    sun_radius_rad: float,
    air: Any,
    bottom_radius_km: float,
    top_radius_km: float,
    samples: int = 32,
    channels: Any = 1.0,
) -> np.ndarray:
    """The weight W of ``atmosphere/eclipse_sky.glsl`` (the float64 twin of its
    eclipse_sky_weight, checked through rendered skies)
    for view directions ``dirs`` (..., 3; unit ENU) from a camera at ``radius_km`` from the
    planet's centre: the fraction of the air's single-scattering weight along each ray
    (extinction e(h) = air[0] exp(-h / air[1]) + air[2] exp(-h / air[3]), 1/km and km,
    times the transmittance back to the camera) that sees the Sun, each point weighted by
    :func:`sun_visible_at`. The same midpoint quadrature as the shader (``samples`` points
    at s = L t^2), so that the two agree to float precision. ``channels``: factors on the
    Rayleigh extinction, one per output channel (a last axis of the result), or a scalar."""
    v = np.asarray(dirs, dtype=float)
    mu = v[..., 2]
    r = float(radius_km)
    disc_ground = r * r * (mu * mu - 1.0) + bottom_radius_km**2
    ground = (mu < 0.0) & (disc_ground >= 0.0)
    to_bottom = -r * mu - np.sqrt(np.maximum(disc_ground, 0.0))
    to_top = -r * mu + np.sqrt(np.maximum(r * r * (mu * mu - 1.0) + top_radius_km**2, 0.0))
    length = np.where(ground, to_bottom, to_top)
    t = (np.arange(samples) + 0.5) / samples
    s = length[..., None] * t * t
    ds = length[..., None] * 2.0 * t / samples
    h = np.sqrt(np.maximum(r * r + 2.0 * r * mu[..., None] * s + s * s, 0.0)) - bottom_radius_km
    a = np.asarray(air, dtype=float)
    ch = np.atleast_1d(np.asarray(channels, dtype=float))
    e = ch * (a[0] * np.exp(-h / a[1]))[..., None] + (a[2] * np.exp(-h / a[3]))[..., None]
    eds = e * ds[..., None]
    tau = np.cumsum(eds, axis=-2) - eds
    w = e * np.exp(-(tau + 0.5 * eds)) * ds[..., None]  # (..., samples, channels)
    vis = sun_visible_at(s[..., None] * v[..., None, :], moon_km, moon_radius_km, sun_dir,
                         sun_radius_rad)[..., None]  # fmt: skip
    den = np.sum(w, axis=-2)
    out = np.where(den > 0, np.sum(w * vis, axis=-2) / np.where(den > 0, den, 1.0), vis[..., 0, :])
    return out if np.ndim(channels) else out[..., 0]


def baumbach_corona(rho: Any) -> np.ndarray:
    """The K+F corona's radiance in units of the Sun's mean disk radiance at ``rho`` solar
    radii from its centre (Baumbach 1937, as given in Allen's Astrophysical Quantities, 4th
    ed., sec. 14.4): 1e-6 (0.0532 rho^-2.5 + 1.425 rho^-7 + 2.565 rho^-17). GLSL twin:
    ``baumbach_corona`` (celestial/sun.glsl)."""
    r = np.asarray(rho, dtype=float)
    return 1e-6 * (0.0532 * r**-2.5 + 1.425 * r**-7.0 + 2.565 * r**-17.0)
