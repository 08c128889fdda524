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

from skydome.night.airglow import bin_relative_to_sun, s10_to_luminance

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
    from skydome.spectra.tables import solar_irradiance

    grid = np.arange(360.0, 831.0, 1.0)
    radiance = solar_irradiance(grid) * reddening(grid, elongation_deg)
    return bin_relative_to_sun(grid, radiance, wavelengths_nm)


# ---------------------------------------------------------------------- geometry


def enu_to_ecliptic_matrix(observer, time) -> np.ndarray:
    """3x3 matrix taking ENU vectors of ``observer`` at one ``time`` (a skydome.astro Time)
    to the mean ecliptic and equinox of date: ENU = E N(t) R1(-eps_A) ecl, with E the true
    equator -> ENU matrix of the local apparent sidereal time (frames.equatorial_to_enu_matrix)
    and N the nutation matrix (IAU 1980, as skydome.astro.Observer uses)."""
    from skydome.astro import frames
    from skydome.astro.time import gast

    jd_tt = float(np.asarray(time.jd_tt).ravel()[0])
    jd_ut1 = float(np.asarray(time.jd_ut1).ravel()[0])
    lst = float(gast(jd_ut1, jd_tt)) + math.radians(float(observer.longitude))
    enu = frames.equatorial_to_enu_matrix(lst, math.radians(float(observer.latitude)))
    ecl_to_true = frames.nutation_matrix(jd_tt) @ frames.rot_x(-frames.mean_obliquity(jd_tt))
    return (enu @ ecl_to_true).T


def sun_ecliptic_longitude(time) -> float:
    """The Sun's apparent geocentric ecliptic longitude (rad) at ``time`` (skydome.astro.sun)."""
    from skydome.astro.sun import sun_apparent_geocentric

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
