"""The Sun's limb darkening per wavelength, and its disk radiance normalised to the irradiance.

The law
-------
The specific intensity of the photosphere falls from the disk centre to the limb. With
mu = cos(psi), psi the *heliocentric angle* (between the local solar surface normal and the
line of sight; mu = 1 at the disk centre, 0 at the limb),

    I(mu, lambda) / I(1, lambda) = sum_{k=0..5} A_k(lambda) mu^k,

the fifth-order polynomial of Neckel & Labs (1994, "Solar limb darkening 1986-1990
(lambda lambda 303 to 1099 nm)", Solar Physics 153, 91-114), who measured it in continuum
windows. The A_k(lambda) used here are Neckel's analytical fits of those measurements
(Neckel 2005, "Analytical reference functions F(lambda) for the Sun's limb darkening and its
absolute continuum intensities (lambda lambda 300 to 1100 nm)", Solar Physics 229, 13-33),
in three wavelength ranges, with lambda in micrometres:

    A_0 = a_00 + a_01 / lambda
    A_1 = a_10 + a_11 / lambda + a_15 / lambda^5
    A_k = a_k0 + a_k5 / lambda^5          (k = 2..5)

built so that sum_k A_k = 1 at every wavelength (a_10 = 1 - sum of the other a_k0,
a_11 = -a_01, a_15 = -sum of the other a_k5). Ranges: 300-372.98 nm, 385-422.57 nm and
422.57-1100 nm. (The brief named Neckel & Labs 1984, "The solar radiation between 3300 and
12500 A", Solar Physics 90, 205; that paper is their absolute disk-centre spectrum, and the
limb-darkening coefficients are in the 1994 paper and Neckel 2005.)

The 39 coefficients were read from two independent implementations that agree digit for
digit: libRadtran 2.0.2 ``libsrc_c/sofi.c`` (``limbdarkening_Neckel``, eclipse code by
C. Emde and P. Ockenfuss; GPL-2, only the published numbers are used here) and the Icarus
light-curve code (R. Breton, BSD-3, ``Atmo_grid_lithium.Coeff_limb_darkening``). A third
copy (ISP-SST/sstred ``red_neckel_coefficients.pro``) prints a_55 = +0.003347 for the
422.57-1100 nm range; that sign breaks sum_k A_k = 1 by 0.0134 at 500 nm, the other two
copies satisfy it, so it is a typo there. The tabulated Neckel & Labs (1994) coefficients at
30 continuum wavelengths test these fits in ``tests/test_limb_darkening.py``.

Wavelengths outside 300-1100 nm are clamped to the nearest end (the renderer's 360-830 nm
grid lies inside). Between 372.98 and 385 nm, where Neckel gives no fit (the crowded Balmer
lines and the Ca II H and K lines leave no continuum), the coefficients are interpolated
linearly in wavelength between the two fits' end values. That bridge is uncertain: the two
ends' profiles differ by up to 10 % near mu = 0.2, and at 374.1 nm, the one tabulated
Neckel & Labs (1994) window in the gap, the bridge is 7.7 % above their profile at mu = 0.1,
3.1 % at mu = 0.5 and 0.2 % at mu = 0.9 (extending either fit does no better: the
385-422.57 nm fit is 6.5 %, 6.6 % and 1.3 % low there). Of the renderer's wavelengths only
380 nm falls in the gap.

How the renderer uses it
------------------------
The Sun has apparent angular radius alpha (sin alpha = R_sun / d). A sky direction at angle
theta <= alpha from the disk centre meets the solar sphere where the heliocentric angle psi
obeys (the sine rule in the triangle observer, Sun centre, surface point)

    sin(psi) = sin(theta) / sin(alpha),   mu = cos(psi) = sqrt(1 - (sin theta / sin alpha)^2),

exactly, for a sphere at any finite distance (:func:`mu_from_sky_angle`); rho = sin(theta) /
sin(alpha) is the fractional radius r/R_sun of the point on the disk (:func:`mu_from_radius`).
The radiance towards that direction, at wavelength lambda, is

    L(theta, lambda) = E_sun(lambda) * ld(mu(theta), lambda) / N(alpha, lambda),

with E_sun the solar spectral irradiance at the observer (W m^-2 nm^-1, on a surface facing
the Sun) and N the disk integral of the limb-darkening profile over solid angle,

    N(alpha, lambda) = integral over the disk of ld dOmega
                     = 2 pi sin^2(alpha) integral_0^1 ld(mu) mu / sqrt(cos^2 alpha
                                                       + mu^2 sin^2 alpha) dmu   [sr],

so that the disk integrates exactly to E_sun: integral L dOmega = E_sun
(:func:`disk_normalisation`, :func:`disk_radiance_factor`). For a uniform disk N is the
disk's solid angle Omega_disk = 2 pi (1 - cos alpha) = 4 pi sin^2(alpha / 2). For alpha << 1,
N = Omega_disk * D(lambda) * (1 + O(alpha^2)), where
D = (1 / (pi R^2)) * integral over the disk of I/I(1) = 2 integral_0^1 ld mu dmu
= 2 sum_k A_k / (k + 2) is the disk-mean to centre intensity ratio
(:func:`disk_mean_intensity`): the mean disk radiance is L_mean = E_sun / Omega_disk and the
centre radiance L_mean / D. At 1 AU (alpha = 4.652 mrad) that approximation is low by
4e-7 to 8e-7 (700 to 400 nm); pi sin^2(alpha), the area of the disk's projection, gives
Omega_disk * (1 - 5.4e-6).

The integral uses dOmega, not cos(theta) dOmega: cos(theta) >= cos(alpha) = 1 - 1.1e-5 at
1 AU. In GLSL, compute sin(theta) as length(cross(view_dir, sun_dir)), not from
sqrt(1 - dot^2), which loses all precision in float32 at theta ~ 1e-3; N(alpha, lambda) is
one number per wavelength, made on the CPU by :func:`disk_normalisation` and passed as a
uniform, and the polynomial coefficients come from :func:`limb_coefficients`.
"""

from __future__ import annotations

import numpy as np

from skydome.errors import ParameterError

__all__ = [
    "ANGULAR_RADIUS_MAX_RAD",
    "WAVELENGTH_RANGE_NM",
    "centre_to_disk_ratio",
    "disk_mean_intensity",
    "disk_normalisation",
    "disk_radiance_factor",
    "limb_coefficients",
    "limb_darkening",
    "mu_from_radius",
    "mu_from_sky_angle",
]

#: Wavelengths (nm) the coefficients cover; others are clamped to the nearest end.
WAVELENGTH_RANGE_NM = (300.0, 1100.0)
#: Largest apparent angular radius (rad) accepted, the Sun seen from 1.003 solar radii from
#: its centre; the 48-node quadrature of N(alpha) is accurate to 1e-12 up to here.
ANGULAR_RADIUS_MAX_RAD = 1.5

# Neckel (2005), Solar Physics 229, 13-33: A_k(lambda) = C0[k] + C1[k] / lambda
# + C5[k] / lambda^5 (lambda in micrometres), one row per wavelength range. Columns k = 0..5:
# C0 = (a_00, a_10, a_20, a_30, a_40, a_50), C1 = (a_01, a_11, 0, 0, 0, 0),
# C5 = (0, a_15, a_25, a_35, a_45, a_55). Numbers as in libRadtran 2.0.2 sofi.c and Icarus.
_RANGE_EDGES_NM = (372.98, 385.0, 422.57)  # range 1 ends, range 2 starts, range 3 starts
_C0 = np.array(
    [
        [0.35601, 1.11529, -0.67237, 0.18696, 0.00038, 0.01373],  # 300-372.98 nm
        [0.09900, 1.96884, -2.80511, 3.32780, -2.17878, 0.58825],  # 385-422.57 nm
        [0.75267, 0.93874, -1.89287, 2.42234, -1.71150, 0.49062],  # 422.57-1100 nm
    ]
)
_C1 = np.array(
    [
        [-0.085217, 0.085217, 0.0, 0.0, 0.0, 0.0],
        [0.010643, -0.010643, 0.0, 0.0, 0.0, 0.0],
        [-0.265577, 0.265577, 0.0, 0.0, 0.0, 0.0],
    ]
)
_C5 = np.array(
    [
        [0.0, -0.001871, 0.003589, -0.002415, 0.000897, -0.000200],
        [0.0, -0.009166, 0.024873, -0.029317, 0.018273, -0.004663],
        [0.0, -0.004095, 0.012582, -0.017117, 0.011977, -0.003347],
    ]
)

# Gauss-Legendre nodes on [0, 1] in mu for N(alpha). The integrand is a polynomial times
# 1/sqrt(cos^2 a + mu^2 sin^2 a), analytic on [0, 1] with poles at mu = +-i/tan(a): 48
# nodes give 1e-12 relative up to a = 1.5 rad (checked against 4000 nodes) and are exact
# to rounding for the Sun at 1 AU.
_GL_X, _GL_W = np.polynomial.legendre.leggauss(48)
_GL_MU = 0.5 * (_GL_X + 1.0)
_GL_W = 0.5 * _GL_W


def _as_float_array(value, name: str) -> np.ndarray:
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(
            f"{name} must be a number or an array of numbers, got {value!r}"
        ) from None


def _check(arr: np.ndarray, ok: np.ndarray, name: str, valid: str) -> None:
    """Raise ParameterError naming the first value where ``ok`` is False (NaN included)."""
    if not np.all(ok):
        bad = arr[~ok] if arr.ndim else arr
        raise ParameterError(
            f"{name} = {float(np.ravel(bad)[0])} is outside the valid range {valid}"
        )


def _wavelengths(wavelength_nm) -> np.ndarray:
    wl = _as_float_array(wavelength_nm, "wavelength_nm")
    _check(wl, np.isfinite(wl) & (wl > 0.0), "wavelength_nm", "(0, inf) nm")
    return wl


def _range_coefficients(wl_nm: np.ndarray, r: int) -> np.ndarray:
    """A_k of Neckel's fit number ``r`` (0, 1, 2) at ``wl_nm``; shape wl.shape + (6,)."""
    inv = 1000.0 / wl_nm[..., None]  # 1 / lambda in 1/um
    return _C0[r] + _C1[r] * inv + _C5[r] * inv**5


def limb_coefficients(wavelengths_nm) -> np.ndarray:
    """The polynomial coefficients A_0..A_5 of I(mu)/I(1) = sum_k A_k mu^k at each wavelength.

    Args:
        wavelengths_nm: wavelength(s) in nm, any shape; > 0 and finite. Values outside
            300-1100 nm are clamped to the nearest end; 372.98-385 nm interpolates linearly
            between Neckel's two neighbouring fits.

    Returns:
        Array of shape ``np.shape(wavelengths_nm) + (6,)`` (so (N, 6) for N wavelengths),
        dimensionless, A_0 first; each row sums to 1 within 1e-5 (the coefficients' rounding).

    Raises:
        ParameterError: a wavelength is NaN, infinite, zero or negative.
    """
    wl = np.clip(_wavelengths(wavelengths_nm), *WAVELENGTH_RANGE_NM)
    end1, start2, start3 = _RANGE_EDGES_NM
    r1 = _range_coefficients(wl, 0)
    r2 = _range_coefficients(wl, 1)
    r3 = _range_coefficients(wl, 2)
    t = ((wl - end1) / (start2 - end1))[..., None]
    gap = (1.0 - t) * _range_coefficients(np.asarray(end1), 0) + t * _range_coefficients(
        np.asarray(start2), 1
    )
    w = wl[..., None]
    return np.where(w < end1, r1, np.where(w < start2, gap, np.where(w < start3, r2, r3)))


def limb_darkening(mu, wavelength_nm) -> np.ndarray:
    """I(mu)/I(1): the Sun's intensity relative to the disk centre, Neckel & Labs (1994).

    Args:
        mu: cosine of the heliocentric angle, 1 at the disk centre, 0 at the limb; in [0, 1].
        wavelength_nm: wavelength(s) in nm (see :func:`limb_coefficients` for clamping).
            ``mu`` and ``wavelength_nm`` broadcast against each other.

    Returns:
        Dimensionless ratio, the broadcast shape of the inputs.

    Raises:
        ParameterError: mu outside [0, 1] or NaN; a bad wavelength.

    GLSL twin: ``limb_darkening``.
    """
    m = _as_float_array(mu, "mu")
    _check(m, (m >= 0.0) & (m <= 1.0), "mu", "[0, 1]")
    a = limb_coefficients(wavelength_nm)
    out = np.zeros(np.broadcast_shapes(m.shape, a.shape[:-1]))
    for k in range(5, -1, -1):  # Horner
        out = out * m + a[..., k]
    return out


def disk_mean_intensity(wavelength_nm) -> np.ndarray:
    """Mean intensity of the disk over its centre intensity, (1/(pi R^2)) integral I/I(1) dA.

    Equals 2 integral_0^1 (I(mu)/I(1)) mu dmu = 2 sum_k A_k / (k + 2) (area element
    dA = 2 pi r dr = 2 pi R^2 mu dmu). Dimensionless; about 0.73 at 400 nm, 0.84 at 700 nm.

    Args:
        wavelength_nm: wavelength(s) in nm, any shape (clamped as in :func:`limb_coefficients`).

    Raises:
        ParameterError: a bad wavelength.
    """
    a = limb_coefficients(wavelength_nm)
    return 2.0 * np.sum(a / np.arange(2.0, 8.0), axis=-1)


def centre_to_disk_ratio(wavelength_nm) -> np.ndarray:
    """Disk-centre intensity over the disk-mean intensity, 1 / :func:`disk_mean_intensity`.

    Dimensionless, > 1 (about 1.37 at 400 nm, 1.19 at 700 nm). Multiply the mean disk radiance
    E_sun / Omega_disk by it to get the centre radiance (small-disk limit).

    Raises:
        ParameterError: a bad wavelength.
    """
    return 1.0 / disk_mean_intensity(wavelength_nm)


def mu_from_radius(rho) -> np.ndarray:
    """Cosine of the heliocentric angle at fractional disk radius rho = r / R_sun.

    mu = sqrt(1 - rho^2): mu is the cosine of the angle between the solar surface normal and
    the line of sight (1 at the centre, 0 at the limb), for an observer far from the Sun;
    for a finite distance use rho = sin(theta) / sin(alpha) (:func:`mu_from_sky_angle`).

    Args:
        rho: fractional radius on the disk, dimensionless, in [0, 1].

    Raises:
        ParameterError: rho outside [0, 1] or NaN.
    """
    r = _as_float_array(rho, "rho")
    _check(r, (r >= 0.0) & (r <= 1.0), "rho", "[0, 1]")
    return np.sqrt((1.0 - r) * (1.0 + r))


def _angular_radius(angular_radius_rad) -> np.ndarray:
    a = _as_float_array(angular_radius_rad, "angular_radius_rad")
    ok = (a > 0.0) & (a <= ANGULAR_RADIUS_MAX_RAD)
    _check(a, ok, "angular_radius_rad", f"(0, {ANGULAR_RADIUS_MAX_RAD}] rad")
    return a


def _theta(theta_rad) -> np.ndarray:
    t = _as_float_array(theta_rad, "theta_rad")
    _check(t, (t >= 0.0) & (t <= np.pi), "theta_rad", "[0, pi] rad")
    return t


def mu_from_sky_angle(theta_rad, angular_radius_rad) -> np.ndarray:
    """mu at sky angle theta from the disk centre, for a disk of apparent radius alpha.

    Exact for a sphere seen from a finite distance: sin(psi) = sin(theta) / sin(alpha),
    mu = cos(psi) (see the module docstring).

    Args:
        theta_rad: angle(s) from the disk centre, rad, in [0, alpha].
        angular_radius_rad: the disk's apparent angular radius alpha, rad, in (0, 1.5].
            Broadcasts against ``theta_rad``.

    Raises:
        ParameterError: theta outside [0, alpha], or a bad angular radius.
    """
    t = _theta(theta_rad)
    a = _angular_radius(angular_radius_rad)
    t, a = np.broadcast_arrays(t, a)
    _check(t, t <= a, "theta_rad", "[0, angular_radius_rad] rad (the disk)")
    rho = np.minimum(np.sin(t) / np.sin(a), 1.0)
    return np.sqrt((1.0 - rho) * (1.0 + rho))


def disk_normalisation(angular_radius_rad, wavelength_nm) -> np.ndarray:
    """N(alpha, lambda) = integral over the disk of I/I(1) dOmega, in sr.

    N = 2 pi sin^2(alpha) sum_k A_k integral_0^1 mu^(k+1) / sqrt(cos^2 alpha
    + mu^2 sin^2 alpha) dmu, by 48-point Gauss-Legendre quadrature in mu (1e-12 relative).
    The disk radiance is E_sun * I(mu)/I(1) / N. About 6.80e-5 sr * D(lambda) at 1 AU.

    Args:
        angular_radius_rad: the disk's apparent angular radius alpha, rad, in (0, 1.5].
        wavelength_nm: wavelength(s) in nm; broadcasts against ``angular_radius_rad``.

    Raises:
        ParameterError: a bad angular radius or wavelength.
    """
    a = _angular_radius(angular_radius_rad)
    coef = limb_coefficients(wavelength_nm)
    shape = np.broadcast_shapes(a.shape, coef.shape[:-1])
    a = np.broadcast_to(a, shape)
    coef = np.broadcast_to(coef, shape + (6,))
    cos_a, sin_a = np.cos(a)[..., None], np.sin(a)[..., None]
    weight = _GL_W * _GL_MU / np.sqrt(cos_a**2 + (_GL_MU * sin_a) ** 2)  # (..., nodes)
    powers = _GL_MU[:, None] ** np.arange(6)  # (nodes, 6)
    moments = weight @ powers  # (..., 6): integral of mu^(k+1) / sqrt(...)
    return 2.0 * np.pi * np.sin(a) ** 2 * np.sum(coef * moments, axis=-1)


def disk_radiance_factor(theta_rad, angular_radius_rad, wavelength_nm) -> np.ndarray:
    """f with L(theta) = E_sun(lambda) * f: the limb-darkened disk normalised to unit integral.

    f = (I(mu(theta))/I(1)) / N(alpha, lambda) on the disk (theta <= alpha) and 0 off it, so
    that integral f dOmega = 1 over the sky: a disk of radiance E_sun * f delivers exactly the
    irradiance E_sun (W m^-2 nm^-1 in, W m^-2 sr^-1 nm^-1 out).

    Args:
        theta_rad: angle(s) from the disk centre, rad, in [0, pi].
        angular_radius_rad: the disk's apparent angular radius alpha, rad, in (0, 1.5].
        wavelength_nm: wavelength(s) in nm. All three broadcast together.

    Returns:
        f in 1/sr, the broadcast shape of the inputs.

    Raises:
        ParameterError: theta outside [0, pi], a bad angular radius or wavelength.
    """
    t = _theta(theta_rad)
    a = _angular_radius(angular_radius_rad)
    wl = _wavelengths(wavelength_nm)
    on_disk = t <= a  # shape of (t, a) broadcast; the wavelength axis joins below
    rho = np.where(on_disk, np.minimum(np.sin(t) / np.sin(a), 1.0), 1.0)
    mu = np.sqrt((1.0 - rho) * (1.0 + rho))
    f = limb_darkening(mu, wl) / disk_normalisation(a, wl)
    return np.where(on_disk, f, 0.0)
