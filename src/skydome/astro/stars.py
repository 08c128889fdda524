"""Star catalogue (Hipparcos 2, Hp <= 8) and apparent places of date, vectorized.

Data
----
``skydome/data/stars_hip2.npz`` holds the 37,622 stars of the Hipparcos new reduction
(van Leeuwen 2007, A&A 474, 653; CDS I/311) with Hp <= 8: ICRS position at epoch
J1991.25, proper motion, parallax, Hp, Johnson V (from Hp and B-V with Bessell 2000,
PASP 112, 961, Table 2), B-V and an effective temperature (Ballesteros 2012, EPL 97,
34008). ``skydome/data/stars_names.csv`` ties IAU proper names and Bayer/Flamsteed
designations (IAU WGSN catalogue of star names, 2018-09-07) and PyEphem's variant
spellings to HIP numbers. Both are written by ``tools/build_star_catalog.py``; nothing is
read from the network or from other packages at run time.

Apparent place
--------------
:func:`apparent_places` reproduces, for the whole catalogue at once, the chain of the
IAU/NOVAS "apparent place" (Explanatory Supplement to the Astronomical Almanac, 3rd ed.,
ch. 7; Kaplan 2005, USNO Circular 179 ch. 7), geocentric:

1. Space motion. The star moves on a straight line at constant velocity from its
   J1991.25 position (the model of skyfield's ``Star`` and of ESA 1997 vol. 1 sec. 1.5.5).
   Dividing positions by the star's distance keeps everything finite for any parallax:
   ``p(t) = u0 + w (t - t0) - varpi * E(t)`` with ``u0`` the unit vector at the epoch,
   ``w`` the proper-motion vector (rad/day, tangent to the sphere), ``varpi`` the parallax
   (rad; <= 0 treated as 0) and ``E`` the heliocentric position of the Earth (au,
   :func:`skydome.astro.sun.earth_position_au`; the Sun-barycentre offset of <= 0.01 au
   changes a parallax shift by < 0.01"). The last term is the annual parallax (up to
   0.75" for alpha Cen). Radial velocities are not in Hipparcos 2 and are taken as zero,
   as skyfield does with them unset. The perspective acceleration this neglects,
   mu * v_r * varpi * dt^2, stays below 0.4" over 1950-2050 for the nearby fast stars
   of the catalogue (largest 61 Cyg A/B: 0.35" in 2050; alpha Cen 0.21"; Groombridge 1830
   0.27"). Skyfield's light-time (Roemer) term moves a star by < 1e-4" and is skipped.
2. Gravitational deflection of light by the Sun (the NOVAS formula, Kaplan 2005 sec. 7.2,
   for a source at infinity): 4 mas at 90 degrees from the Sun, 1.75" at the limb; bounded
   by the limb value for a star behind the Sun's disk (where skyfield lets it grow).
3. Annual aberration with the Earth's velocity (:func:`skydome.astro.frames.aberrate`).
4. Precession (IAU 2006) and nutation (IAU 1980) to the true equator and equinox of date
   (:func:`skydome.astro.frames.precession_matrix`, :func:`~skydome.astro.frames.nutation_matrix`).
   The Hipparcos frame is the ICRS, which differs from the J2000 mean equator by < 0.02"
   (frame bias, neglected).

Against skyfield (DE421, IAU 2006/2000A) for random stars and times in 2000-2050 the
difference is 0.035" at most and 0.020" RMS (``tests/astro/test_stars.py``); the residual
is the IAU 1980 nutation series and the neglected frame bias. Refraction and diurnal
aberration are not applied here (see :mod:`skydome.astro.frames`). Whole-catalogue apparent
places at one instant take ~6 ms on a 2-core machine (``benchmarks/bench_stars.py``).
"""

from __future__ import annotations

import csv
import difflib
import functools
import io
import json
import re
from dataclasses import dataclass
from importlib import resources
from typing import Any

import numpy as np

from skydome.astro import frames, photometry, sun
from skydome.astro.time import VALID_JD_RANGE
from skydome.errors import ParameterError, SkydomeError

__all__ = [
    "HIPPARCOS_EPOCH_JD",
    "StarCatalog",
    "StarInfo",
    "catalog",
    "find_star",
    "apparent_places",
    "apparent_unit_vectors",
    "enu_unit_vectors",
    "horizontal_coordinates",
    "star_illuminance_lux",
]

#: Hipparcos catalogue epoch J1991.25 as a Julian Date (TT).
HIPPARCOS_EPOCH_JD = 2448349.0625

_CATALOG_FILE = "stars_hip2.npz"
_NAMES_FILE = "stars_names.csv"
_FORMAT_VERSION = 1
_MAS = np.pi / 648_000_000.0  # radians per milliarcsecond
_DAYS_PER_JULIAN_YEAR = 365.25
# 2 G M_sun / c^2 in au: 2 x 1476.625 m (IAU 2015 nominal GM_sun, Resolution B3) / 1 au.
_TWO_GM_SUN_OVER_C2_AU = 2.0 * 1476.6250e-3 / frames.AU_KM
# Guard of the deflection term's denominator 1 + cos(elongation) for a star behind the
# Sun's disk (elongation < 0.267 deg, where the star is not visible anyway).
_MIN_ONE_PLUS_COS = 1.0 - np.cos(np.radians(0.267))


# ---------------------------------------------------------------------------- data


@dataclass(frozen=True)
class StarCatalog:
    """The packaged star catalogue: parallel read-only arrays of length ``n``, brightest first.

    Attributes (units in the names): ``hip`` (int32 Hipparcos number), ``ra_rad``,
    ``dec_rad`` (float64, ICRS at ``epoch_jd_tt`` = J1991.25), ``pmra_mas_yr``
    (mu_alpha* = mu_alpha cos dec), ``pmdec_mas_yr``, ``parallax_mas`` (may be <= 0 for
    distant stars), ``hp_mag`` (Hipparcos Hp), ``vmag`` (Johnson V), ``bv`` (Johnson
    B-V), ``teff_k`` (effective temperature, K); ``meta`` records sources and units.
    """

    hip: np.ndarray
    ra_rad: np.ndarray
    dec_rad: np.ndarray
    pmra_mas_yr: np.ndarray
    pmdec_mas_yr: np.ndarray
    parallax_mas: np.ndarray
    hp_mag: np.ndarray
    vmag: np.ndarray
    bv: np.ndarray
    teff_k: np.ndarray
    epoch_jd_tt: float
    meta: dict[str, Any]

    @property
    def n(self) -> int:
        """Number of stars."""
        return int(self.hip.size)

    def __len__(self) -> int:
        return self.n

    def index_of_hip(self, hip: int) -> int | None:
        """Row of Hipparcos number ``hip``, or None if it is not in the catalogue."""
        return _hip_index().get(int(hip))


@dataclass(frozen=True)
class StarInfo:
    """One catalogue star as returned by :func:`find_star`.

    ``index`` is its row in :func:`catalog` (usable as ``mask`` of
    :func:`apparent_places`); ``name`` is the IAU proper name (None if it has none),
    ``designation`` e.g. ``"alf CMa"`` (None if unknown), ``names`` every accepted name.
    """

    index: int
    hip: int
    name: str | None
    designation: str | None
    names: tuple[str, ...]
    vmag: float
    bv: float
    teff_k: float
    ra_rad: float
    dec_rad: float
    parallax_mas: float


def _read_only(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


@functools.lru_cache(maxsize=1)
def catalog() -> StarCatalog:
    """The star catalogue, read once per process from the package data."""
    try:
        raw = resources.files("skydome.data").joinpath(_CATALOG_FILE).read_bytes()
        with np.load(io.BytesIO(raw), allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
        meta = json.loads(str(data.pop("meta_json")))
    except Exception as exc:  # missing, truncated or foreign file
        raise SkydomeError(
            f"the packaged star catalogue {_CATALOG_FILE} cannot be read ({exc}); "
            "rebuild it with tools/build_star_catalog.py"
        ) from exc
    if meta.get("format_version") != _FORMAT_VERSION:
        raise SkydomeError(
            f"{_CATALOG_FILE} has format {meta.get('format_version')}, expected "
            f"{_FORMAT_VERSION}; rebuild it with tools/build_star_catalog.py"
        )
    f64 = ("ra_rad", "dec_rad", "pmra_mas_yr", "pmdec_mas_yr", "parallax_mas")
    f32 = ("hp_mag", "vmag", "bv", "teff_k")
    arrays = {k: _read_only(data[k].astype(np.float64)) for k in f64}
    arrays.update({k: _read_only(data[k].astype(np.float32)) for k in f32})
    return StarCatalog(
        hip=_read_only(data["hip"].astype(np.int32)),
        epoch_jd_tt=float(meta["epoch_jd_tt"]),
        meta=meta,
        **arrays,
    )


@functools.lru_cache(maxsize=1)
def _hip_index() -> dict[int, int]:
    return {int(h): i for i, h in enumerate(catalog().hip)}


# ---------------------------------------------------------------------------- names

_GREEK = (
    ("alf", "alpha", "α"),
    ("bet", "beta", "β"),
    ("gam", "gamma", "γ"),
    ("del", "delta", "δ"),
    ("eps", "epsilon", "ε"),
    ("zet", "zeta", "ζ"),
    ("eta", "eta", "η"),
    ("tet", "theta", "θϑ"),
    ("iot", "iota", "ι"),
    ("kap", "kappa", "κϰ"),
    ("lam", "lambda", "λ"),
    ("mu", "mu", "μ"),
    ("nu", "nu", "ν"),
    ("ksi", "xi", "ξ"),
    ("omi", "omicron", "ο"),
    ("pi", "pi", "π"),
    ("rho", "rho", "ρ"),
    ("sig", "sigma", "σ"),
    ("tau", "tau", "τ"),
    ("ups", "upsilon", "υ"),
    ("phi", "phi", "φϕ"),
    ("chi", "chi", "χ"),
    ("psi", "psi", "ψ"),
    ("ome", "omega", "ω"),
)
_LETTER_TO_ABBREV: dict[str, str] = {}
for _abbrev, _full, _glyphs in _GREEK:
    _LETTER_TO_ABBREV[_abbrev] = _abbrev
    _LETTER_TO_ABBREV[_full] = _abbrev
    for _g in _glyphs:
        _LETTER_TO_ABBREV[_g] = _abbrev
_LETTER_TO_ABBREV["xi"] = "ksi"  # SIMBAD spells xi "ksi"
_SUPERSCRIPTS = str.maketrans("¹²³⁴⁵⁶⁷⁸⁹⁰", "1234567890")
# "<letter or number><optional index> <constellation>", e.g. "alf CMa", "θ1 Ori", "80 UMa".
_DESIGNATION_RE = re.compile(r"^([^\W\d_]+|\d+)\s*(\d{0,2})\s+([a-z]{3})$")
_HIP_RE = re.compile(r"^(?:hip\s*)?(\d+)$")
_LOOSE_RE = re.compile(r"(?<=[^\d\s])\d+ ")  # the component index of "tet01 eri"


def _normalize(text: str) -> str:
    return " ".join(text.casefold().translate(_SUPERSCRIPTS).split())


def _designation_key(ident: str, con: str) -> str | None:
    """Canonical ``"alf01 cma"``-style key of a designation, or None if not parseable."""
    m = _DESIGNATION_RE.match(_normalize(f"{ident} {con}"))
    if m is None:
        return None
    letter, number, constellation = m.groups()
    if letter.isdigit():  # Flamsteed number, "80 UMa"
        return f"{int(letter)} {constellation}"
    abbrev = _LETTER_TO_ABBREV.get(letter)
    if abbrev is None:  # a variable-star name such as "Y CVn" or "V2500 Oph"
        return f"{letter}{number} {constellation}"
    return f"{abbrev}{int(number):02d} {constellation}" if number else f"{abbrev} {constellation}"


@dataclass(frozen=True)
class _Names:
    by_name: dict[str, int]  # normalized name or designation key -> HIP
    proper: dict[int, str]  # HIP -> IAU proper name
    designation: dict[int, str]  # HIP -> "alf CMa"
    all_names: dict[int, tuple[str, ...]]
    display: dict[str, str]  # normalized proper name -> as written in the source


@functools.lru_cache(maxsize=1)
def _names() -> _Names:
    text = resources.files("skydome.data").joinpath(_NAMES_FILE).read_text(encoding="utf-8")
    rows = list(csv.DictReader(line for line in text.splitlines() if not line.startswith("#")))
    cat = catalog()
    index = _hip_index()
    by_name: dict[str, int] = {}
    proper: dict[int, str] = {}
    designation: dict[int, str] = {}
    all_names: dict[int, list[str]] = {}
    display: dict[str, str] = {}
    # Several components may share a designation (alf Cen A and B): keep the brightest,
    # which is what the bare designation means to an observer. "tet Eri" also finds
    # "tet01 Eri" unless a star is designated exactly so.
    exact: dict[str, int] = {}
    loose: dict[str, int] = {}
    for row in rows:
        hip = int(row["hip"])
        if hip not in index:
            continue
        name = row["name"]
        by_name[_normalize(name)] = hip
        display[_normalize(name)] = name
        all_names.setdefault(hip, []).append(name)
        if row["source"] == "IAU-CSN":
            proper[hip] = name
        ident, con = row["designation"], row["constellation"]
        key = _designation_key(ident, con) if ident and con else None
        if key is None:
            continue
        designation.setdefault(hip, f"{ident} {con}")
        for table, k in ((exact, key), (loose, _LOOSE_RE.sub(" ", key))):
            old = table.get(k)
            if old is None or cat.vmag[index[hip]] < cat.vmag[index[old]]:
                table[k] = hip
    for table in (exact, loose):
        for k, hip in table.items():
            by_name.setdefault(k, hip)
    return _Names(
        by_name=by_name,
        proper=proper,
        designation=designation,
        all_names={h: tuple(v) for h, v in all_names.items()},
        display=display,
    )


def _star_info(i: int) -> StarInfo:
    cat = catalog()
    hip = int(cat.hip[i])
    names = _names()
    return StarInfo(
        index=i,
        hip=hip,
        name=names.proper.get(hip),
        designation=names.designation.get(hip),
        names=names.all_names.get(hip, ()),
        vmag=float(cat.vmag[i]),
        bv=float(cat.bv[i]),
        teff_k=float(cat.teff_k[i]),
        ra_rad=float(cat.ra_rad[i]),
        dec_rad=float(cat.dec_rad[i]),
        parallax_mas=float(cat.parallax_mas[i]),
    )


def find_star(name_or_hip: str | int) -> StarInfo:
    """Look a star up by IAU proper name, designation or Hipparcos number.

    Accepted: proper names in any case (``"sirius"``, ``"Rigil Kentaurus"``, PyEphem
    variants such as ``"Agena"``); Bayer designations with SIMBAD abbreviations, Greek
    names or letters and the IAU constellation abbreviation (``"alf CMa"``,
    ``"alpha CMa"``, ``"α CMa"``, ``"tet1 Ori"``); Flamsteed numbers (``"80 UMa"``);
    Hipparcos numbers as an int, ``"32349"`` or ``"HIP 32349"``. Designations are known
    for the ~330 IAU-named stars.

    Raises :class:`~skydome.errors.ParameterError` naming the input if no star matches or
    the HIP number is not in the catalogue (Hp <= 8).
    """
    cat = catalog()
    if isinstance(name_or_hip, (int, np.integer)) and not isinstance(name_or_hip, bool):
        return _star_by_hip(int(name_or_hip), repr(name_or_hip))
    if not isinstance(name_or_hip, str):
        raise ParameterError(f"star must be a name, designation or HIP number, got {name_or_hip!r}")
    query = _normalize(name_or_hip)
    m = _HIP_RE.match(query)
    if m:
        return _star_by_hip(int(m.group(1)), repr(name_or_hip))
    names = _names()
    hip = names.by_name.get(query)
    if hip is None:
        m = _DESIGNATION_RE.match(query)
        key = _designation_key(m.group(1) + m.group(2), m.group(3)) if m else None
        hip = names.by_name.get(key) if key else None
    if hip is None:
        close = difflib.get_close_matches(query, list(names.display), n=3, cutoff=0.75)
        hint = (
            f"; did you mean {', '.join(repr(names.display[c]) for c in close)}?" if close else ""
        )
        raise ParameterError(
            f"unknown star {name_or_hip!r}: not an IAU proper name, Bayer/Flamsteed "
            f"designation (e.g. 'alf CMa') or HIP number of the catalogue "
            f"({cat.n} stars with Hp <= 8){hint}"
        )
    return _star_info(_hip_index()[hip])


def _star_by_hip(hip: int, shown: str) -> StarInfo:
    i = _hip_index().get(hip)
    if i is None:
        raise ParameterError(
            f"star {shown}: HIP {hip} is not in the catalogue (Hipparcos 2 stars with "
            f"Hp <= 8; {catalog().n} stars)"
        )
    return _star_info(i)


# ---------------------------------------------------------------------------- positions


@dataclass(frozen=True)
class _Kinematics:
    u0: np.ndarray  # (N, 3) unit vectors at the catalogue epoch, ICRS
    w: np.ndarray  # (N, 3) proper-motion vectors, rad/day
    parallax_rad: np.ndarray  # (N,), >= 0


@functools.lru_cache(maxsize=1)
def _kinematics() -> _Kinematics:
    """Epoch unit vectors and proper-motion vectors of the whole catalogue (cached)."""
    cat = catalog()
    ca, sa = np.cos(cat.ra_rad), np.sin(cat.ra_rad)
    cd, sd = np.cos(cat.dec_rad), np.sin(cat.dec_rad)
    u0 = np.stack([cd * ca, cd * sa, sd], axis=-1)
    # Unit vectors towards increasing RA and Dec; mu_alpha* already contains cos(dec).
    e_ra = np.stack([-sa, ca, np.zeros_like(ca)], axis=-1)
    e_dec = np.stack([-sd * ca, -sd * sa, cd], axis=-1)
    scale = _MAS / _DAYS_PER_JULIAN_YEAR
    w = (cat.pmra_mas_yr * scale)[:, None] * e_ra + (cat.pmdec_mas_yr * scale)[:, None] * e_dec
    plx = np.maximum(cat.parallax_mas, 0.0) * _MAS
    return _Kinematics(_read_only(u0), _read_only(w), _read_only(plx))


def _select(mask: Any, n: int) -> np.ndarray | slice:
    """Row selector from ``mask`` (None, boolean (N,) or integer indices)."""
    if mask is None:
        return slice(None)
    m = np.asarray(mask)
    if m.dtype == bool:
        if m.shape != (n,):
            raise ParameterError(f"boolean star mask must have shape ({n},), got {m.shape}")
        return m
    if not np.issubdtype(m.dtype, np.integer):
        raise ParameterError(f"star mask must be boolean or integer indices, got dtype {m.dtype}")
    if m.size and (m.min() < -n or m.max() >= n):
        raise ParameterError(f"star indices must lie in [0, {n - 1}], got {m.min()}..{m.max()}")
    return m.reshape(-1)


def _jd_array(jd_tt: Any) -> np.ndarray:
    jd = np.asarray(getattr(jd_tt, "jd_tt", jd_tt), dtype=float)
    if not np.all(np.isfinite(jd)):
        raise ParameterError(f"jd_tt must be finite Julian Dates, got {jd_tt!r}")
    # The precession/nutation series and the low-precision Earth position are meant for
    # a few millennia around J2000; beyond that the linear space motion is meaningless too.
    lo, hi = VALID_JD_RANGE
    if jd.size and (jd.min() < lo or jd.max() > hi):
        raise ParameterError(
            f"jd_tt = {jd.min()}..{jd.max()} is outside the valid range [{lo}, {hi}] "
            "(years -3000 to 4000)"
        )
    return jd


def apparent_unit_vectors(jd_tt: Any, mask: Any = None) -> np.ndarray:
    """Geocentric apparent directions of catalogue stars, true equator and equinox of date.

    ``jd_tt``: Julian Date(s) in TT (a number, an array of any shape ``S`` or a
    :class:`skydome.astro.time.Time`); ``mask``: None for every star, a boolean array of
    length ``catalog().n`` or integer row indices. Returns unit vectors of shape
    ``S + (n_selected, 3)`` (float64). Temporaries hold ``T x n x 3`` float64 values for
    ``T`` instants (0.9 MB per instant for the whole catalogue): for long time series,
    call per instant or per chunk.
    """
    jd = _jd_array(jd_tt)
    cat = catalog()
    sel = _select(mask, cat.n)
    kin = _kinematics()
    u0, w, plx = kin.u0[sel], kin.w[sel], kin.parallax_rad[sel]

    shape = jd.shape
    t = jd.reshape(-1)  # (T,)
    earth = sun.earth_position_au(t)  # (T, 3), heliocentric, J2000 axes (VSOP87)
    dt = (t - cat.epoch_jd_tt)[:, None, None]  # days
    # 1. space motion and annual parallax, in units of the star's distance
    p = u0[None] + w[None] * dt - plx[None, :, None] * earth[:, None, :]
    p /= np.linalg.norm(p, axis=-1, keepdims=True)
    # 2. light deflection by the Sun (NOVAS formula, Kaplan 2005 sec. 7.2, star at infinity):
    #    p' = p + (2GM/(c^2 |E|)) (e - (p.e) p) / (1 + p.e),  e = E/|E| (Sun -> Earth)
    r_earth = np.linalg.norm(earth, axis=-1)
    e = (earth / r_earth[:, None])[:, None, :]
    pe = np.sum(p * e, axis=-1, keepdims=True)
    k = (_TWO_GM_SUN_OVER_C2_AU / r_earth)[:, None, None]
    p = p + k * (e - pe * p) / np.maximum(1.0 + pe, _MIN_ONE_PLUS_COS)
    # 3. annual aberration (frames.aberrate renormalizes)
    v = frames.earth_velocity_au_per_day(t)[:, None, :]
    p = frames.aberrate(p, v)
    # 4. precession + nutation: J2000 mean -> true equator and equinox of date
    npm = frames.nutation_matrix(t) @ frames.precession_matrix(t)  # (T, 3, 3)
    p = p @ np.swapaxes(npm, -1, -2)
    return p.reshape(shape + p.shape[1:])


def apparent_places(jd_tt: Any, mask: Any = None) -> tuple[np.ndarray, np.ndarray]:
    """Geocentric apparent right ascension and declination of date (rad) of catalogue stars.

    Includes proper motion from J1991.25, annual parallax, solar light deflection, annual
    aberration, precession and nutation (see the module docstring). ``jd_tt`` and
    ``mask`` as for :func:`apparent_unit_vectors`. Returns ``(ra, dec)``, each of shape
    ``S + (n_selected,)``, ra in [0, 2 pi).
    """
    p = apparent_unit_vectors(jd_tt, mask)
    x, y, z = p[..., 0], p[..., 1], p[..., 2]
    ra = np.mod(np.arctan2(y, x), 2.0 * np.pi)
    dec = np.arctan2(z, np.hypot(x, y))
    return ra, dec


def enu_unit_vectors(jd_tt: Any, lst_rad: Any, lat_rad: Any, mask: Any = None) -> np.ndarray:
    """Apparent directions of catalogue stars in the observer's East-North-Up frame.

    ``lst_rad``: local apparent sidereal time (rad, e.g. ``skydome.astro.time.gast`` plus
    east longitude); ``lat_rad``: geodetic latitude (rad); both broadcast against the
    shape ``S`` of ``jd_tt``. Returns unit vectors ``S + (n_selected, 3)`` (x east,
    y north, z up), geometric: no refraction. Diurnal aberration (<= 0.32") and the
    geocentric-topocentric parallax of stars (< 1e-5") are neglected.
    """
    jd = _jd_array(jd_tt)
    lat = np.asarray(lat_rad, dtype=float)
    if not (np.all(np.isfinite(lat)) and np.all(np.abs(lat) <= np.pi / 2)):
        raise ParameterError(f"lat_rad = {lat_rad!r} is outside the valid range [-pi/2, pi/2]")
    lst = np.asarray(lst_rad, dtype=float)
    if not np.all(np.isfinite(lst)):
        raise ParameterError(f"lst_rad must be finite, got {lst_rad!r}")
    shape = np.broadcast_shapes(jd.shape, lst.shape, lat.shape)
    p = apparent_unit_vectors(np.broadcast_to(jd, shape), mask)  # S + (N, 3)
    m = frames.equatorial_to_enu_matrix(np.broadcast_to(lst, shape), np.broadcast_to(lat, shape))
    return p @ np.swapaxes(m, -1, -2)


def horizontal_coordinates(
    jd_tt: Any, lst_rad: Any, lat_rad: Any, mask: Any = None
) -> tuple[np.ndarray, np.ndarray]:
    """Geometric (unrefracted) altitude and azimuth (rad) of catalogue stars.

    Arguments as for :func:`enu_unit_vectors`; azimuth from north through east in
    [0, 2 pi). Returns ``(alt, az)`` of shape ``S + (n_selected,)``. Add refraction with
    :func:`skydome.astro.frames.refraction_saemundsson` where wanted.
    """
    return frames.enu_to_horizontal(enu_unit_vectors(jd_tt, lst_rad, lat_rad, mask))


# ---------------------------------------------------------------------------- photometry


def star_illuminance_lux(vmag: Any) -> np.ndarray:
    """Illuminance (lux) on a surface normal to a star of visual magnitude ``vmag`` (V).

    E = 10^(-0.4 (m + z)) lux with skydome's one zero point
    z = :data:`skydome.astro.photometry.MAGNITUDE_ZERO_POINT` (14.18; m = 0 gives
    2.1e-6 lux). Outside the atmosphere: apply extinction separately.
    """
    return photometry.magnitude_to_lux(vmag)
