"""Reference frames: precession, nutation, aberration, horizontal coordinates, refraction.

Conventions
-----------
* Angles are radians unless a name says ``_deg``/``_arcmin``; times are Julian Dates.
* ``jd_tt`` is Terrestrial Time (TT = TDB to 2 ms, ignored here); ``jd_ut1`` drives the
  Earth's rotation.
* Vectors are float64 arrays with the 3 components on the last axis; matrices are
  ``(..., 3, 3)`` and act on column vectors (``v_new = M @ v``).
* The local frame is East-North-Up (x = east, y = north, z = up); azimuth is measured
  from north through east.

Models
------
* Precession: IAU 2006 (P03, Capitaine, Wallace & Chapront 2003), angles zeta_A, z_A,
  theta_A of the IERS Conventions 2010 eq. 5.40; mean obliquity IAU 2006 (eq. 5.40 too).
* Nutation: IAU 1980, the 63-term series of Meeus, *Astronomical Algorithms* 2nd ed.
  (1998), ch. 22 table 22.A, accurate to about 0.1".
* Annual aberration: first order in v/c (Meeus ch. 23 gives the same in ecliptic form),
  with the Earth's heliocentric velocity from the VSOP87 series.
* Refraction: Bennett (1982) apparent -> true (Meeus eq. 16.4), Saemundsson (1986)
  true -> apparent (Meeus eq. 16.4 companion), both scaled by (P/1010)(283/(273+T))
  (Meeus p. 107).
* Observer: WGS84 ellipsoid (NIMA TR8350.2), geodetic latitude.
"""

from __future__ import annotations

import functools

import numpy as np

from skydome.astro._series import (
    PhasorSums,
    integer_combination_plan,
    segment_memo,
    smooth,
    tables,
    vsop,
)
from skydome.physics.constants import (
    ARCSEC_RAD,
    AU_KM,
    EARTH_EQUATORIAL_RADIUS_KM,
    J2000_JD,
    JULIAN_CENTURY_DAYS,
)
from skydome.physics.geometry import horizontal_to_enu
from skydome.physics.refraction import refraction_bennett, refraction_saemundsson

__all__ = [
    "ARCSEC",
    "AU_KM",
    "C_AU_PER_DAY",
    "ecliptic_to_equatorial",
    "equatorial_to_ecliptic",
    "ecliptic_of_date_to_j2000_matrix",
    "mean_obliquity",
    "true_obliquity",
    "nutation_angles",
    "nutation_matrix",
    "ecliptic_to_true_matrix_from_angles",
    "nutation_matrix_from_angles",
    "precession_matrix",
    "precession_nutation_matrix",
    "equation_of_equinoxes",
    "earth_velocity_au_per_day",
    "apply_aberration",
    "aberrate",
    "deflect_by_sun",
    "dot3",
    "norm3",
    "equatorial_to_horizontal",
    "horizontal_to_enu",
    "enu_to_horizontal",
    "equatorial_to_enu_matrix",
    "geodetic_to_geocentric_km",
    "diurnal_speed_au_per_day",
    "refraction_bennett",
    "refraction_saemundsson",
    "rot_x",
    "rot_y",
    "rot_z",
    "spherical_to_cartesian",
    "cartesian_to_spherical",
]

ARCSEC = ARCSEC_RAD  # radians per arcsecond
DEG = np.pi / 180.0
C_KM_PER_S = 299792.458
C_AU_PER_DAY = C_KM_PER_S * 86400.0 / AU_KM  # 173.1446... au/day
WGS84_A_KM = EARTH_EQUATORIAL_RADIUS_KM  # equatorial radius
WGS84_F = 1.0 / 298.257223563  # flattening
EARTH_OMEGA = 7.292115e-5  # rad/s, WGS84 nominal rotation rate (for diurnal velocity)


def julian_centuries(jd_tt) -> np.ndarray:
    """Julian centuries of 36525 days since J2000.0 (Meeus eq. 22.1); also
    ``skydome.astro.time.julian_centuries``."""
    return (np.asarray(jd_tt, dtype=float) - J2000_JD) / JULIAN_CENTURY_DAYS


# ------------------------------------------------------------------ rotation helpers


def _frame_rotation(angle, i: int, j: int) -> np.ndarray:
    """Rotation of the frame by ``angle`` about the axis other than i and j (right-handed
    order i, j): m[i, i] = m[j, j] = cos, m[i, j] = sin, m[j, i] = -sin. Shape (..., 3, 3)."""
    a = np.asarray(angle, dtype=float)
    c, s = np.cos(a), np.sin(a)
    m = np.zeros(a.shape + (3, 3))
    k = 3 - i - j
    m[..., k, k] = 1.0
    m[..., i, i] = c
    m[..., j, j] = c
    m[..., i, j] = s
    m[..., j, i] = -s
    return m


def rot_x(angle) -> np.ndarray:
    """Rotation matrix R1(angle) (rotates the frame, not the vector), shape (..., 3, 3)."""
    return _frame_rotation(angle, 1, 2)


def rot_y(angle) -> np.ndarray:
    """Rotation matrix R2(angle), shape (..., 3, 3)."""
    return _frame_rotation(angle, 2, 0)


def rot_z(angle) -> np.ndarray:
    """Rotation matrix R3(angle), shape (..., 3, 3)."""
    return _frame_rotation(angle, 0, 1)


def _apply(m: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``m @ v`` for stacks of matrices (..., 3, 3) and vectors (..., 3)."""
    return np.einsum("...ij,...j->...i", m, v)


def spherical_to_cartesian(lon, lat, r=1.0) -> np.ndarray:
    """Unit (or length ``r``) vector from longitude/latitude in radians; shape (..., 3)."""
    lon, lat, r = np.broadcast_arrays(
        np.asarray(lon, float), np.asarray(lat, float), np.asarray(r, float)
    )
    cl = np.cos(lat)
    return np.stack([r * cl * np.cos(lon), r * cl * np.sin(lon), r * np.sin(lat)], axis=-1)


def cartesian_to_spherical(v) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(lon in [0, 2pi), lat, r) of vectors ``v`` (..., 3)."""
    v = np.asarray(v, dtype=float)
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    rxy = np.hypot(x, y)
    return np.mod(np.arctan2(y, x), 2 * np.pi), np.arctan2(z, rxy), np.hypot(rxy, z)


# ------------------------------------------------------------------ obliquity, precession


def mean_obliquity(jd_tt) -> np.ndarray:
    """Mean obliquity of the ecliptic epsilon_A (rad), IAU 2006 (IERS Conventions 2010 eq. 5.40).

    ``jd_tt``: Julian Date(s), TT.
    """
    t = julian_centuries(jd_tt)
    eps = 84381.406 + t * (
        -46.836769 + t * (-0.0001831 + t * (0.00200340 + t * (-0.000000576 + t * -0.0000000434)))
    )
    return eps * ARCSEC


def _precession_angles(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """IAU 2006 equatorial precession angles zeta_A, z_A, theta_A (rad); t in TT centuries."""
    zeta = 2.650545 + t * (
        2306.083227 + t * (0.2988499 + t * (0.01801828 + t * (-0.000005971 + t * -0.0000003173)))
    )
    z = -2.650545 + t * (
        2306.077181 + t * (1.0927348 + t * (0.01826837 + t * (-0.000028596 + t * -0.0000002904)))
    )
    theta = t * (
        2004.191903 + t * (-0.4294934 + t * (-0.04182264 + t * (-0.000007089 + t * -0.0000001274)))
    )
    return zeta * ARCSEC, z * ARCSEC, theta * ARCSEC


def precession_matrix(jd_tt) -> np.ndarray:
    """Matrix (..., 3, 3) rotating J2000 mean equatorial vectors to the mean equator and
    equinox of date: P = R3(-z_A) R2(theta_A) R3(-zeta_A) (Meeus eq. 21.4 with IAU 2006 angles).

    ``jd_tt``: Julian Date(s), TT. Frame bias (ICRS vs J2000 mean, 0.02") is neglected.
    """
    zeta, z, theta = _precession_angles(julian_centuries(jd_tt))
    cz, sz = np.cos(zeta), np.sin(zeta)
    cZ, sZ = np.cos(z), np.sin(z)
    ct, st = np.cos(theta), np.sin(theta)
    m = np.empty(np.shape(zeta) + (3, 3))
    m[..., 0, 0] = cz * ct * cZ - sz * sZ
    m[..., 0, 1] = -sz * ct * cZ - cz * sZ
    m[..., 0, 2] = -st * cZ
    m[..., 1, 0] = cz * ct * sZ + sz * cZ
    m[..., 1, 1] = -sz * ct * sZ + cz * cZ
    m[..., 1, 2] = -st * sZ
    m[..., 2, 0] = cz * st
    m[..., 2, 1] = -sz * st
    m[..., 2, 2] = ct
    return m


# ------------------------------------------------------------------ nutation


def _fundamental_args(t: np.ndarray) -> np.ndarray:
    """Delaunay arguments D, M, M', F, Omega (rad), Meeus ch. 22 (p. 144); shape (5, N)."""
    d = 297.85036 + t * (445267.111480 + t * (-0.0019142 + t / 189474.0))
    m = 357.52772 + t * (35999.050340 + t * (-0.0001603 - t / 300000.0))
    mp = 134.96298 + t * (477198.867398 + t * (0.0086972 + t / 56250.0))
    f = 93.27191 + t * (483202.017538 + t * (-0.0036825 + t / 327270.0))
    om = 125.04452 + t * (-1934.136261 + t * (0.0020708 + t / 450000.0))
    return np.stack([d, m, mp, f, om]) * DEG


@functools.cache
def _nutation_sums() -> PhasorSums:
    """Sums of Meeus table 22.A from the phasors exp(i(kD D + kM M + kM' M' + kF F + kO Om)).

    Rows: sum S sin(arg), sum S' sin(arg), sum C cos(arg), sum C' cos(arg) (table units,
    0.0001"), with dpsi = (S + S' T) sin(arg) and deps = (C + C' T) cos(arg) per term.
    """
    tab = tables()
    mult = tab["nut_args"].astype(int)
    dpsi_c, deps_c = tab["nut_dpsi"], tab["nut_deps"]
    terms = np.arange(mult.shape[0])
    return PhasorSums(
        integer_combination_plan(mult),
        np.concatenate([terms] * 4),
        np.concatenate([-1j * dpsi_c[:, 0], -1j * dpsi_c[:, 1], deps_c[:, 0], deps_c[:, 1]]),
        np.repeat(np.arange(4), terms.size),
        4,
    )


def _nutation_direct(jd_tt: np.ndarray) -> np.ndarray:
    """(dpsi, deps) in radians, shape (2, N), IAU 1980 series of Meeus table 22.A."""
    t = julian_centuries(jd_tt).ravel()
    fund = _fundamental_args(t)
    rows = _nutation_sums()(lambda blk: fund[:, blk], t.size)
    dpsi = rows[0] + t * rows[1]
    deps = rows[2] + t * rows[3]
    return np.stack([dpsi, deps]) * (1e-4 * ARCSEC)  # table unit: 0.0001"


def nutation_angles(jd_tt) -> tuple[np.ndarray, np.ndarray]:
    """Nutation in longitude and in obliquity (dpsi, deps), radians (Meeus ch. 22, IAU 1980).

    ``jd_tt``: Julian Date(s), TT; the result has the shape of ``jd_tt``.
    """
    jd = np.asarray(jd_tt, dtype=float)
    # Shortest period in the series is 5.6 d (0.0001"); 16-day segments of degree 15
    # interpolate the series to 1.3e-6" (measured over 1945-2055; < 1e-4" is tested in
    # tests/astro/test_astro_frames.py), with 1 evaluation a day where 4-day segments of
    # degree 11 took 3 (sparse times, e.g. 1e5 at random over 150 years, are then
    # interpolated too).
    out = smooth(_nutation_direct, jd, 16.0, 15, memo=segment_memo("nutation"))
    return out[0].reshape(jd.shape), out[1].reshape(jd.shape)


def true_obliquity(jd_tt) -> np.ndarray:
    """True obliquity epsilon = epsilon_A + deps (rad)."""
    return mean_obliquity(jd_tt) + nutation_angles(jd_tt)[1]


def ecliptic_to_true_matrix_from_angles(eps_a, dpsi, deps) -> np.ndarray:
    """Mean ecliptic of date -> true equator of date from the mean obliquity ``eps_a`` and
    the nutation angles ``dpsi``, ``deps`` (rad; for a caller that has them already):
    N R1(-eps_A), which is R1(-(eps_A + deps)) R3(-dpsi) (N's last factor R1(eps_A) cancels);
    the product written out (a stack of 3x3 products is several times slower)."""
    eps = np.asarray(eps_a, dtype=float) + deps
    ce, se = np.cos(eps), np.sin(eps)
    cp, sp = np.cos(dpsi), np.sin(dpsi)
    out = np.empty(np.shape(ce) + (3, 3))
    out[..., 0, 0], out[..., 0, 1], out[..., 0, 2] = cp, -sp, 0.0
    out[..., 1, 0], out[..., 1, 1], out[..., 1, 2] = ce * sp, ce * cp, -se
    out[..., 2, 0], out[..., 2, 1], out[..., 2, 2] = se * sp, se * cp, ce
    return out


def nutation_matrix_from_angles(eps_a, dpsi, deps) -> np.ndarray:
    """The nutation matrix from the mean obliquity and the nutation angles (rad):
    N = R1(-(eps_A + deps)) R3(-dpsi) R1(eps_A) (Explanatory Supplement eq. 3.222-3)."""
    return ecliptic_to_true_matrix_from_angles(eps_a, dpsi, deps) @ rot_x(eps_a)


def ecliptic_to_true_equator_matrix(jd_tt) -> np.ndarray:
    """Matrix (..., 3, 3) taking mean-ecliptic-of-date vectors to the true equator of date."""
    dpsi, deps = nutation_angles(jd_tt)
    return ecliptic_to_true_matrix_from_angles(mean_obliquity(jd_tt), dpsi, deps)


def nutation_matrix(jd_tt) -> np.ndarray:
    """Matrix (..., 3, 3) taking mean-of-date equatorial vectors to true-of-date."""
    dpsi, deps = nutation_angles(jd_tt)
    return nutation_matrix_from_angles(mean_obliquity(jd_tt), dpsi, deps)


def precession_nutation_matrix(jd_tt) -> np.ndarray:
    """N @ P: J2000 mean equatorial -> true equator and equinox of date, (..., 3, 3)."""
    return nutation_matrix(jd_tt) @ precession_matrix(jd_tt)


def equation_of_equinoxes(jd_tt) -> np.ndarray:
    """GAST - GMST (rad): dpsi cos(eps_A) plus the IAU 1994 complementary terms
    0.00264" sin(Omega) + 0.000063" sin(2 Omega) (IERS Conventions 1996 ch. 5)."""
    jd = np.asarray(jd_tt, dtype=float)
    dpsi, _ = nutation_angles(jd)
    om = _fundamental_args(julian_centuries(jd).ravel())[4].reshape(jd.shape)
    return (
        dpsi * np.cos(mean_obliquity(jd))
        + (0.00264 * np.sin(om) + 0.000063 * np.sin(2 * om)) * ARCSEC
    )


# ------------------------------------------------------------------ ecliptic <-> equatorial


def ecliptic_to_equatorial(lon, lat, obliquity) -> tuple[np.ndarray, np.ndarray]:
    """(ra, dec) from ecliptic (lon, lat) for the given obliquity, radians (Meeus eq. 13.3-4)."""
    lon, lat, eps = (np.asarray(x, dtype=float) for x in (lon, lat, obliquity))
    ra = np.arctan2(np.sin(lon) * np.cos(eps) - np.tan(lat) * np.sin(eps), np.cos(lon))
    dec = np.arcsin(np.sin(lat) * np.cos(eps) + np.cos(lat) * np.sin(eps) * np.sin(lon))
    return np.mod(ra, 2 * np.pi), dec


def equatorial_to_ecliptic(ra, dec, obliquity) -> tuple[np.ndarray, np.ndarray]:
    """(lon, lat) from equatorial (ra, dec) for the given obliquity, radians (Meeus eq. 13.1-2)."""
    ra, dec, eps = (np.asarray(x, dtype=float) for x in (ra, dec, obliquity))
    lon = np.arctan2(np.sin(ra) * np.cos(eps) + np.tan(dec) * np.sin(eps), np.cos(ra))
    lat = np.arcsin(np.sin(dec) * np.cos(eps) - np.cos(dec) * np.sin(eps) * np.sin(ra))
    return np.mod(lon, 2 * np.pi), lat


def ecliptic_of_date_to_j2000_matrix(jd_tt) -> np.ndarray:
    """Matrix taking mean ecliptic-and-equinox-of-date vectors to J2000 mean equatorial:
    P^T R1(-eps_A)."""
    p = precession_matrix(jd_tt)
    return np.swapaxes(p, -1, -2) @ rot_x(-mean_obliquity(jd_tt))


# ------------------------------------------------------------------ aberration


def _earth_lbr_rates(jd_tt: np.ndarray) -> np.ndarray:
    """Heliocentric (L, B, R) of the Earth and their rates per day; shape (6, N)."""
    # Rates to 2e-5 relative need only the terms with A*(C + alpha) above 0.013 (2e-6 of the
    # mean motion 6283 rad/millennium) and the values (used only to orient the velocity)
    # the terms above 1e-5; select them once.
    return vsop("earth").lbr_rates(jd_tt, _earth_rate_terms())


_RATE_KEEP: np.ndarray | None = None


def _earth_rate_terms() -> np.ndarray:
    global _RATE_KEEP
    if _RATE_KEEP is None:
        s = vsop("earth")
        _RATE_KEEP = (np.abs(s.a) >= 1e-5) | (np.abs(s.a) * (s.c + s.power) >= 2e-6 * 6283.0)
    return _RATE_KEEP


def _earth_velocity_ecliptic_of_date(jd_tt) -> np.ndarray:
    """Heliocentric velocity of the Earth, mean ecliptic of date axes, au/day, (..., 3)."""
    jd = np.asarray(jd_tt, dtype=float)
    lbr = smooth(_earth_lbr_rates, jd, 16.0, 9, memo=segment_memo("earth rates"))
    return velocity_from_lbr_rates(lbr).reshape(jd.shape + (3,))


def velocity_from_lbr_rates(lbr_rates: np.ndarray) -> np.ndarray:
    """Cartesian velocity (N, 3) from spherical L, B, R and their rates, rows (6, N): the
    time derivative of (R cos B cos L, R cos B sin L, R sin B)."""
    lon, lat, r, dl, db, dr = lbr_rates
    cl, sl, cb, sb = np.cos(lon), np.sin(lon), np.cos(lat), np.sin(lat)
    vx = dr * cb * cl - r * sb * cl * db - r * cb * sl * dl
    vy = dr * cb * sl - r * sb * sl * db + r * cb * cl * dl
    vz = dr * sb + r * cb * db
    return np.stack([vx, vy, vz], axis=-1)


def earth_velocity_au_per_day(jd_tt) -> np.ndarray:
    """Heliocentric velocity of the Earth in J2000 mean equatorial axes, au/day, (..., 3).

    From the derivative of the VSOP87D series (terms contributing less than 1e-6 of the
    velocity dropped). The barycentric velocity differs by the Sun's, about 13 m/s, i.e. a
    relative 4e-4 (0.01" in aberration).
    """
    v = _earth_velocity_ecliptic_of_date(jd_tt)
    return _apply(ecliptic_of_date_to_j2000_matrix(jd_tt), v)


def dot3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Dot products of 3-vectors along the last axis (broadcasting); a sum written out,
    several times faster than ``np.sum(a * b, axis=-1)``'s reduction over a 3-long axis."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def norm3(v: np.ndarray) -> np.ndarray:
    """Lengths of 3-vectors along the last axis (see :func:`dot3`)."""
    return np.sqrt(dot3(v, v))


def aberrate(unit_vec, velocity_au_per_day) -> np.ndarray:
    """First-order aberration: u' = normalize(u + v/c - u (u.v)/c), same axes as ``v``."""
    u = np.asarray(unit_vec, dtype=float)
    beta = np.asarray(velocity_au_per_day, dtype=float) / C_AU_PER_DAY
    w = u + beta - u * dot3(u, beta)[..., None]
    return w / norm3(w)[..., None]


# 2 G M_sun / c^2 in au: 2 x 1476.625 m (IAU 2015 nominal GM_sun, Resolution B3) / 1 au.
TWO_GM_SUN_OVER_C2_AU = 2.0 * 1476.6250e-3 / AU_KM
# Floor of the deflection's denominator 1 + cos(angle at the Sun between body and observer)
# for a body behind the Sun's disk (there the formula diverges; the body is not visible).
_MIN_ONE_PLUS_Q_DOT_E = 1.0 - np.cos(np.radians(0.267))


def deflect_by_sun(obs_to_body_au, sun_to_obs_au) -> np.ndarray:
    """Gravitational light deflection by the Sun of a body at a finite distance.

    ``obs_to_body_au``: astrometric (light-time corrected) vector from the observer to the
    body; ``sun_to_obs_au``: from the Sun to the observer; same axes, (..., 3). Returns the
    deflected observer-to-body vector (same length to 1e-11). Kaplan et al. 2005 (USNO
    Circular 179 / NOVAS ``grav_vec``), with p, q, e the unit vectors observer -> body,
    Sun -> body and Sun -> observer:
    p' = p + (2GM/(c^2 |E|)) ((p.q) e - (e.p) q) / (1 + q.e).
    For a star (q = p) this is the formula of :mod:`skydome.astro.stars`.
    """
    pos = np.asarray(obs_to_body_au, dtype=float)
    pe = np.asarray(sun_to_obs_au, dtype=float)
    pq = pos + pe  # Sun -> body
    p_mag = norm3(pos)[..., None]
    e_mag = norm3(pe)[..., None]
    p_hat = pos / p_mag
    q_hat = pq / norm3(pq)[..., None]
    e_hat = pe / e_mag
    p_dot_q = dot3(p_hat, q_hat)[..., None]
    q_dot_e = dot3(q_hat, e_hat)[..., None]
    e_dot_p = dot3(e_hat, p_hat)[..., None]
    fac = TWO_GM_SUN_OVER_C2_AU / e_mag / np.maximum(1.0 + q_dot_e, _MIN_ONE_PLUS_Q_DOT_E)
    return pos + fac * (p_dot_q * e_hat - e_dot_p * q_hat) * p_mag


def apply_aberration(unit_vec_j2000, jd_tt) -> np.ndarray:
    """Annual aberration of J2000 unit vectors (..., 3) at ``jd_tt``; returns unit vectors.

    ``unit_vec_j2000`` broadcasts against ``jd_tt`` (give a (N, 3) array with (N,) times,
    or (M, 1, 3) stars with (N,) times for (M, N, 3)).
    """
    return aberrate(unit_vec_j2000, earth_velocity_au_per_day(jd_tt))


# ------------------------------------------------------------------ horizontal frame


def equatorial_to_horizontal(ra_rad, dec_rad, lst_rad, lat_rad) -> tuple[np.ndarray, np.ndarray]:
    """(alt, az) in radians from hour angle H = lst - ra and declination (Meeus eq. 13.5-6).

    Azimuth is from north through east in [0, 2pi). All inputs broadcast together.
    """
    alt, az = enu_to_horizontal(_equatorial_to_enu(ra_rad, dec_rad, lst_rad, lat_rad))
    return alt, az


def _equatorial_to_enu(ra, dec, lst, lat) -> np.ndarray:
    h = np.asarray(lst, float) - np.asarray(ra, float)
    dec = np.asarray(dec, float)
    lat = np.asarray(lat, float)
    cd, sd, ch = np.cos(dec), np.sin(dec), np.cos(h)
    cp, sp = np.cos(lat), np.sin(lat)
    e = -cd * np.sin(h)
    n = sd * cp - cd * ch * sp
    u = sd * sp + cd * ch * cp
    return np.stack(np.broadcast_arrays(e, n, u), axis=-1)


def enu_to_horizontal(enu) -> tuple[np.ndarray, np.ndarray]:
    """(alt, az) in radians of ENU vectors (..., 3) (any length); az from north via east."""
    v = np.asarray(enu, dtype=float)
    e, n, u = v[..., 0], v[..., 1], v[..., 2]
    return np.arctan2(u, np.hypot(e, n)), np.mod(np.arctan2(e, n), 2 * np.pi)


def equatorial_to_enu_matrix(lst_rad, lat_rad) -> np.ndarray:
    """Matrix (..., 3, 3) taking true-of-date equatorial vectors to local ENU.

    ``lst_rad``: local apparent sidereal time; ``lat_rad``: geodetic latitude.
    """
    lst, lat = np.broadcast_arrays(np.asarray(lst_rad, float), np.asarray(lat_rad, float))
    cl, sl = np.cos(lst), np.sin(lst)
    cp, sp = np.cos(lat), np.sin(lat)
    m = np.empty(lst.shape + (3, 3))
    m[..., 0, 0] = -sl  # east = (-sin lst, cos lst, 0)
    m[..., 0, 1] = cl
    m[..., 0, 2] = 0.0
    m[..., 1, 0] = -sp * cl  # north
    m[..., 1, 1] = -sp * sl
    m[..., 1, 2] = cp
    m[..., 2, 0] = cp * cl  # up
    m[..., 2, 1] = cp * sl
    m[..., 2, 2] = sp
    return m


def geodetic_to_geocentric_km(lat_rad, lon_rad, height_m) -> np.ndarray:
    """Earth-fixed geocentric position (km, (..., 3)) of a WGS84 geodetic position."""
    lat, lon, h = np.broadcast_arrays(
        np.asarray(lat_rad, float), np.asarray(lon_rad, float), np.asarray(height_m, float)
    )
    e2 = WGS84_F * (2.0 - WGS84_F)
    sp, cp = np.sin(lat), np.cos(lat)
    n = WGS84_A_KM / np.sqrt(1.0 - e2 * sp * sp)  # prime-vertical radius
    hk = h * 1e-3
    return np.stack(
        [(n + hk) * cp * np.cos(lon), (n + hk) * cp * np.sin(lon), (n * (1 - e2) + hk) * sp],
        axis=-1,
    )


def diurnal_speed_au_per_day(lat_rad: float, height_m: float) -> float:
    """Eastward speed (au/day) at which the Earth's rotation carries an observer at a WGS84
    geodetic latitude and height: EARTH_OMEGA times the distance from the axis (the velocity
    of the diurnal aberration)."""
    r = geodetic_to_geocentric_km(lat_rad, 0.0, height_m)
    return float(np.hypot(r[0], r[1])) / AU_KM * EARTH_OMEGA * 86400.0


# ------------------------------------------------------------------ refraction
# refraction_bennett and refraction_saemundsson: skydome.physics.refraction (re-exported).
