"""The Moon's albedo map and spectral albedo (skydome.celestial.moon_albedo).

External numbers used here:
* feature positions: IAU/USGS Gazetteer of Planetary Nomenclature centres (as given in the brief);
* maria/highland contrast: Velikodsky et al. (2011, Icarus 214, 30) Table 2, typical highland /
  typical mare equigonal albedo at phase 6 deg, 0.1531 / 0.0936 = 1.64 at 560 nm; normal
  albedos of about 0.07 (maria) and 0.11-0.14 (highlands), ratio 1.6-2.0;
* Johnson B and V: Bessell (1990, PASP 102, 1181) Table 2 passbands;
* colours: Sun B-V = 0.653 +- 0.003 (Ramirez et al. 2012, ApJ 752, 5; 0.65 in Allen's
  Astrophysical Quantities); Moon B-V = 0.92 (Harris 1961, quoted by van den Bergh 1962,
  AJ 67, 147) and 0.876 +- 0.022 for Mare Serenitatis, 0.86 for the mean of 11 regions
  (van den Bergh 1962);
* ROLO: Kieffer & Stone (2005, AJ 129, 2887) eq. 10 and Table 4, an independent lunar model.
"""

from __future__ import annotations

import hashlib
import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from skydome.celestial import moon_albedo as ma
from skydome.errors import ParameterError
from skydome.spectra.tables import solar_irradiance

REPO = Path(__file__).resolve().parent.parent

# Named maria: (lat N, lon E) in degrees.
MARIA = {
    "Mare Imbrium": (32.8, -15.6),
    "Mare Serenitatis": (28.0, 17.5),
    "Mare Tranquillitatis": (8.5, 31.4),
    "Oceanus Procellarum": (18.4, -57.4),
    "Mare Crisium": (17.0, 59.1),
}
SOUTHERN_HIGHLANDS = (-20.0, 10.0)
TYCHO = (-43.3, -11.2)


def _pixel_grid():
    a = ma.moon_albedo_map()
    h, w = a.shape
    lat = np.radians(90.0 - (np.arange(h) + 0.5) * 180.0 / h)
    lon = np.radians(-180.0 + (np.arange(w) + 0.5) * 360.0 / w)
    return a, *np.meshgrid(lat, lon, indexing="ij")


def region_mean(lat_deg: float, lon_deg: float, radius_deg: float) -> float:
    """Area-weighted mean of the map over a spherical cap."""
    a, lat, lon = _pixel_grid()
    la, lo = math.radians(lat_deg), math.radians(lon_deg)
    cos_d = np.sin(lat) * math.sin(la) + np.cos(lat) * math.cos(la) * np.cos(lon - lo)
    sel = cos_d > math.cos(math.radians(radius_deg))
    wt = np.cos(lat[sel])
    return float((a[sel] * wt).sum() / wt.sum())


# ---------------------------------------------------------------------------------------------
# the map
# ---------------------------------------------------------------------------------------------


def test_map_shape_type_and_cache():
    a = ma.moon_albedo_map()
    assert a.shape == (512, 1024) and a.dtype == np.float32
    assert not a.flags.writeable
    assert ma.moon_albedo_map() is a  # cached
    assert np.all(np.isfinite(a)) and 0.2 < a.min() and a.max() < 4.0
    meta = ma.moon_albedo_metadata()
    assert "public domain" in meta["licence"]
    assert meta["source_sha256"].startswith("13b79742")
    assert "east-positive" in meta["longitude"]


def test_packaged_file_is_small():
    path = REPO / "src" / "skydome" / "data" / "moon_albedo.npz"
    assert path.stat().st_size < 1.5e6


@pytest.mark.parametrize("name", list(MARIA))
def test_maria_darker_than_southern_highlands(name):
    # A mare's floor (2 deg cap) against the southern highlands around 20 S 10 E. Measured:
    # maria 0.53-0.65, highlands 1.13.
    mare = region_mean(*MARIA[name], 2.0)
    highland = region_mean(*SOUTHERN_HIGHLANDS, 2.0)
    assert mare < 0.75 < 1.0 < highland, (name, mare, highland)


def test_highland_to_maria_ratio():
    # Published: typical highland / typical mare 1.64 at 560 nm (Velikodsky et al. 2011 Table 2,
    # phase 6 deg); normal albedos 0.11-0.14 against 0.07, 1.6-2.0. The five maria here include
    # the darkest, titanium-rich ones (Tranquillitatis, Procellarum: 0.53-0.55 in this map,
    # against 0.64-0.65 for Imbrium and Serenitatis), and the map's reflectance is at phase
    # 60 deg, not near opposition; hence [1.5, 2.2]. A wrong display decoding gives 4-5 (sRGB
    # curve or a gamma without the 0.16 offset). Measured: 1.87.
    maria = np.mean([region_mean(*p, 2.0) for p in MARIA.values()])
    ratio = region_mean(*SOUTHERN_HIGHLANDS, 2.0) / maria
    assert 1.5 <= ratio <= 2.2, ratio


def test_tycho_is_bright():
    # Tycho's floor and the ray material around it are among the brightest near-side terrain.
    # Measured: 1.91 in a 1 deg cap, against 1.14 for the southern highlands.
    tycho = region_mean(*TYCHO, 1.0)
    assert tycho > 1.5 and tycho > 1.4 * region_mean(*SOUTHERN_HIGHLANDS, 1.0), tycho


def test_map_orientation_not_mirrored():
    # East/west and north/south, with features whose mirror images differ: the bright crater
    # Copernicus (9.6 N 20.1 W) against 9.6 N 20.1 E (the western edge of Mare Tranquillitatis), and
    # Mare Frigoris (56 N 0 E) against the highlands at 56 S.
    assert region_mean(9.6, -20.1, 0.8) > 1.8 * region_mean(9.6, 20.1, 0.8)
    assert region_mean(56.0, 0.0, 2.0) < 0.85 * region_mean(-56.0, 0.0, 2.0)


def test_near_side_disk_mean_is_one():
    # Independent of how the tool normalised (cell sums): sample the full Moon's projected disk
    # on a uniform 1201 x 1201 grid of image-plane points (each element of the disk alike),
    # map each to selenographic coordinates by orthographic projection from the sub-Earth
    # point (0, 0), and average the bilinear values. Measured 0.99999; bilinear vs cell means
    # and the grid's edge cells account for well under 0.5 %.
    x = np.linspace(-1.0, 1.0, 1201)
    xx, yy = np.meshgrid(x, x)
    inside = xx**2 + yy**2 < 1.0
    zz = np.sqrt(1.0 - xx[inside] ** 2 - yy[inside] ** 2)
    lat = np.arcsin(yy[inside])
    lon = np.arctan2(xx[inside], zz)
    mean = ma.albedo_at(lon, lat).mean()
    assert mean == pytest.approx(ma.MAP_NEAR_SIDE_DISK_MEAN, rel=5e-3)
    assert ma.moon_albedo_metadata()["near_side_disk_mean"] == pytest.approx(1.0, abs=1e-4)


def test_albedo_at_pixel_centres_and_wrap():
    a = ma.moon_albedo_map()
    h, w = a.shape
    j, i = 137, 5
    lat = math.radians(90.0 - (j + 0.5) * 180.0 / h)
    lon = math.radians(-180.0 + (i + 0.5) * 360.0 / w)
    assert ma.albedo_at(lon, lat) == pytest.approx(float(a[j, i]), rel=1e-6)
    # Longitude wraps: +-2 pi and the seam at +-180 deg.
    lons = np.linspace(-math.pi, math.pi, 97)
    lats = np.full_like(lons, math.radians(12.3))
    base = ma.albedo_at(lons, lats)
    np.testing.assert_allclose(ma.albedo_at(lons + 2 * math.pi, lats), base, rtol=1e-12)
    np.testing.assert_allclose(ma.albedo_at(lons - 4 * math.pi, lats), base, rtol=1e-12)
    assert ma.albedo_at(math.pi, 0.2) == pytest.approx(ma.albedo_at(-math.pi, 0.2), rel=1e-12)
    # Across the seam the value is the interpolation of the last and first columns.
    jj = 200
    lat_c = math.radians(90.0 - (jj + 0.5) * 180.0 / h)
    mid = 0.5 * (float(a[jj, -1]) + float(a[jj, 0]))
    assert ma.albedo_at(math.pi, lat_c) == pytest.approx(mid, rel=1e-6)
    # Poles: finite, equal to the outermost row's interpolation.
    assert np.isfinite(ma.albedo_at(0.3, math.pi / 2)) and np.isfinite(
        ma.albedo_at(0.3, -math.pi / 2)
    )
    # Broadcasting.
    assert ma.albedo_at(np.zeros((3, 1)), np.zeros((1, 4))).shape == (3, 4)


@pytest.mark.parametrize(
    "lon, lat",
    [(0.0, 1.6), (0.0, -1.58), (0.0, float("nan")), (float("inf"), 0.0), (float("nan"), 0.0)],
)
def test_albedo_at_rejects_bad_input(lon, lat):
    with pytest.raises(ParameterError, match="rad"):
        ma.albedo_at(lon, lat)


def test_build_tool_reproduces_the_packaged_map():
    source = REPO / "build" / "moon" / "lroc_color_poles_2k.tif"
    if not source.is_file():
        pytest.skip(f"source map not present at {source} (see src/skydome/data/moon_albedo.txt)")
    spec = importlib.util.spec_from_file_location(
        "build_moon_albedo", REPO / "tools" / "build_moon_albedo.py"
    )
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    blob, meta = tool.build(source, 1024, tool.SOURCE_SHA256)
    packaged = (REPO / "src" / "skydome" / "data" / "moon_albedo.npz").read_bytes()
    assert hashlib.sha256(blob).hexdigest() == hashlib.sha256(packaged).hexdigest()


def test_build_tool_decoding_inverts_the_svs_encoding():
    # The SVS page's encoding, applied forward to known linear reflectances, must come back.
    spec = importlib.util.spec_from_file_location(
        "build_moon_albedo", REPO / "tools" / "build_moon_albedo.py"
    )
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    lin = np.array([[[0.01, 0.02, 0.03], [0.05, 0.06, 0.07]]])
    enc = np.array([0.935, 1.005, 1.04]) * lin ** (1 / 2.8)
    v = (enc - 0.16) / (0.40 - 0.16) * 255.0
    np.testing.assert_allclose(tool.decode(v), lin, rtol=1e-12)


# ---------------------------------------------------------------------------------------------
# the spectral albedo
# ---------------------------------------------------------------------------------------------

# Velikodsky et al. (2011) Table 2, whole-Moon equigonal albedo at phase 6 deg (4 decimals).
VELIKODSKY_443, VELIKODSKY_467, VELIKODSKY_700 = 0.0988, 0.1049, 0.1531


def test_spectral_albedo_is_one_at_550_nm_and_holds_its_ends():
    assert ma.moon_spectral_albedo(550.0) == pytest.approx(1.0, abs=1e-12)
    s = ma.moon_spectral_albedo([200.0, 350.0, 1050.0, 3000.0])
    assert s[0] == s[1] and s[2] == s[3]
    assert ma.moon_spectral_albedo(np.ones((2, 3)) * 600.0).shape == (2, 3)


def test_spectral_albedo_ratio_700_450_against_the_table():
    # 450 nm lies between the 443 and 467 nm rows: linear interpolation of the published values.
    a450 = VELIKODSKY_443 + (450.0 - 443.0) / (467.0 - 443.0) * (VELIKODSKY_467 - VELIKODSKY_443)
    expected = VELIKODSKY_700 / a450  # 1.522
    # Each published value is rounded to 0.00005 on >= 0.0988 (<= 5.1e-4 relative), so the
    # ratio is known to 1.0e-3; the CSV's relative column adds 5e-6.
    got = float(ma.moon_spectral_albedo(700.0) / ma.moon_spectral_albedo(450.0))
    assert got == pytest.approx(expected, rel=1.0e-3)


def _rolo_disk_reflectance(a, d, g_deg: float) -> float:
    """Kieffer & Stone (2005) eq. 10 with zero libration: ln A = sum a_i g^i (g in rad) +
    d1 exp(-g/p1) + d2 exp(-g/p2) + d3 cos((g - p3)/p4) (g in deg; p from their Table 4)."""
    p1, p2, p3, p4 = 4.06054, 12.8802, -30.5858, 16.7498
    g = math.radians(g_deg)
    ln_a = sum(ai * g**i for i, ai in enumerate(a))
    ln_a += d[0] * math.exp(-g_deg / p1) + d[1] * math.exp(-g_deg / p2)
    ln_a += d[2] * math.cos((g_deg - p3) / p4)
    return math.exp(ln_a)


def test_spectral_albedo_against_rolo():
    # An independent data set and model: ROLO (Kieffer & Stone 2005, Table 4 rows 441.6 and
    # 703.6 nm) at phase 6 deg gives A(703.6)/A(441.6) = 1.469; the Velikodsky spectrum gives
    # 1.561 (6.3 % more). The two data sets are known to differ by more than that in absolute
    # terms (ROLO/Velikodsky = 0.87 at 603 nm, Velikodsky et al. abstract; ROLO's stated
    # absolute uncertainty is 5-10 %), so this asks for agreement on the Moon's reddening to
    # 10 %: a neutral (1.0) or inverted spectrum fails by far.
    a441 = (-2.31964, -1.72114, 0.37286, -0.19304)
    d441 = (0.37935, -0.09562, 0.00970)
    a703 = (-1.92103, -1.60151, 0.36924, -0.20567)
    d703 = (0.37155, -0.13989, 0.00412)
    rolo = _rolo_disk_reflectance(a703, d703, 6.0) / _rolo_disk_reflectance(a441, d441, 6.0)
    ours = float(ma.moon_spectral_albedo(703.6) / ma.moon_spectral_albedo(441.6))
    assert ours == pytest.approx(rolo, rel=0.10), (ours, rolo)


# Bessell (1990) Table 2: B from 360 to 560 nm and V from 470 to 700 nm, 10 nm steps.
BESSELL_B = [0.0, 0.030, 0.134, 0.567, 0.920, 0.978, 1.000, 0.978, 0.935, 0.853, 0.740,
             0.640, 0.536, 0.424, 0.325, 0.235, 0.150, 0.095, 0.043, 0.009, 0.0]  # fmt: skip
BESSELL_V = [0.0, 0.030, 0.163, 0.458, 0.780, 0.967, 1.000, 0.973, 0.898, 0.792, 0.684,
             0.574, 0.461, 0.359, 0.270, 0.197, 0.135, 0.081, 0.045, 0.025, 0.017, 0.013,
             0.009, 0.0]  # fmt: skip


def _trapezoid(y: np.ndarray, x: np.ndarray) -> float:
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))  # numpy 1.24 has no trapezoid


@pytest.mark.parametrize("photon_counting", [False, True])
def test_moon_is_redder_than_the_sun_in_b_minus_v(photon_counting):
    # Moonlight = sunlight (ASTM G-173 extraterrestrial spectrum, skydome.spectra) x the
    # spectral albedo. Its B-V minus the Sun's is independent of the magnitude zero points:
    #   delta = -2.5 log10[(<A>_B) / (<A>_V)], <A>_X = int F A S_X / int F S_X.
    # Published: 0.92 - 0.65 = 0.27 (Harris 1961 via van den Bergh 1962; Allen); van den
    # Bergh's own photoelectric values, 0.86-0.88, give 0.21-0.23. Tolerance 0.05 covers that
    # spread, the Sun's 0.64-0.66 and the 10 nm binning of the solar table (~0.01). Bessell's
    # curves are energy responses; the photon-counting weighting (x lambda) moves the result
    # by 0.003. Measured: 0.245 (energy), 0.242 (photon counting).
    wl = np.arange(360.0, 700.0 + 0.25, 0.5)
    sun = solar_irradiance(wl) * (wl if photon_counting else 1.0)
    sb = np.interp(wl, np.arange(360.0, 561.0, 10.0), BESSELL_B, left=0.0, right=0.0)
    sv = np.interp(wl, np.arange(470.0, 701.0, 10.0), BESSELL_V, left=0.0, right=0.0)
    alb = ma.moon_spectral_albedo(wl)
    mean_b = _trapezoid(sun * alb * sb, wl) / _trapezoid(sun * sb, wl)
    mean_v = _trapezoid(sun * alb * sv, wl) / _trapezoid(sun * sv, wl)
    delta_bv = -2.5 * math.log10(mean_b / mean_v)
    assert delta_bv == pytest.approx(0.27, abs=0.05), delta_bv


@pytest.mark.parametrize("bad", [0.0, -5.0, float("nan"), float("inf")])
def test_spectral_albedo_rejects_bad_wavelengths(bad):
    with pytest.raises(ParameterError, match="nm"):
        ma.moon_spectral_albedo([500.0, bad])
