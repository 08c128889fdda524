"""The Moon's orientation as seen from the Earth: librations, axis position angle, and the
Moon-fixed frame (Meeus, *Astronomical Algorithms* 2nd ed. 1998, ch. 53).

What the renderer needs to draw the Moon's albedo map the right way round:

* :func:`moon_libration`: the selenographic longitude ``l`` and latitude ``b`` of the
  Earth (the sub-Earth point: the point of the Moon's surface at the centre of the disk
  seen from the Earth's centre), optical plus physical libration, and the position
  angle ``P`` of the Moon's axis (of its north pole, on the sky, from the north point of
  the disk towards the east), geocentric.
* :func:`moon_topocentric_libration`: the same for an observer on the Earth's surface
  (Meeus ch. 53, "topocentric librations": changes of up to about 1 deg).
* :func:`moon_pole_and_prime_meridian`: the rotation matrix from Moon-fixed
  (selenographic) axes to the true equator and equinox of date, built from the same
  model, so that a direction expressed in it has the selenographic coordinates
  :func:`moon_libration` gives (to 1e-3 deg, the error of Meeus' linearised physical
  librations). With an observer's topocentric Moon vector it gives the exact
  sub-observer point (:func:`selenographic_lon_lat`) and axis position angle
  (:func:`axis_position_angle`).
* :func:`moon_selenographic_sun`: the selenographic longitude and latitude of the Sun
  (the sub-solar point) and the Sun's selenographic colongitude.

Model (Meeus ch. 53): the Moon's mean equator is inclined I = 1.54242 deg to the ecliptic; by Cassini's laws its
descending node on the ecliptic is at the mean ascending node Omega of the orbit, and its
prime meridian points at the Earth's mean direction (it runs the argument of latitude F
from that node). The physical librations rho (in inclination), sigma (in node, times
sin I) and tau (in the rotation angle) are Meeus' truncated series (p. 373), terms of
1e-4 deg and up.

Conventions: selenographic longitude is positive towards Mare Crisium (east in the IAU
sense, the west side of the disk in the sky); librations are in (-pi, pi], position
angles as returned. Angles are radians; ``jd_tt`` is a Terrestrial Time Julian Date (or
a :class:`~skydome.astro.time.Time`). Everything is vectorised over arrays of times.
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np

from skydome.astro import frames, moon, sun
from skydome.astro._series import PhasorSums, integer_combination_plan
from skydome.astro.frames import AU_KM
from skydome.astro.time import Time, gast, julian_centuries
from skydome.errors import ParameterError

__all__ = [
    "MOON_EQUATOR_INCLINATION",
    "moon_libration",
    "moon_topocentric_libration",
    "moon_pole_and_prime_meridian",
    "moon_selenographic_sun",
    "selenographic_lon_lat",
    "axis_position_angle",
]

DEG = np.pi / 180.0
#: Inclination I of the Moon's mean equator to the ecliptic, 1.54242 deg (Meeus p. 372,
#: the IAU value).
MOON_EQUATOR_INCLINATION = 1.54242 * DEG
_SIN_I = np.sin(MOON_EQUATOR_INCLINATION)
_COS_I = np.cos(MOON_EQUATOR_INCLINATION)


def _jd(jd_tt: Any, name: str = "jd_tt") -> np.ndarray:
    jd = np.asarray(getattr(jd_tt, "jd_tt", jd_tt), dtype=float)
    if not np.all(np.isfinite(jd)):
        raise ParameterError(f"{name} must hold finite Julian Dates (TT), got {jd_tt!r}")
    return jd


def _wrap(angle: np.ndarray) -> np.ndarray:
    """Angle reduced to (-pi, pi]."""
    return np.pi - np.mod(np.pi - angle, 2.0 * np.pi)


# ------------------------------------------------------------------ fundamental arguments

# Columns of the argument tables below: multiples of D, M, M', F, Omega, K1, K2.
_N_ARGS = 7


def _arguments(jd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Fundamental arguments (rad), shape (7, ...): D, M, M', F, Omega (Meeus eqs. 47.2-47.5
    and 47.7, the expressions ch. 53 prescribes) and K1, K2 (p. 373); and the eccentricity
    factor E (eq. 47.6)."""
    t = julian_centuries(jd)
    d = 297.8501921 + t * (445267.1114034 + t * (-0.0018819 + t * (1 / 545868 - t / 113065000)))
    m = 357.5291092 + t * (35999.0502909 + t * (-0.0001536 + t / 24490000))
    mp = 134.9633964 + t * (477198.8675055 + t * (0.0087414 + t * (1 / 69699 - t / 14712000)))
    f = 93.2720950 + t * (483202.0175233 + t * (-0.0036539 + t * (-1 / 3526000 + t / 863310000)))
    om = 125.0445479 + t * (-1934.1362891 + t * (0.0020754 + t * (1 / 467441 - t / 60616000)))
    k1 = 119.75 + 131.849 * t
    k2 = 72.56 + 20.186 * t
    e = 1.0 - t * (0.002516 + 0.0000074 * t)
    return np.stack([d, m, mp, f, om, k1, k2]) * DEG, e


# Physical libration series of Meeus p. 373, in units of 1e-5 deg. Each row: amplitude,
# 0 for a sine / 1 for a cosine, the multiples of (D, M, M', F, Omega, K1, K2), and the
# power of E the term carries (only tau's 0.02520 E sin M).
# fmt: off
_RHO = [
    (-2752, 1, 0, 0, 1, 0, 0, 0, 0, 0), (-2245, 0, 0, 0, 0, 1, 0, 0, 0, 0),
    (684, 1, 0, 0, 1, -2, 0, 0, 0, 0), (-293, 1, 0, 0, 0, 2, 0, 0, 0, 0),
    (-85, 1, -2, 0, 0, 2, 0, 0, 0, 0), (-54, 1, -2, 0, 1, 0, 0, 0, 0, 0),
    (-20, 0, 0, 0, 1, 1, 0, 0, 0, 0), (-20, 1, 0, 0, 1, 2, 0, 0, 0, 0),
    (-20, 1, 0, 0, 1, -1, 0, 0, 0, 0), (14, 1, -2, 0, 1, 2, 0, 0, 0, 0),
]
_SIGMA = [
    (-2816, 0, 0, 0, 1, 0, 0, 0, 0, 0), (2244, 1, 0, 0, 0, 1, 0, 0, 0, 0),
    (-682, 0, 0, 0, 1, -2, 0, 0, 0, 0), (-279, 0, 0, 0, 0, 2, 0, 0, 0, 0),
    (-83, 0, -2, 0, 0, 2, 0, 0, 0, 0), (69, 0, -2, 0, 1, 0, 0, 0, 0, 0),
    (40, 1, 0, 0, 1, 1, 0, 0, 0, 0), (-25, 0, 0, 0, 2, 0, 0, 0, 0, 0),
    (-23, 0, 0, 0, 1, 2, 0, 0, 0, 0), (20, 1, 0, 0, 1, -1, 0, 0, 0, 0),
    (19, 0, 0, 0, 1, -1, 0, 0, 0, 0), (13, 0, -2, 0, 1, 2, 0, 0, 0, 0),
    (-10, 1, 0, 0, 1, -3, 0, 0, 0, 0),
]
_TAU = [
    (2520, 0, 0, 1, 0, 0, 0, 0, 0, 1), (473, 0, 0, 0, 2, -2, 0, 0, 0, 0),
    (-467, 0, 0, 0, 1, 0, 0, 0, 0, 0), (396, 0, 0, 0, 0, 0, 0, 1, 0, 0),
    (276, 0, -2, 0, 2, 0, 0, 0, 0, 0), (196, 0, 0, 0, 0, 0, 1, 0, 0, 0),
    (-183, 1, 0, 0, 1, -1, 0, 0, 0, 0), (115, 0, -2, 0, 1, 0, 0, 0, 0, 0),
    (-96, 0, -1, 0, 1, 0, 0, 0, 0, 0), (46, 0, -2, 0, 0, 2, 0, 0, 0, 0),
    (-39, 0, 0, 0, 1, -1, 0, 0, 0, 0), (-32, 0, -1, -1, 1, 0, 0, 0, 0, 0),
    (27, 0, -2, -1, 2, 0, 0, 0, 0, 0), (23, 0, 0, 0, 0, 0, 0, 0, 1, 0),
    (-14, 0, 2, 0, 0, 0, 0, 0, 0, 0), (14, 1, 0, 0, 2, -2, 0, 0, 0, 0),
    (-12, 0, 0, 0, 1, -2, 0, 0, 0, 0), (-12, 0, 0, 0, 2, 0, 0, 0, 0, 0),
    (11, 0, -2, -2, 2, 0, 0, 0, 0, 0),
]
# fmt: on


@functools.cache
def _physical_sums() -> PhasorSums:
    """The three series as sums of phasors exp(i(kD D + ... + kK2 K2)) (the evaluator of
    :mod:`skydome.astro.moon`): rows rho, sigma, tau without its E term, tau's E term.
    A sin x = Re(-iA exp(ix)), A cos x = Re(A exp(ix))."""
    rows = np.array(_RHO + _SIGMA + _TAU, dtype=float)
    series = np.repeat([0, 1, 2], [len(_RHO), len(_SIGMA), len(_TAU)])
    series = np.where(rows[:, -1] > 0, 3, series)
    amp = rows[:, 0] * 1e-5 * DEG
    weight = np.where(rows[:, 1] > 0, amp + 0j, -1j * amp)
    mult = rows[:, 2 : 2 + _N_ARGS].astype(int)
    return PhasorSums(integer_combination_plan(mult), np.arange(rows.shape[0]), weight, series, 4)


def _physical_librations(args: np.ndarray, e: np.ndarray) -> np.ndarray:
    """rho, sigma, tau (rad), Meeus p. 373; shape (3, ...)."""
    flat = args.reshape(_N_ARGS, -1)
    rows = _physical_sums()(lambda blk: flat[:, blk], flat.shape[1])
    out = np.stack([rows[0], rows[1], rows[2] + e.reshape(-1) * rows[3]])
    return out.reshape((3,) + args.shape[1:])


# ------------------------------------------------------------------ the chapter 53 chain


def _chapter53(jd: np.ndarray, lam_mean: np.ndarray, beta: np.ndarray) -> dict[str, np.ndarray]:
    """Every quantity of Meeus ch. 53 for a body direction (lambda, beta).

    ``lam_mean``: geocentric longitude of the Moon referred to the mean equinox of date
    (the apparent longitude minus the nutation, lambda - dpsi of eq. 53.1), ``beta`` its
    latitude; for the Sun's selenographic position pass the heliocentric ones of the Moon.
    Returns radians: W, A, F, Omega, rho, sigma, tau, l_optical, b_optical, l_physical,
    b_physical, l, b, dpsi, eps (true obliquity), V, X, Y, omega, ra (apparent right
    ascension of the direction), P.
    """
    jd, lam_mean, beta = np.broadcast_arrays(jd, lam_mean, beta)
    args, e = _arguments(jd)
    f, om = args[3], args[4]
    dpsi, deps = frames.nutation_angles(jd)
    eps = frames.mean_obliquity(jd) + deps
    # optical librations, eq. 53.1
    w = lam_mean - om
    sw, cw = np.sin(w), np.cos(w)
    sb, cb = np.sin(beta), np.cos(beta)
    a = np.arctan2(sw * cb * _COS_I - sb * _SIN_I, cw * cb)
    l_opt = _wrap(a - f)
    b_opt = np.arcsin(np.clip(-sw * cb * _SIN_I - sb * _COS_I, -1.0, 1.0))
    # physical librations, eq. 53.2
    rho, sigma, tau = _physical_librations(args, e)
    l_phys = -tau + (rho * np.cos(a) + sigma * np.sin(a)) * np.tan(b_opt)
    b_phys = sigma * np.cos(a) - rho * np.sin(a)
    b_tot = b_opt + b_phys
    # position angle of the axis (Meeus ch. 53: V, X, Y, omega, then sin P)
    v = om + dpsi + sigma / _SIN_I
    i_rho = MOON_EQUATOR_INCLINATION + rho
    x = np.sin(i_rho) * np.sin(v)
    y = np.sin(i_rho) * np.cos(v) * np.cos(eps) - np.cos(i_rho) * np.sin(eps)
    omega = np.arctan2(x, y)
    ra, _ = frames.ecliptic_to_equatorial(lam_mean + dpsi, beta, eps)
    p = np.arcsin(np.clip(np.hypot(x, y) * np.cos(ra - omega) / np.cos(b_tot), -1.0, 1.0))
    return {
        "W": w,
        "A": a,
        "F": f,
        "Omega": om,
        "rho": rho,
        "sigma": sigma,
        "tau": tau,
        "l_optical": l_opt,
        "b_optical": b_opt,
        "l_physical": l_phys,
        "b_physical": b_phys,
        "l": _wrap(l_opt + l_phys),
        "b": b_tot,
        "dpsi": dpsi,
        "eps": eps,
        "V": v,
        "X": x,
        "Y": y,
        "omega": omega,
        "ra": ra,
        "P": p,
    }


_PUBLIC_KEYS = ("l", "b", "l_optical", "b_optical", "l_physical", "b_physical", "P")


def moon_libration(
    jd_tt: Any, *, apparent_lambda: Any = None, apparent_beta: Any = None
) -> dict[str, np.ndarray]:
    """Geocentric librations of the Moon and position angle of its axis (Meeus ch. 53).

    ``jd_tt``: Julian Date(s), TT (or a :class:`~skydome.astro.time.Time`).
    ``apparent_lambda``, ``apparent_beta``: the Moon's apparent geocentric ecliptic
    longitude (true equinox of date, i.e. with the nutation dpsi) and latitude, radians;
    by default those of :func:`skydome.astro.moon.moon_ecliptic_of_date` plus dpsi. Give
    both or neither.

    Returns a dict of arrays shaped like the inputs (radians): ``l``, ``b`` (total
    libration: selenographic longitude in (-pi, pi] and latitude of the Earth),
    ``l_optical``, ``b_optical`` (eq. 53.1), ``l_physical``, ``b_physical`` (eq. 53.2),
    ``P`` (position angle of the Moon's axis, from the north point of the disk, i.e. the
    direction of the celestial pole of date, towards the east; in [-pi/2, pi/2]:
    it never exceeds about 25 deg).
    """
    jd = _jd(jd_tt)
    if (apparent_lambda is None) != (apparent_beta is None):
        raise ParameterError(
            "apparent_lambda and apparent_beta must be given together (or both left None)"
        )
    if apparent_lambda is None:
        lam, beta, _ = moon.moon_ecliptic_of_date(jd)  # mean equinox of date, geometric
    else:
        lam = np.asarray(apparent_lambda, dtype=float)
        beta = np.asarray(apparent_beta, dtype=float)
        bad = ~(np.abs(beta) <= np.pi / 2) | ~np.isfinite(lam)
        if np.any(bad):
            raise ParameterError(
                "apparent_lambda must be finite and apparent_beta within [-pi/2, pi/2] rad, "
                f"got {apparent_lambda!r}, {apparent_beta!r}"
            )
        jd_b = np.broadcast_to(jd, np.broadcast_shapes(jd.shape, lam.shape, beta.shape))
        lam = lam - frames.nutation_angles(jd_b)[0]  # W = lambda - dpsi - Omega (eq. 53.1)
    q = _chapter53(jd, lam, beta)
    return {k: q[k] for k in _PUBLIC_KEYS}


# ------------------------------------------------------------------ the Moon-fixed frame


def _moon_axes_ecliptic(jd: np.ndarray, dpsi: np.ndarray) -> np.ndarray:
    """Moon-fixed axes (columns x, y, z) in ecliptic-of-date axes, true equinox; (..., 3, 3).

    The same rotation as Meeus' formulas, made exact: the node of the Moon's equator on
    the ecliptic at V = Omega + dpsi + sigma / sin I (true equinox), inclination I + rho,
    and the prime meridian at an angle Phi = F + pi + tau - (sigma / sin I) cos I from
    that node along the Moon's equator. The last term makes the linearised physical
    librations of eq. 53.2 come out: moving the node by dV about the ecliptic pole turns
    the Moon's equator frame by dV cos I about the Moon's axis, which eq. 53.2 does not
    count in l'' (its -tau is the whole change along the equator). ``dpsi``: the
    nutation in longitude (rad) at ``jd``.
    """
    args, e = _arguments(jd)
    f, om = args[3], args[4]
    rho, sigma, tau = _physical_librations(args, e)
    node_shift = sigma / _SIN_I
    v = om + dpsi + node_shift
    inc = MOON_EQUATOR_INCLINATION + rho
    phi = f + np.pi + tau - node_shift * _COS_I
    sv, cv = np.sin(v), np.cos(v)
    si, ci = np.sin(inc), np.cos(inc)
    zeros = np.zeros_like(sv)
    node = np.stack([cv, sv, zeros], axis=-1)  # along the node line
    quad = np.stack([-sv * ci, cv * ci, -si], axis=-1)  # pole x node, in the Moon's equator
    pole = np.stack([-sv * si, cv * si, ci], axis=-1)  # ecliptic longitude V + 90 deg
    sp, cp = np.sin(phi)[..., None], np.cos(phi)[..., None]
    x_axis = cp * node + sp * quad
    y_axis = -sp * node + cp * quad
    return np.stack([x_axis, y_axis, pole], axis=-1)


def moon_pole_and_prime_meridian(jd_tt: Any) -> dict[str, np.ndarray]:
    """The Moon-fixed (selenographic) frame in the true equator and equinox of date.

    ``jd_tt``: Julian Date(s), TT. Returns a dict: ``matrix`` (..., 3, 3), whose columns
    are the Moon-fixed axes (x towards selenographic longitude 0, latitude 0; y towards
    longitude 90 deg east; z the Moon's north pole) as unit vectors in the equatorial
    frame of :mod:`skydome.astro.observer` (true equator and equinox of date), so that
    ``matrix @ v_moon_fixed`` gives equatorial components and ``matrix.T @ v_eq`` the
    Moon-fixed ones; ``pole`` (..., 3) and ``prime_meridian`` (..., 3), its third and first
    columns. For an observer, ``frames.equatorial_to_enu_matrix(last, lat) @ matrix`` gives
    the Moon's axes in East-North-Up.

    Built from the same model as :func:`moon_libration` (Meeus ch. 53 with I = 1.54242
    deg, rho, sigma, tau): the direction Moon -> Earth has selenographic coordinates
    (l, b) and the projected pole position angle P within 1e-3 deg (measured 1.1e-4 deg in
    l, 7e-4 deg in b, 2e-5 deg in P, 1950-2050: the second-order terms eq. 53.2 drops).
    The axes are Meeus'; the IAU mean-Earth axes of lunar maps (Archinal et al. 2011) and
    NASA SVS's DE421 ones differ from them by a constant 81" about the y axis (0.022 deg
    in b; < 1" about x and z), which is below what a rendered disk shows (tested).
    """
    jd = _jd(jd_tt)
    dpsi, deps = frames.nutation_angles(jd)
    to_eq = frames.rot_x(-(frames.mean_obliquity(jd) + deps))  # ecliptic -> true equator
    m = to_eq @ _moon_axes_ecliptic(jd, dpsi)
    return {"matrix": m, "pole": m[..., :, 2], "prime_meridian": m[..., :, 0]}


def selenographic_lon_lat(matrix: Any, direction: Any) -> tuple[np.ndarray, np.ndarray]:
    """Selenographic longitude in (-pi, pi] and latitude (rad) of the point of the Moon's
    surface towards ``direction`` (..., 3), any length, given in the equatorial axes of
    ``matrix`` (from :func:`moon_pole_and_prime_meridian`).

    For the sub-observer point pass the vector Moon -> observer (minus the topocentric
    Moon vector); for the sub-solar point, Moon -> Sun.
    """
    m = np.asarray(matrix, dtype=float)
    v = np.einsum("...ji,...j->...i", m, np.asarray(direction, dtype=float))
    lon, lat, _ = frames.cartesian_to_spherical(v)
    return _wrap(lon), lat


def axis_position_angle(pole: Any, moon_direction: Any) -> np.ndarray:
    """Position angle (rad, (-pi, pi]) of the Moon's north pole on the sky, from the north
    point of the disk towards the east, for an observer seeing the Moon's centre towards
    ``moon_direction`` (..., 3); ``pole`` (..., 3) in the same equatorial axes (the
    celestial pole is their z axis)."""
    u = np.asarray(moon_direction, dtype=float)
    u = u / np.linalg.norm(u, axis=-1, keepdims=True)
    p = np.asarray(pole, dtype=float)
    east = np.stack(np.broadcast_arrays(-u[..., 1], u[..., 0], np.zeros_like(u[..., 0])), -1)
    east = east / np.linalg.norm(east, axis=-1, keepdims=True)
    north = np.cross(u, east)
    return np.arctan2(np.sum(p * east, axis=-1), np.sum(p * north, axis=-1))


# ------------------------------------------------------------------ the Sun on the Moon


def moon_selenographic_sun(jd_tt: Any) -> dict[str, np.ndarray]:
    """Selenographic position of the Sun (Meeus ch. 53, "selenographic position of the Sun").

    ``jd_tt``: Julian Date(s), TT. Returns radians: ``l0`` (selenographic longitude of the
    sub-solar point, (-pi, pi]), ``b0`` (its latitude) and ``colongitude`` (c0 = 90 deg -
    l0 in [0, 2pi): the selenographic longitude of the morning terminator, 0 near first
    quarter).

    Meeus feeds the Moon's heliocentric longitude and latitude, approximated from the Sun's
    apparent longitude, through the libration formulas. Here the direction Moon -> Sun
    comes from the heliocentric Earth (VSOP87) plus the geocentric Moon (mean ecliptic of
    date), aberrated with the Earth's orbital velocity as Meeus' apparent solar longitude
    is: sunlight arrives at the Moon, which moves round the Sun with the Earth to 1 km/s
    (0.7"), from the aberrated direction.
    """
    jd = _jd(jd_tt)
    lam, beta, dist_km = moon.moon_ecliptic_of_date(jd)
    earth, v_earth = sun.earth_heliocentric_state(jd)
    helio = earth + frames.spherical_to_cartesian(lam, beta, dist_km / AU_KM)
    to_sun = -helio / np.linalg.norm(helio, axis=-1, keepdims=True)
    to_sun = frames.aberrate(to_sun, v_earth)
    lam_h, beta_h, _ = frames.cartesian_to_spherical(-to_sun)  # as if Sun -> Moon
    q = _chapter53(jd, lam_h, beta_h)
    l0 = q["l"]
    return {"l0": l0, "b0": q["b"], "colongitude": np.mod(np.pi / 2 - l0, 2 * np.pi)}


# ------------------------------------------------------------------ topocentric


def _observer_true_equator_km(t: Time, lat, lon, h, shape) -> np.ndarray:
    """Geocentric position (km) of WGS84 observers in the true equator and equinox of date
    (Earth-fixed position turned by the apparent sidereal time; polar motion neglected,
    as in :mod:`skydome.astro.observer`); shape ``shape + (3,)``."""
    r = np.broadcast_to(frames.geodetic_to_geocentric_km(lat, lon, h), shape + (3,))
    th = gast(np.broadcast_to(t.jd_ut1, shape), np.broadcast_to(t.jd_tt, shape))
    c, s = np.cos(th), np.sin(th)
    return np.stack([c * r[..., 0] - s * r[..., 1], s * r[..., 0] + c * r[..., 1], r[..., 2]], -1)


def moon_topocentric_libration(
    time: Any, latitude: Any, longitude: Any, elevation_m: Any = 0.0, *, method: str = "meeus"
) -> dict[str, np.ndarray]:
    """Librations and axis position angle for an observer on the Earth (Meeus ch. 53,
    "topocentric librations").

    ``time``: a :class:`~skydome.astro.time.Time` (its UT1 drives the sidereal time) or
    Julian Date(s) TT (UT1 from the model Delta T); ``latitude`` (geodetic, rad, north
    positive), ``longitude`` (rad, east positive), ``elevation_m`` (metres above the WGS84
    ellipsoid); all broadcast together. ``method``: ``"meeus"`` (the corrections below) or
    ``"exact"`` (the observer's geometric topocentric Moon vector through
    :func:`moon_pole_and_prime_meridian` and :func:`axis_position_angle`).

    Returns radians: ``l``, ``b``, ``P`` (topocentric), ``dl``, ``db``, ``dP`` (topocentric
    minus geocentric) and ``parallax`` (p: the angle at the Moon between the Earth's centre
    and the observer, up to about 1 deg).

    Meeus' corrections, with H the geocentric hour angle, delta the geocentric declination,
    z the geocentric zenith distance and Q from tan Q = cos phi' sin H / (cos delta sin phi'
    - sin delta cos phi' cos H): dl = -p sin(Q - P) / cos b, db = p cos(Q - P),
    dP = dl sin(b + db) - p sin Q tan delta. Meeus' p = pi (sin z + 0.0084 sin 2z) is the
    first two terms of p = atan(r sin z / (1 - r cos z)), r = rho sin(pi), used here with
    phi' and rho the observer's geocentric latitude and distance (Earth radii) on WGS84.
    They differ from ``"exact"`` by 1e-3 deg in l and b and 0.011 deg in P at most
    (measured over random places and times, 1975-2025).
    """
    if method not in ("meeus", "exact"):
        raise ParameterError(f"method = {method!r}: choose 'meeus' or 'exact'")
    t = time if isinstance(time, Time) else Time.from_jd(_jd(time, "time"))
    jd = _jd(t)
    lat = np.asarray(latitude, dtype=float)
    lon = np.asarray(longitude, dtype=float)
    h = np.asarray(elevation_m, dtype=float)
    if np.any(~(np.abs(lat) <= np.pi / 2)):
        raise ParameterError(
            f"latitude = {latitude!r} rad is outside the valid range [-pi/2, pi/2]"
        )
    if np.any(~(np.abs(lon) <= 2 * np.pi)):
        raise ParameterError(
            f"longitude = {longitude!r} rad is outside the valid range [-2pi, 2pi]"
        )
    if np.any(~((h >= -1000.0) & (h <= 100000.0))):
        raise ParameterError(
            f"elevation_m = {elevation_m!r} m is outside the valid range [-1000, 100000] m"
        )
    shape = np.broadcast_shapes(jd.shape, lat.shape, lon.shape, h.shape)
    jd_b = np.broadcast_to(jd, shape)
    lam, beta, dist_km = moon.moon_ecliptic_of_date(jd_b)
    q = _chapter53(jd_b, lam, beta)
    dec = np.arcsin(
        np.sin(beta) * np.cos(q["eps"]) + np.cos(beta) * np.sin(q["eps"]) * np.sin(lam + q["dpsi"])
    )
    geo = frames.spherical_to_cartesian(q["ra"], dec, dist_km)  # true equator of date
    r_obs = _observer_true_equator_km(t, lat, lon, h, shape)
    topo = geo - r_obs
    cos_p = np.sum(geo * topo, -1) / (dist_km * np.linalg.norm(topo, axis=-1))
    par = np.arccos(np.clip(cos_p, -1.0, 1.0))
    b, p_geo = q["b"], q["P"]
    if method == "exact":
        frame = moon_pole_and_prime_meridian(jd_b)
        l_top, b_top = selenographic_lon_lat(frame["matrix"], -topo)
        l_geo, b_geo = selenographic_lon_lat(frame["matrix"], -geo)
        dl = _wrap(l_top - l_geo)
        db = b_top - b_geo
        dp = _wrap(
            axis_position_angle(frame["pole"], topo) - axis_position_angle(frame["pole"], geo)
        )
    else:
        phi_c = np.arctan2(r_obs[..., 2], np.hypot(r_obs[..., 0], r_obs[..., 1]))
        ha = np.arctan2(r_obs[..., 1], r_obs[..., 0]) - q["ra"]  # local sidereal time - ra
        sd, cd = np.sin(dec), np.cos(dec)
        sp, cp = np.sin(phi_c), np.cos(phi_c)
        qq = np.arctan2(cp * np.sin(ha), cd * sp - sd * cp * np.cos(ha))
        cz = sd * sp + cd * cp * np.cos(ha)
        sz = np.sqrt(np.maximum(1.0 - cz * cz, 0.0))
        r = np.linalg.norm(r_obs, axis=-1) / dist_km  # rho sin(pi)
        par = np.arctan2(r * sz, 1.0 - r * cz)
        dl = -par * np.sin(qq - p_geo) / np.cos(b)
        db = par * np.cos(qq - p_geo)
        dp = dl * np.sin(b + db) - par * np.sin(qq) * np.tan(dec)
    return {
        "l": _wrap(q["l"] + dl),
        "b": b + db,
        "P": p_geo + dp,
        "dl": dl,
        "db": db,
        "dP": dp,
        "parallax": par,
    }


def moon_frame_enu(
    moon_true: np.ndarray, pole_enu: np.ndarray, l_rad: float, b_rad: float, p_rad: float
) -> np.ndarray:
    """Moon-fixed axes (columns x, y, z) in ENU from the libration and the axis angle.

    ``moon_true``: unit ENU vector from the observer to the Moon (airless); ``pole_enu``: the
    celestial north pole in ENU; ``l_rad``, ``b_rad``: selenographic longitude and latitude
    of the sub-observer point; ``p_rad``: position angle of the Moon's axis from the north
    point of the disk through east (Meeus ch. 53).
    """
    u = moon_true / np.linalg.norm(moon_true)
    w = -u  # from the Moon towards the observer
    north = pole_enu - np.dot(pole_enu, u) * u
    north /= np.linalg.norm(north)
    east = np.cross(pole_enu, u)  # towards increasing right ascension on the sky
    east /= np.linalg.norm(east)
    axis_on_sky = math.cos(p_rad) * north + math.sin(p_rad) * east
    # The pole leans towards the observer by the libration in latitude b.
    pole = math.cos(b_rad) * axis_on_sky + math.sin(b_rad) * w
    q = w - math.sin(b_rad) * pole
    q /= np.linalg.norm(q)  # the sub-observer meridian on the Moon's equator: longitude l
    x = math.cos(l_rad) * q - math.sin(l_rad) * np.cross(pole, q)
    y = np.cross(pole, x)
    return np.stack([x, y, pole], axis=1)
