"""Zodiacal light: sunlight scattered by interplanetary dust, from Leinert et al. 1998.

The brightness is Leinert et al. (1998, A&AS 127, 1) table 17, shipped as
``data/zodiacal_leinert1998.csv`` (source and transcription in the .txt beside it): 500 nm
brightness by helioecliptic longitude lambda - lambda_sun and ecliptic latitude beta,
interpolated bilinearly in the table's nodes and symmetric in both angles. The spectrum is
the solar one reddened as Leinert et al. sec. 8.1 give it. Float64 twins of what
``shaders/night/zodiacal_light.glsl`` draws.
"""

from __future__ import annotations

import math
from functools import lru_cache
from importlib import resources

import numpy as np

from skydome.astro import frames
from skydome.astro.sun import sun_apparent_geocentric
from skydome.astro.time import gast
from skydome.night.airglow import bin_relative_to_sun, s10_to_luminance
from skydome.spectra.tables import solar_irradiance

#: 1 S10 (solar-type spectrum) at 500 nm in the table's unit, 1e-8 W m^-2 sr^-1 um^-1
#: (Leinert et al. 1998, note to table 17: 1 S10 = 1.28e-8 W m^-2 sr^-1 um^-1).
TABLE_UNITS_PER_S10 = 1.28
#: The table's nodes (deg).
DLON_NODES_DEG = (0, 5, 10, 15, 20, 25, 30, 35, 40, 45, 60, 75, 90, 105, 120, 135, 150, 165, 180)
BETA_NODES_DEG = (0, 5, 10, 15, 20, 25, 30, 45, 60, 75, 90)


@lru_cache(maxsize=1)
def load_table() -> np.ndarray:
    """Table 17 as shipped: (19, 11) array over (DLON_NODES_DEG, BETA_NODES_DEG) in
    1e-8 W m^-2 sr^-1 um^-1 at 500 nm, NaN where the paper gives no value."""
    text = resources.files("skydome.data").joinpath("zodiacal_leinert1998.csv").read_text()
    rows = [line for line in text.splitlines() if line and not line.startswith("#")][1:]
    table = np.full((len(DLON_NODES_DEG), len(BETA_NODES_DEG)), np.nan)
    for i, line in enumerate(rows):
        cells = line.split(",")
        if float(cells[0]) != DLON_NODES_DEG[i]:
            raise ValueError(f"zodiacal table row {i} is for {cells[0]} deg")
        for j, cell in enumerate(cells[1:]):
            if cell.strip():
                table[i, j] = float(cell)
    table.setflags(write=False)
    return table


@lru_cache(maxsize=1)
def filled_table() -> np.ndarray:
    """Table 17 with its empty near-Sun cells (solar elongation below ~15 deg, where the
    zodiacal light merges into the F-corona and the sky is in twilight anyway) filled: along
    each row, towards beta = 0, log brightness is extrapolated linearly in beta from the row's
    first two tabulated cells. E.g. lambda - lambda_sun = 0: 3140 at beta 15 and 1610 at 20
    give 6125 at 10, 11950 at 5 and 23300 at 0."""
    t = np.array(load_table())
    beta = np.asarray(BETA_NODES_DEG, dtype=np.float64)
    for i in range(t.shape[0]):
        valid = np.flatnonzero(np.isfinite(t[i]))
        j1, j2 = valid[0], valid[1]
        slope = (math.log(t[i, j2]) - math.log(t[i, j1])) / (beta[j2] - beta[j1])
        for j in range(j1):
            t[i, j] = t[i, j1] * math.exp(slope * (beta[j] - beta[j1]))
    t.setflags(write=False)
    return t


def _bracket(nodes: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Index of the interval of ``nodes`` holding each ``x`` and the fraction across it."""
    i = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, len(nodes) - 2)
    f = (x - nodes[i]) / (nodes[i + 1] - nodes[i])
    return i, np.clip(f, 0.0, 1.0)


def zodiacal_table_value(dlon_deg, beta_deg) -> np.ndarray:
    """Bilinear interpolation of the (filled) table in its own nodes, in the table's unit
    (1e-8 W m^-2 sr^-1 um^-1 at 500 nm). Symmetric: |lambda - lambda_sun| folded into
    [0, 180] deg, |beta| into [0, 90] deg."""
    dl = np.abs((np.asarray(dlon_deg, dtype=np.float64) + 180.0) % 360.0 - 180.0)
    b = np.minimum(np.abs(np.asarray(beta_deg, dtype=np.float64)), 90.0)
    t = filled_table()
    i, fx = _bracket(np.asarray(DLON_NODES_DEG, dtype=np.float64), dl)
    j, fy = _bracket(np.asarray(BETA_NODES_DEG, dtype=np.float64), b)
    return (
        (1 - fx) * (1 - fy) * t[i, j]
        + fx * (1 - fy) * t[i + 1, j]
        + (1 - fx) * fy * t[i, j + 1]
        + fx * fy * t[i + 1, j + 1]
    )


def zodiacal_s10(dlon_deg, beta_deg) -> np.ndarray:
    """Zodiacal brightness in S10 (solar-type spectrum, at 500 nm); e.g. the ecliptic pole
    77 / 1.28 = 60 S10, the antisolar point (gegenschein) 230 / 1.28 = 180 S10."""
    return zodiacal_table_value(dlon_deg, beta_deg) / TABLE_UNITS_PER_S10


def zodiacal_luminance(dlon_deg, beta_deg) -> np.ndarray:
    """Luminance (cd/m^2) of the solar-spectrum light of the same S10 brightness (what the
    layer scales its reddened colours by: they are normalised to the solar spectrum's
    luminance at equal 500 nm radiance)."""
    return s10_to_luminance(zodiacal_s10(dlon_deg, beta_deg))


# ---------------------------------------------------------------------- colour

#: Elongations (deg) between which the reddening slopes are interpolated, and the slopes
#: (below, above 500 nm) at each end: Leinert et al. 1998 sec. 8.1, eq. 22-23, f_co(lambda) =
#: 1 + b log10(lambda / 500 nm) with b = 1.2 / 0.8 at elongation 30 deg and 0.9 / 0.6 at 90 deg
#: and beyond (the zodiacal light is redder than the Sun, more so near the Sun).
REDDENING_ELONGATION_DEG = (30.0, 90.0)
REDDENING_SLOPES = ((1.2, 0.8), (0.9, 0.6))


def reddening(wavelengths_nm, elongation_deg: float) -> np.ndarray:
    """Leinert's colour correction f_co: the zodiacal spectrum over the solar one, 1 at
    500 nm, at a solar elongation (deg; clamped to 30-90)."""
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    e0, e1 = REDDENING_ELONGATION_DEG
    w = float(np.clip((elongation_deg - e0) / (e1 - e0), 0.0, 1.0))
    blue = (1 - w) * REDDENING_SLOPES[0][0] + w * REDDENING_SLOPES[1][0]
    red = (1 - w) * REDDENING_SLOPES[0][1] + w * REDDENING_SLOPES[1][1]
    x = np.log10(wl / 500.0)
    return 1.0 + np.where(x < 0, blue, red) * x


def zodiacal_relative_spectrum(wavelengths_nm, elongation_deg: float) -> np.ndarray:
    """The reddened solar spectrum binned onto ``wavelengths_nm``, relative to the solar
    spectrum (transfer values for SpectralBasis), normalised to 1 at 500 nm before binning."""

    grid = np.arange(360.0, 831.0, 1.0)
    radiance = solar_irradiance(grid) * reddening(grid, elongation_deg)
    return bin_relative_to_sun(grid, radiance, wavelengths_nm)


# ---------------------------------------------------------------------- geometry


def enu_to_ecliptic_matrix(observer, time) -> np.ndarray:
    """3x3 matrix taking ENU vectors of ``observer`` at one ``time`` (a skydome.astro Time)
    to the mean ecliptic and equinox of date: ENU = E N(t) R1(-eps_A) ecl, with E the true
    equator -> ENU matrix of the local apparent sidereal time (frames.equatorial_to_enu_matrix)
    and N the nutation matrix (IAU 1980, as skydome.astro.Observer uses)."""

    jd_tt = float(np.asarray(time.jd_tt).ravel()[0])
    jd_ut1 = float(np.asarray(time.jd_ut1).ravel()[0])
    lst = float(gast(jd_ut1, jd_tt)) + math.radians(float(observer.longitude))
    enu = frames.equatorial_to_enu_matrix(lst, math.radians(float(observer.latitude)))
    ecl_to_true = frames.ecliptic_to_true_equator_matrix(jd_tt)
    return (enu @ ecl_to_true).T


def sun_ecliptic_longitude(time) -> float:
    """The Sun's apparent geocentric ecliptic longitude (rad) at ``time`` (skydome.astro.sun)."""

    jd_tt = float(np.asarray(time.jd_tt).ravel()[0])
    return float(sun_apparent_geocentric(jd_tt)["lon"])


def helioecliptic_matrix(observer, time) -> np.ndarray:
    """3x3 matrix taking ENU vectors to helioecliptic axes: x towards the Sun's ecliptic
    longitude on the ecliptic, z the north ecliptic pole (so lambda - lambda_sun =
    atan2(y, x) and beta = atan2(z, |xy|))."""
    s = sun_ecliptic_longitude(time)
    c, n = math.cos(s), math.sin(s)
    rot = np.array([[c, n, 0.0], [-n, c, 0.0], [0.0, 0.0, 1.0]])
    return rot @ enu_to_ecliptic_matrix(observer, time)


def helioecliptic_coordinates(directions_enu, matrix) -> tuple[np.ndarray, np.ndarray]:
    """(lambda - lambda_sun, beta) in degrees of unit ENU directions (..., 3)."""
    v = np.asarray(directions_enu, dtype=np.float64) @ np.asarray(matrix).T
    dlon = np.degrees(np.arctan2(v[..., 1], v[..., 0]))
    beta = np.degrees(np.arctan2(v[..., 2], np.hypot(v[..., 0], v[..., 1])))
    return dlon, beta


def elongation_deg(dlon_deg, beta_deg) -> np.ndarray:
    """Angular distance from the Sun (deg) of helioecliptic coordinates (deg)."""
    c = np.cos(np.radians(dlon_deg)) * np.cos(np.radians(beta_deg))
    return np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))


# ---------------------------------------------------------------------- GPU tables

#: Texels (nu, nv) of the zodiacal grid over the pseudo-angles (u, v) of
#: :func:`grid_coordinates`: a cell spans 0.23 to 0.46 deg of helioecliptic longitude and
#: of latitude.
GRID_SHAPE = (501, 251)


def grid_coordinates(h) -> tuple[np.ndarray, np.ndarray]:
    """The shader's table coordinates (u, v) in [0, 1] of helioecliptic vectors ``h``
    (..., 3; any length): "diamond" pseudo-angles, monotonic in |lambda - lambda_sun| and
    |beta| and made without inverse trigonometric functions: u = (1 - x / (|x| + |y|)) / 2
    (0 towards the Sun, 1/2 at 90 deg, 1 at the antisolar point), v = |z| / (rho + |z|)
    (0 on the ecliptic, 1 at its poles), rho = |(x, y)|. A step of one degree moves u by
    1/230 to 1/115 and v by 1/115 to 1/57."""
    h = np.asarray(h, dtype=np.float64)
    x, y, z = h[..., 0], np.abs(h[..., 1]), np.abs(h[..., 2])
    u = 0.5 - 0.5 * x / np.maximum(np.abs(x) + y, 1e-300)
    rho = np.hypot(x, y)
    return u, z / (rho + z)


def grid_angles_deg(u, v) -> tuple[np.ndarray, np.ndarray]:
    """(|lambda - lambda_sun|, |beta|) in degrees of pseudo-angles (u, v): the inverse of
    :func:`grid_coordinates`."""
    t = 1.0 - 2.0 * np.asarray(u, dtype=np.float64)  # x / (|x| + y)
    dlon = np.degrees(np.arctan2(np.where(t >= 0.0, 1.0 - t, 1.0 + t), t))
    v = np.asarray(v, dtype=np.float64)
    return dlon, np.degrees(np.arctan2(v, 1.0 - v))


def reddening_weight(dlon_deg, beta_deg) -> np.ndarray:
    """The weight of the far (elongation >= 90 deg) colour against the near (<= 30 deg) one:
    (elongation - 30 deg) / 60 deg clamped to [0, 1] (Leinert et al. 1998 sec. 8.1)."""
    e0, e1 = REDDENING_ELONGATION_DEG
    return np.clip((elongation_deg(dlon_deg, beta_deg) - e0) / (e1 - e0), 0.0, 1.0)


@lru_cache(maxsize=1)
def zodiacal_grid() -> np.ndarray:
    """The table the shader reads, (GRID_SHAPE[1], GRID_SHAPE[0], 2) float64 over (v, u) at
    the nodes u = i / (nu - 1), v = j / (nv - 1): (L, L w), L the node-bilinear luminance of
    :func:`zodiacal_luminance` (cd/m^2 of solar-type light) and w the
    :func:`reddening_weight`, so that one bilinear fetch gives the light's two colour terms."""
    nu, nv = GRID_SHAPE
    u, v = np.meshgrid(np.linspace(0.0, 1.0, nu), np.linspace(0.0, 1.0, nv))
    dlon, beta = grid_angles_deg(u, v)
    lum = zodiacal_luminance(dlon, beta)
    out = np.stack([lum, lum * reddening_weight(dlon, beta)], axis=-1)
    out.setflags(write=False)
    return out


def zodiacal_grid_value(h) -> np.ndarray:
    """Float64 twin of the shader's lookup: (L, L w) of helioecliptic vectors ``h`` (..., 3),
    bilinear in the grid's pseudo-angles between its nodes."""
    g = zodiacal_grid()
    nv, nu = g.shape[:2]
    u, v = grid_coordinates(h)
    x, y = u * (nu - 1), v * (nv - 1)
    i = np.clip(np.floor(x).astype(int), 0, nu - 2)
    j = np.clip(np.floor(y).astype(int), 0, nv - 2)
    fx, fy = (x - i)[..., None], (y - j)[..., None]
    return (1 - fy) * ((1 - fx) * g[j, i] + fx * g[j, i + 1]) + fy * (
        (1 - fx) * g[j + 1, i] + fx * g[j + 1, i + 1]
    )
