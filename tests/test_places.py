"""The built-in gazetteer (skydome.astro.places and data/places.csv).

Positions are checked against two independent tables, PyEphem's city database and the IANA
tz database's zone.tab, and a few against the published values by hand; then name matching,
the error messages, search order and parse_place.
"""

import math
import re
import subprocess
import sys
from datetime import datetime, timezone
from importlib import resources
from pathlib import Path
from zoneinfo import ZoneInfo

import pytest

from skydome.astro import Observer
from skydome.astro import places as P
from skydome.astro.places import Place, find_place, normalise, parse_place, places, search
from skydome.errors import ParameterError, SkydomeError
from tests.tools_module import load_tool

#: Mean Earth radius (IUGG), km. A sphere is enough here: it is within 0.5 % of the
#: ellipsoid's distances, 0.1 km at the 25 km bound.
R_EARTH_KM = 6371.0088


def _km(lat1: float, lon1: float, lat2: float, lon2: float) -> float:
    """Great-circle distance (haversine), km."""
    p1, p2 = math.radians(lat1), math.radians(lat2)
    dp, dl = p2 - p1, math.radians(lon2 - lon1)
    h = math.sin(dp / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    return 2 * R_EARTH_KM * math.asin(math.sqrt(h))


def _find(name: str) -> Place | None:
    try:
        return find_place(name)
    except ParameterError:
        return None


# ---------------------------------------------------------------- the table


def test_table_size_and_kinds():
    rows = places()
    assert len(rows) >= 190
    kinds = {p.kind for p in rows}
    assert kinds == {"city", "observatory"}
    assert sum(p.kind == "observatory" for p in rows) >= 40
    assert places() is rows  # loaded once


@pytest.mark.parametrize("place", places(), ids=lambda p: p.name)
def test_every_row_in_range(place):
    assert -90.0 <= place.latitude_deg <= 90.0
    assert -180.0 <= place.longitude_deg < 180.0
    assert -500.0 <= place.elevation_m <= 6000.0
    assert place.country and place.name == place.name.strip()
    assert all(a and a == a.strip() for a in place.aliases)


def test_csv_header_and_four_decimals():
    text = (resources.files("skydome") / "data" / "places.csv").read_text(encoding="utf-8")
    lines = text.splitlines()
    comments = [line for line in lines if line.startswith("#")]
    assert lines[: len(comments)] == comments  # comments only at the top
    header = " ".join(comments)
    for word in (
        "public",
        "Wikipedia",
        "GeoNames",
        "ephem",
        "zone.tab",
        "tz database",
        "build_place_zones",
        "timezonefinder",
        "Urbanization Prospects",
        "Bortle",
    ):
        assert word in header, word
    assert lines[len(comments)] == (
        "name,aliases,country,kind,latitude_deg,longitude_deg,elevation_m,timezone,population,"
        "bortle"
    )
    for line in lines[len(comments) + 1 :]:
        lat, lon = line.split(",")[-6:-4]
        assert re.fullmatch(r"-?\d+\.\d{4}", lat) and re.fullmatch(r"-?\d+\.\d{4}", lon), line


def test_names_and_aliases_unique_after_normalising():
    """No two rows share a name or alias, compared as find_place compares them (also with the
    spaces taken out), and no alias repeats its own row's name."""
    owner: dict[str, str] = {}
    owner_compact: dict[str, str] = {}
    for place in places():
        keys = [normalise(s) for s in (place.name, *place.aliases)]
        assert all(keys), place
        assert len(set(keys)) == len(keys), f"redundant alias in {place.name}: {keys}"
        for key in keys:
            for table, k in ((owner, key), (owner_compact, key.replace(" ", ""))):
                assert table.setdefault(k, place.name) == place.name, (k, table[k], place.name)


# ---------------------------------------------------------------- independent tables


def test_cities_agree_with_pyephem():
    """PyEphem's city database (ephem.cities._city_data: geocoded positions, MIT licence)
    against ours, for every city both have: within 25 km. The bound holds positions that put
    a city's centre in different places (PyEphem's Luxembourg, 22.6 km from ours, is the
    grand duchy's centre, its Hong Kong the territory's); a wrong sign or degree is off by
    100 km or more. PyEphem's "Brazilia" is Brazil's centre, not Brasilia: it matches no
    name here and so is not compared."""
    cities = pytest.importorskip("ephem.cities")
    matched, worst = 0, (0.0, "")
    for name, (lat, lon, _elev) in cities._city_data.items():
        place = _find(name)
        if place is None or place.kind != "city":
            continue
        matched += 1
        d = _km(float(lat), float(lon), place.latitude_deg, place.longitude_deg)
        worst = max(worst, (d, name))
        assert d < 25.0, f"{name}: PyEphem ({lat}, {lon}) is {d:.1f} km from {place}"
    print(f"\nPyEphem: {matched} of {len(cities._city_data)} cities matched; farthest {worst}")
    assert matched >= 40  # measured: 98, farthest Luxembourg 22.6 km


#: Our country names where the tz database's iso3166.tab spells them differently.
_TZ_COUNTRY = {
    "Bosnia and Herzegovina": "Bosnia & Herzegovina",
    "Czechia": "Czech Republic",
    "Democratic Republic of the Congo": "Congo (Dem. Rep.)",
    "Ivory Coast": "Côte d'Ivoire",
    "Myanmar": "Myanmar (Burma)",
    "North Korea": "Korea (North)",
    "Republic of the Congo": "Congo (Rep.)",
    "South Korea": "Korea (South)",
    "United Kingdom": "Britain (UK)",
}
#: zone.tab's position for Arctic/Longyearbyen is rounded to whole degrees (+7800+01600),
#: 26 km from the town (78.22 N, 15.63 E).
_TZ_ROUNDED = {"Arctic/Longyearbyen"}


def _zone_dir() -> Path | None:
    candidates = [Path("/usr/share/zoneinfo")]
    try:
        candidates.append(Path(str(resources.files("tzdata") / "zoneinfo")))
    except ModuleNotFoundError:
        pass
    for d in candidates:
        if (d / "zone.tab").is_file() and (d / "iso3166.tab").is_file():
            return d
    return None


#: zone.tab's +DDMM[SS] / +DDDMM[SS] to degrees: the zone tool's own reader.
_dms = load_tool("build_place_zones").dms


def test_cities_agree_with_tz_database():
    """The IANA tz database (public domain) gives each zone's principal city to 1' or 1":
    every city of ours named by a zone (Europe/Berlin, America/Sao_Paulo, ...) in the same
    country is within 25 km of it (the bound as for PyEphem: zone.tab's Muscat, Kampala and
    Samarkand are 16-21 km from the centres that GeoNames and Wikipedia give, which agree
    with each other to 5 km there)."""
    zone_dir = _zone_dir()
    if zone_dir is None:
        pytest.skip("no zone.tab (tz database) on this machine")
    country_of = {}
    for line in (zone_dir / "iso3166.tab").read_text(encoding="utf-8").splitlines():
        if line and not line.startswith("#"):
            code, name = line.split("\t")
            country_of[code] = name
    matched, worst = 0, (0.0, "")
    for line in (zone_dir / "zone.tab").read_text(encoding="utf-8").splitlines():
        if not line or line.startswith("#"):
            continue
        code, coords, zone = line.split("\t")[:3]
        m = re.fullmatch(r"([+-]\d+)([+-]\d+)", coords)
        lat, lon = _dms(m.group(1)), _dms(m.group(2))
        place = _find(zone.split("/")[-1].replace("_", " "))
        if place is None or place.kind != "city" or zone in _TZ_ROUNDED:
            continue
        if _TZ_COUNTRY.get(place.country, place.country) != country_of[code]:
            continue  # a namesake (America/Argentina/San_Juan is not San Juan, Puerto Rico)
        matched += 1
        d = _km(lat, lon, place.latitude_deg, place.longitude_deg)
        worst = max(worst, (d, zone))
        assert d < 25.0, f"{zone}: zone.tab ({lat:.4f}, {lon:.4f}) is {d:.1f} km from {place}"
    print(f"\ntz database: {matched} cities matched; farthest {worst}")
    assert matched >= 100  # measured: 151, farthest Asia/Muscat 20.5 km


# ---------------------------------------------------------------- time zones


@pytest.mark.parametrize("place", places(), ids=lambda p: p.name)
def test_every_place_has_a_zone_that_zoneinfo_knows(place):
    """Every place names an IANA zone that zoneinfo loads (the tzdata wheel on Windows), and
    its clock, in January and in July 2025, is within 3 h of the place's mean solar time
    (longitude / 15 h): a zone of another continent or hemisphere is 5-12 h off, while
    China's one zone is 1.9 h ahead of Lhasa's sun, Spain's 2.2 h ahead of La Palma's and
    Greenland's summer time 2.5 h ahead of Nuuk's. The poles (all meridians) are left out."""
    assert place.timezone and place.zone == ZoneInfo(place.timezone)
    if abs(place.latitude_deg) > 85.0:
        return
    for month in (1, 7):
        noon = datetime(2025, month, 1, 12, tzinfo=timezone.utc)
        offset_h = noon.astimezone(place.zone).utcoffset().total_seconds() / 3600.0
        ahead = (offset_h - place.longitude_deg / 15.0 + 12.0) % 24.0 - 12.0
        assert abs(ahead) < 3.0, (place.name, place.timezone, month, ahead)


#: Places whose zone is not one zone.tab lists for their country: Antarctic stations keep
#: their suppliers' time; Hong Kong (HK) and Svalbard (SJ) are countries of their own in the
#: tz database (and ISO 3166).
_ZONE_ELSEWHERE = {
    "Concordia Station": "Australia/Perth",
    "Hong Kong": "Asia/Hong_Kong",
    "Longyearbyen": "Arctic/Longyearbyen",
}


def test_zones_are_those_the_tz_database_gives_the_country():
    """Each place's zone is one that zone.tab lists for the place's country (iso3166.tab's
    name), but for _ZONE_ELSEWHERE."""
    zone_dir = _zone_dir()
    if zone_dir is None:
        pytest.skip("no zone.tab (tz database) on this machine")
    code_of = {}
    for line in (zone_dir / "iso3166.tab").read_text(encoding="utf-8").splitlines():
        if line and not line.startswith("#"):
            code, name = line.split("\t")
            code_of[name.replace("\u2019", "'")] = code  # newer tables' curly apostrophe
    zones: dict[str, set[str]] = {}
    for line in (zone_dir / "zone.tab").read_text(encoding="utf-8").splitlines():
        if line and not line.startswith("#"):
            code, _, zone = line.split("\t")[:3]
            zones.setdefault(code, set()).add(zone)
    for place in places():
        if place.name in _ZONE_ELSEWHERE:
            assert place.timezone == _ZONE_ELSEWHERE[place.name]
            continue
        code = code_of[_TZ_COUNTRY.get(place.country, place.country)]
        assert place.timezone in zones[code], (place.name, place.timezone, sorted(zones[code]))


# The multi-zone countries, by hand (each a fact of the place's law or practice: New
# Mexico keeps Mountain time with DST, Arizona without; west Texas' Jeff Davis County
# Central; Alberta Mountain; the Northern Territory +09:30 without DST; the Canaries WET).
HAND_ZONES = [
    ("Valletta", "Europe/Malta"), ("Paris", "Europe/Paris"), ("Madrid", "Europe/Madrid"),
    ("Roque de los Muchachos", "Atlantic/Canary"), ("Teide", "Atlantic/Canary"),
    ("Calar Alto", "Europe/Madrid"), ("Lisbon", "Europe/Lisbon"),
    ("Mauna Kea", "Pacific/Honolulu"), ("Paranal", "America/Santiago"),
    ("La Silla", "America/Santiago"), ("Punta Arenas", "America/Punta_Arenas"),
    ("Dallas", "America/Chicago"), ("Denver", "America/Denver"), ("Phoenix", "America/Phoenix"),
    ("Kitt Peak", "America/Phoenix"), ("Apache Point", "America/Denver"),
    ("McDonald Observatory", "America/Chicago"), ("Seattle", "America/Los_Angeles"),
    ("Green Bank", "America/New_York"), ("Calgary", "America/Edmonton"),
    ("Mont Mégantic Observatory", "America/Toronto"), ("Alice Springs", "Australia/Darwin"),
    ("Perth", "Australia/Perth"), ("Siding Spring", "Australia/Sydney"),
    ("Lhasa", "Asia/Shanghai"), ("Hong Kong", "Asia/Hong_Kong"),
    ("Novosibirsk", "Asia/Novosibirsk"), ("Special Astrophysical Observatory", "Europe/Moscow"),
    ("Astana", "Asia/Almaty"), ("Manaus", "America/Manaus"),
    ("Ushuaia", "America/Argentina/Ushuaia"), ("Quito", "America/Guayaquil"),
    ("Kinshasa", "Africa/Kinshasa"), ("Ulaanbaatar", "Asia/Ulaanbaatar"),
    ("Jakarta", "Asia/Jakarta"), ("Mexico City", "America/Mexico_City"),
    ("San Pedro Mártir", "America/Tijuana"), ("Longyearbyen", "Arctic/Longyearbyen"),
    ("South Pole", "Antarctica/McMurdo"),
]  # fmt: skip


@pytest.mark.parametrize("name, zone", HAND_ZONES, ids=[h[0] for h in HAND_ZONES])
def test_zones_of_multi_zone_countries(name, zone):
    assert find_place(name).timezone == zone


def test_zone_column_is_what_the_tool_builds(capsys):
    """tools/build_place_zones.py --check recomputes every zone (nearest zone.tab point of
    the country, then its hand-checked list) and finds the table's column the same."""
    if _zone_dir() is None:
        pytest.skip("no zone.tab (tz database) on this machine")
    tool = load_tool("build_place_zones")
    assert tool.main(["--check"]) == 0, capsys.readouterr().out
    assert "0 rows differ" in capsys.readouterr().out


# Published values, by hand; 0.01 deg (1.1 km) allows for where on a site the position is
# taken (a city's centre, one telescope of several).
PUBLISHED = [
    # GeoNames 2562305, Valletta: 35.89968 N, 14.5148 E.
    ("Valletta", 35.8989, 14.5146, None),
    # ESO, Paranal "Site Information" (eso.org/sci/facilities/paranal/astroclimate/site.html):
    # UT3 at 24 deg 37' 36.64" S, 70 deg 24' 16.32" W; altitude 2635.43 m.
    ("Paranal", -24.6272, -70.4042, (2635.43, 1.0)),
    # Wikipedia, "Mauna Kea Observatories": 19 deg 49' 28" N, 155 deg 28' 24" W, 4205 m (the
    # summit; the telescopes stand at 4100-4215 m).
    ("Mauna Kea", 19.8244, -155.4733, (4205.0, 10.0)),
    # The Airy transit circle in WGS84 (Ordnance Survey, as astropy-data's sites.json quotes
    # it): 51.477811 N, 0.001475 W; the brief's 51.4769 N, 0.0005 W is the same to 0.001 deg.
    ("Greenwich", 51.4778, -0.0015, None),
    ("Royal Observatory Greenwich", 51.4769, -0.0005, None),
]


@pytest.mark.parametrize("name, lat, lon, elevation", PUBLISHED, ids=[p[0] for p in PUBLISHED])
def test_published_positions(name, lat, lon, elevation):
    place = find_place(name)
    assert place.latitude_deg == pytest.approx(lat, abs=0.01)
    assert place.longitude_deg == pytest.approx(lon, abs=0.01)
    if elevation is not None:
        assert place.elevation_m == pytest.approx(elevation[0], abs=elevation[1])


def test_brief_observatories_present():
    """The observatories the gazetteer promises, each by a name people use."""
    for name in [
        "Mauna Kea", "Subaru", "Paranal", "La Silla", "Cerro Tololo", "Cerro Pachon",
        "Roque de los Muchachos", "La Palma", "Teide", "Kitt Peak", "Mount Wilson", "Palomar",
        "Lick", "McDonald", "Apache Point", "Siding Spring", "Mount Stromlo", "SAAO",
        "Sutherland", "Greenwich", "Paris Observatory", "Pic du Midi", "Calar Alto",
        "Jodrell Bank", "Arecibo", "Green Bank", "ALMA", "Chajnantor", "Hanle", "Xinglong",
        "Mount Graham", "Lowell Observatory", "Anderson Mesa", "Haute-Provence", "Effelsberg",
        "Parkes", "Devasthal", "Maidanak", "Sierra Nevada", "Las Campanas", "Big Bear",
    ]:  # fmt: skip
        assert find_place(name).kind == "observatory", name


# ---------------------------------------------------------------- matching


@pytest.mark.parametrize(
    "given, expected",
    [
        ("valletta", "Valletta"),
        ("  VALLETTA ", "Valletta"),
        ("Valletta, Malta", "Valletta"),
        ("São Paulo", "São Paulo"),
        ("Sao Paulo", "São Paulo"),
        ("sao-paulo", "São Paulo"),
        ("SaoPaulo", "São Paulo"),
        ("roque de los muchachos", "Roque de los Muchachos Observatory"),
        ("ESO Paranal", "Paranal Observatory"),
        ("Subaru", "Mauna Kea Observatories"),
        ("Mt. Wilson", "Mount Wilson Observatory"),
        ("St. Petersburg", "Saint Petersburg"),
        ("Kiev", "Kyiv"),
        ("Zürich", "Zurich"),
        ("Kobenhavn", "Copenhagen"),
        ("Xian", "Xi'an"),
        ("東京", "Tokyo"),
        ("Cordoba, Argentina", "Córdoba"),
        ("Reykjavik", "Reykjavík"),
    ],
)
def test_find_place_ignores_case_accents_punctuation(given, expected):
    assert find_place(given).name == expected


def test_unknown_place_suggests_close_names():
    with pytest.raises(ParameterError) as err:
        find_place("Atlantis")
    msg = str(err.value)
    assert "\n" not in msg
    m = re.fullmatch(
        r"unknown place 'Atlantis'; did you mean (.+)\? \(skydome places lists them\)", msg
    )
    assert m, msg
    names = re.split(r", | or ", m.group(1))
    assert 1 <= len(names) <= 3 and names[0] == "Atlanta"
    assert all(find_place(n) for n in names)  # each suggestion is a name that works

    with pytest.raises(ParameterError) as err:
        find_place("Vallleta")
    assert "did you mean Valletta?" in str(err.value)


def test_unknown_place_without_suggestions():
    with pytest.raises(ParameterError) as err:
        find_place("Qwxyzzz")
    assert str(err.value) == "unknown place 'Qwxyzzz' (skydome places lists them)"
    with pytest.raises(ParameterError) as err:
        find_place("Atl\nantis-qqq")  # a newline in the name stays escaped: one line
    assert "\n" not in str(err.value)
    with pytest.raises(ParameterError):
        find_place("Valletta, Spain")  # the country must be the place's


@pytest.mark.parametrize("bad", ["", "   ", "!!!", None, 42])
def test_empty_or_non_string_name_refused(bad):
    with pytest.raises(ParameterError) as err:
        find_place(bad)
    assert "\n" not in str(err.value)


def test_ambiguous_name_is_not_silently_picked(monkeypatch):
    twins = (
        Place("Springfield", "United States", "city", 39.80, -89.65, 180.0),
        Place("Springfield", "Australia", "city", -27.65, 152.92, 40.0),
    )
    monkeypatch.setattr(P, "_gazetteer", lambda: P._build(twins))
    with pytest.raises(ParameterError) as err:
        find_place("springfield")
    msg = str(err.value)
    assert "ambiguous" in msg and "Australia" in msg and "United States" in msg
    assert find_place("Springfield, Australia") is twins[1]


def test_bad_table_rows_are_reported_with_their_line():
    head = (
        "# comment\nname,aliases,country,kind,latitude_deg,longitude_deg,elevation_m,timezone,"
        "population,bortle\n"
    )
    with pytest.raises(SkydomeError, match="line 3"):
        P._parse_csv(head + "X,,Y,city,95.0000,0.0000,0,UTC,1000,\n")
    with pytest.raises(SkydomeError, match="line 4: expected 10 fields"):
        P._parse_csv(head + "X,,Y,city,1.0000,0.0000,0,UTC,1000,\nZ,,Y,city,1.0000\n")
    with pytest.raises(SkydomeError, match="line 3"):
        P._parse_csv(head + "X,,Y,observatory,1.0000,0.0000,0,UTC,,12\n")  # no Bortle 12
    with pytest.raises(SkydomeError, match="columns"):
        P._parse_csv("name,country\nX,Y\n")


# ---------------------------------------------------------------- search


def test_search_empty_query_and_limit():
    assert search("") == [] and search("  ,. ") == []
    assert len(search("a", limit=5)) == 5
    for bad in (0, -1, 2.5, True):
        with pytest.raises(ParameterError):
            search("par", limit=bad)


def test_search_order_prefix_then_substring_then_fuzzy():
    names = [p.name for p in search("par", limit=50)]
    # names that start with the query, alphabetically, come first ...
    assert names[:4] == ["Paranal Observatory", "Paris", "Paris Observatory", "Parkes Observatory"]
    # ... then those with it inside (Alice Springs' alias Mparntwe), then the country
    # Paraguay (Asuncion), then near misses.
    assert names.index("Alice Springs") < names.index("Asunción")
    assert "Palomar Observatory" in names[names.index("Asunción") :]

    # a word of the name that starts with the query
    assert search("kea")[0].name == "Mauna Kea Observatories"
    # names before aliases in the same tier: San Francisco ... before Bogota (Santa Fe de Bogota)
    san = [p.name for p in search("san", limit=20)]
    assert san[:6] == [
        "San Francisco", "San José", "San Juan", "San Pedro de Atacama",
        "San Pedro Mártir Observatory", "San Salvador",
    ]  # fmt: skip
    assert san.index("Bogotá") > 6
    # an exact alias beats every prefix
    assert search("LA")[0].name == "Los Angeles"


def test_search_by_country_and_typos():
    chile = {p.name for p in search("chile", limit=100)}
    assert chile >= {p.name for p in places() if p.country == "Chile"}
    assert search("valeta")[0].name == "Valletta"
    assert search("tokio")[0].name == "Tokyo"
    assert search("muchachs")[0].name == "Roque de los Muchachos Observatory"
    assert all(isinstance(p, Place) for p in search("obs"))


# ---------------------------------------------------------------- parse_place


def test_parse_place_names_places_and_tuples():
    valletta = find_place("Valletta")
    assert parse_place(valletta) is valletta
    assert parse_place("valletta") is valletta
    p = parse_place((35.8989, 14.5146))
    assert (p.name, p.kind, p.country) == ("35.8989, 14.5146", "coordinates", "")
    assert (p.latitude_deg, p.longitude_deg, p.elevation_m) == (35.8989, 14.5146, 0.0)
    q = parse_place([-24.6272, 289.5958, 2635])  # east longitude past 180 -> west
    assert q.longitude_deg == pytest.approx(-70.4042, abs=1e-9) and q.elevation_m == 2635
    assert q.name == "-24.6272, -70.4042"
    r = parse_place(" -24.6272 , -70.4042, 2635 ")  # the same as text
    assert (r.latitude_deg, r.longitude_deg, r.elevation_m) == (-24.6272, -70.4042, 2635.0)
    assert parse_place((90, -180)).longitude_deg == -180.0


@pytest.mark.parametrize(
    "bad, words",
    [
        ((91, 0), ["latitude_deg", "91", "[-90.0, 90.0]"]),
        ((-90.5, 0), ["latitude_deg", "-90.5"]),
        ((0, 360), ["longitude_deg", "360", "[-180, 360)"]),
        ((0, -180.01), ["longitude_deg", "-180.01", "[-180, 360)"]),
        ((0, 0, -2000), ["elevation_m", "-2000"]),
        ((float("nan"), 0), ["latitude_deg", "nan"]),
        (("north", 0), ["latitude_deg", "north"]),
        ((True, 0), ["latitude_deg", "True"]),
        ((1.0,), ["latitude_deg, longitude_deg"]),
        ((1, 2, 3, 4), ["latitude_deg, longitude_deg"]),
        (None, ["None"]),
        (12.5, ["12.5"]),
    ],
)
def test_parse_place_refuses_bad_tuples(bad, words):
    with pytest.raises(ParameterError) as err:
        parse_place(bad)
    msg = str(err.value)
    assert "\n" not in msg
    for w in words:
        assert w in msg, msg


def test_observer_from_place():
    paranal = find_place("Paranal")
    obs = paranal.observer(pressure_hPa=743.0, temperature_C=12.0)
    assert isinstance(obs, Observer)
    assert float(obs.latitude) == paranal.latitude_deg
    assert float(obs.longitude) == paranal.longitude_deg
    assert float(obs.elevation_m) == paranal.elevation_m
    assert float(obs.pressure_hPa) == 743.0
    with pytest.raises(ParameterError, match="latitude"):
        paranal.observer(latitude=0.0)
    assert find_place("Valletta").label == "Valletta, Malta"


def test_module_does_not_import_numpy():
    """The CLI imports the gazetteer to resolve --place; the module itself needs only the
    standard library (skydome.astro's __init__, which loads NumPy, is bypassed here)."""
    code = (
        "import importlib.util, sys\n"
        f"spec = importlib.util.spec_from_file_location('places_alone', {P.__file__!r})\n"
        "m = importlib.util.module_from_spec(spec); sys.modules['places_alone'] = m\n"
        "spec.loader.exec_module(m)\n"
        "assert m.find_place('Valletta').country == 'Malta'\n"
        "assert m.search('paran')[0].name == 'Paranal Observatory'\n"
        "assert 'numpy' not in sys.modules, 'numpy imported'\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
