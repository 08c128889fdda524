"""A built-in gazetteer: about 330 major cities and astronomical observatories.

The table ships as ``skydome/data/places.csv`` (its header says where the positions come
from). Names are matched ignoring case, accents, punctuation and spacing, so ``"sao paulo"``,
``"São Paulo"`` and ``"SAO-PAULO"`` are the same place, and ``"Mt. Wilson"`` is ``"Mount
Wilson"``:

>>> from skydome.astro.places import find_place, parse_place, search
>>> find_place("valletta").latitude_deg
35.8989
>>> [p.name for p in search("paran")][:1]
['Paranal Observatory']
>>> parse_place((35.8989, 14.5146)).name
'35.8989, 14.5146'

This module needs only the standard library; :meth:`Place.observer` imports the astronomy
layer when it is called.
"""

from __future__ import annotations

import csv
import difflib
import io
import math
import re
import unicodedata
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cache
from importlib import resources
from typing import TYPE_CHECKING, Any, NamedTuple
from zoneinfo import ZoneInfo, ZoneInfoNotFoundError

from skydome.errors import ParameterError, SkydomeError, check_range

if TYPE_CHECKING:  # pragma: no cover - typing only
    from skydome.astro.observer import Observer

__all__ = [
    "KINDS",
    "PLACES_FILE",
    "Place",
    "find_place",
    "normalise",
    "parse_place",
    "places",
    "search",
    "time_zone",
]

#: The packaged table, in ``skydome/data``.
PLACES_FILE = "places.csv"
#: What a place is: a row of the table is a city or an observatory; a position given as
#: numbers (:func:`parse_place` of a tuple) is "coordinates".
KINDS = ("city", "observatory", "coordinates")
_COLUMNS = [
    "name", "aliases", "country", "kind", "latitude_deg", "longitude_deg", "elevation_m",
    "timezone", "population", "bortle",
]  # fmt: skip
#: The elevation range accepted, the same as :class:`skydome.astro.Observer`'s (m).
_ELEVATION_RANGE_M = (-1000.0, 100000.0)
#: difflib's similarity ratio below which a name is not offered as a suggestion.
_CLOSE = 0.6
#: The same for one word of a longer name, in search().
_CLOSE_WORD = 0.75
_HINT = "(skydome places lists them)"


@dataclass(frozen=True)
class Place:
    """A named position on the Earth.

    Attributes:
        name: the name shown, e.g. ``"Valletta"`` or ``"Paranal Observatory"``.
        country: the country (English short name); empty for a position given as numbers.
        kind: ``"city"``, ``"observatory"`` or ``"coordinates"`` (see :data:`KINDS`).
        latitude_deg: geodetic latitude (WGS84), degrees, north positive, in [-90, 90].
        longitude_deg: longitude, degrees, east positive, in [-180, 180).
        elevation_m: height above sea level, metres.
        aliases: other names it is found by (native spellings, telescopes on the site, ...).
        timezone: the IANA time zone its clocks keep (``"Europe/Malta"``); empty for a
            position given as numbers (its times are UTC unless they carry an offset).
        population: a city's urban-area population (people), or None; it sets the city's
            estimated light pollution (``skydome.night.light_pollution.place_light_pollution``).
        bortle: an observatory's Bortle class (1-9), or None.
    """

    name: str
    country: str
    kind: str
    latitude_deg: float
    longitude_deg: float
    elevation_m: float = 0.0
    aliases: tuple[str, ...] = field(default=())
    timezone: str = ""
    population: float | None = None
    bortle: int | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise ParameterError(f"Place name must be a non-empty string, got {self.name!r}")
        if not isinstance(self.country, str):
            raise ParameterError(f"Place country must be a string, got {self.country!r}")
        if self.kind not in KINDS:
            raise ParameterError(
                f"Place kind {self.kind!r}: unknown kind; choose one of {', '.join(KINDS)}"
            )
        lat, lon, elev = _check_position(self.latitude_deg, self.longitude_deg, self.elevation_m)
        object.__setattr__(self, "latitude_deg", lat)
        object.__setattr__(self, "longitude_deg", lon)
        object.__setattr__(self, "elevation_m", elev)
        if isinstance(self.aliases, str) or not all(isinstance(a, str) for a in self.aliases):
            raise ParameterError(
                f"Place aliases must be a sequence of strings, got {self.aliases!r}"
            )
        object.__setattr__(self, "aliases", tuple(self.aliases))
        if not isinstance(self.timezone, str):
            raise ParameterError(f"Place timezone must be a string, got {self.timezone!r}")
        if self.population is not None:
            pop = _number("population", self.population)
            object.__setattr__(self, "population", check_range("population", pop, 0.0, 1e9))
        if self.bortle is not None and (
            isinstance(self.bortle, bool) or self.bortle not in range(1, 10)
        ):
            raise ParameterError(f"Place bortle = {self.bortle!r} must be a class from 1 to 9")

    @property
    def zone(self) -> ZoneInfo | None:
        """The place's time zone (``zoneinfo.ZoneInfo``), or None when it has none.

        Raises:
            ParameterError: for a zone name the system's and ``tzdata``'s tables lack.
        """
        if not self.timezone:
            return None
        return time_zone(self.timezone)

    @property
    def label(self) -> str:
        """``"name, country"`` (just the name when there is no country), e.g. for a title."""
        return f"{self.name}, {self.country}" if self.country else self.name

    def observer(self, **weather: Any) -> Observer:
        """A :class:`skydome.astro.Observer` standing here.

        Args:
            **weather: passed on to the Observer: ``pressure_hPa`` (hPa) and
                ``temperature_C`` (deg C), used for refraction.
        """
        taken = sorted(set(weather) & {"latitude", "longitude", "elevation_m"})
        if taken:
            raise ParameterError(
                f"Place.observer() takes the weather only (pressure_hPa, temperature_C); "
                f"{', '.join(taken)} comes from the place"
            )
        from skydome.astro.observer import Observer  # the NumPy layer, only when asked for

        return Observer(
            latitude=self.latitude_deg,
            longitude=self.longitude_deg,
            elevation_m=self.elevation_m,
            **weather,
        )


@cache
def time_zone(name: str) -> ZoneInfo:
    """The IANA time zone ``name`` (``"Europe/Paris"``) as a ``zoneinfo.ZoneInfo``.

    Raises:
        ParameterError: for a name that neither the system's tables nor ``tzdata`` know.
    """
    if not isinstance(name, str) or not name:
        raise ParameterError(
            f"a time zone must be an IANA name such as 'Europe/Paris', got {name!r}"
        )
    try:
        return ZoneInfo(name)
    except (ZoneInfoNotFoundError, ValueError):
        raise ParameterError(
            f"time zone {name!r} is unknown to zoneinfo (install the tzdata package)"
        ) from None


# ---------------------------------------------------------------- names


#: Letters that Unicode does not decompose into a base letter and an accent.
_LETTERS = str.maketrans(
    {"ø": "o", "æ": "ae", "œ": "oe", "ł": "l", "đ": "d", "ð": "d", "þ": "th", "ı": "i", "ħ": "h"}
)
#: Apostrophes and the like join their neighbours ("Xi'an" = "Xian", "N'Djamena" = "Ndjamena").
_APOSTROPHES = re.compile(r"['’ʼʻ`´]")
_SEPARATORS = re.compile(r"[\W_]+")
#: Abbreviations spelled out, one word at a time: "Mt. Wilson" = "Mount Wilson".
_WORDS = {"mt": "mount", "st": "saint"}


def normalise(text: str) -> str:
    """The form names are compared in: no accents, case folded, punctuation as single spaces,
    ``mt``/``st`` spelled out (``"São-Paulo"`` -> ``"sao paulo"``, ``"Mt. Wilson"`` ->
    ``"mount wilson"``). Scripts other than Latin are kept (``"東京"`` stays)."""
    decomposed = unicodedata.normalize("NFKD", text)
    plain = "".join(c for c in decomposed if not unicodedata.combining(c)).casefold()
    plain = _APOSTROPHES.sub("", plain.translate(_LETTERS))
    return " ".join(_WORDS.get(w, w) for w in _SEPARATORS.sub(" ", plain).split())


def _keys(place: Place) -> list[tuple[str, str]]:
    """(normalised key, the spelling it came from) for the name and each alias."""
    return [(normalise(s), s) for s in (place.name, *place.aliases)]


class _Gazetteer(NamedTuple):
    places: tuple[Place, ...]
    #: normalised name or alias -> the places that carry it (one, unless the table is wrong)
    index: dict[str, tuple[Place, ...]]
    #: the same with spaces removed ("saopaulo"), a second chance for run-together input
    compact: dict[str, tuple[Place, ...]]
    #: normalised key -> how it is spelled in the table, for suggestions
    spelling: dict[str, str]


def _parse_csv(text: str) -> tuple[Place, ...]:
    lines = text.splitlines()
    first = 0
    while first < len(lines) and lines[first].startswith("#"):
        first += 1
    reader = csv.DictReader(io.StringIO("\n".join(lines[first:])))
    if reader.fieldnames != _COLUMNS:
        raise SkydomeError(f"{PLACES_FILE}: columns {reader.fieldnames} are not {_COLUMNS}")
    rows = []
    for number, row in enumerate(reader, start=first + 2):
        if None in row or None in row.values():
            raise SkydomeError(f"{PLACES_FILE} line {number}: expected {len(_COLUMNS)} fields")
        try:
            rows.append(
                Place(
                    name=row["name"],
                    country=row["country"],
                    kind=row["kind"],
                    latitude_deg=float(row["latitude_deg"]),
                    longitude_deg=float(row["longitude_deg"]),
                    elevation_m=float(row["elevation_m"]),
                    aliases=tuple(a.strip() for a in row["aliases"].split(";") if a.strip()),
                    timezone=row["timezone"],
                    population=float(row["population"]) if row["population"] else None,
                    bortle=int(row["bortle"]) if row["bortle"] else None,
                )
            )
        except (ValueError, TypeError, AttributeError) as exc:
            raise SkydomeError(f"{PLACES_FILE} line {number}: {exc}") from None
    return tuple(rows)


def _build(rows: tuple[Place, ...]) -> _Gazetteer:
    """The look-up tables for ``rows``."""
    index: dict[str, list[Place]] = {}
    compact: dict[str, list[Place]] = {}
    spelling: dict[str, str] = {}
    for place in rows:
        for key, original in _keys(place):
            for table, k in ((index, key), (compact, key.replace(" ", ""))):
                found = table.setdefault(k, [])
                if not any(p is place for p in found):
                    found.append(place)
            spelling.setdefault(key, original)

    def freeze(table: dict[str, list[Place]]) -> dict[str, tuple[Place, ...]]:
        return {k: tuple(v) for k, v in table.items()}

    return _Gazetteer(rows, freeze(index), freeze(compact), spelling)


@cache
def _gazetteer() -> _Gazetteer:
    text = (resources.files("skydome") / "data" / PLACES_FILE).read_text(encoding="utf-8")
    return _build(_parse_csv(text))


def places() -> tuple[Place, ...]:
    """Every place in the built-in table, in table order (cities, then observatories).

    Read once from the packaged ``places.csv`` and kept.
    """
    return _gazetteer().places


def _or_list(words: Sequence[str]) -> str:
    """``"A"``, ``"A or B"``, ``"A, B or C"``."""
    return words[0] if len(words) == 1 else f"{', '.join(words[:-1])} or {words[-1]}"


def _lookup(key: str) -> tuple[Place, ...]:
    g = _gazetteer()
    return g.index.get(key) or g.compact.get(key.replace(" ", ""), ())


def _suggestions(key: str, n: int = 3) -> list[str]:
    """Up to n spellings from the table close to ``key`` (difflib), one per place."""
    g = _gazetteer()
    out: list[str] = []
    seen: list[Place] = []
    for close in difflib.get_close_matches(key, list(g.spelling), n=4 * n, cutoff=_CLOSE):
        place = g.index[close][0]
        if any(p is place for p in seen):
            continue
        seen.append(place)
        out.append(g.spelling[close])
        if len(out) == n:
            break
    return out


def find_place(name: str) -> Place:
    """The place called ``name`` (its name or an alias), ignoring case, accents, punctuation
    and spacing; ``"Name, Country"`` is accepted too (``"Córdoba, Argentina"``).

    Raises:
        ParameterError: for an empty name, or one that is not in the table (with up to three
            close names as suggestions), or one that several places share.
    """
    if not isinstance(name, str):
        raise ParameterError(f"a place name must be a string, got {name!r}")
    key = normalise(name)
    if not key:
        raise ParameterError(f"place name {name!r} is empty; give one such as 'Valletta' {_HINT}")
    hits = _lookup(key)
    if not hits and "," in name:
        head, tail = name.rsplit(",", 1)
        country = normalise(tail)
        hits = tuple(p for p in _lookup(normalise(head)) if normalise(p.country) == country)
    if len(hits) == 1:
        return hits[0]
    if hits:
        raise ParameterError(
            f"place {name!r} is ambiguous: {_or_list([p.label for p in hits])}; "
            f"give it as 'name, country'"
        )
    close = _suggestions(key)
    if close:
        raise ParameterError(f"unknown place {name!r}; did you mean {_or_list(close)}? {_HINT}")
    raise ParameterError(f"unknown place {name!r} {_HINT}")


def search(query: str, limit: int = 10) -> list[Place]:
    """Places for an interactive search box, best first, at most ``limit``.

    Order: an exact name or alias; a name or alias that starts with the query; one with a
    word that starts with it; one that contains it; a country that matches it (all the
    places of ``"chile"``); then names within difflib's similarity ratio 0.6 of it (typos),
    closest first. Ties go alphabetically by name. An empty query gives ``[]``.
    """
    if not isinstance(query, str):
        raise ParameterError(f"a search query must be a string, got {query!r}")
    if isinstance(limit, bool) or not isinstance(limit, int) or limit < 1:
        raise ParameterError(f"limit = {limit!r} must be a whole number of at least 1")
    q = normalise(query)
    if not q:
        return []
    qc = q.replace(" ", "")
    ranked = []
    for place in _gazetteer().places:
        keys = [k for k, _ in _keys(place)]
        best = (6, 1, 0.0)  # (tier, 0 for the name / 1 for an alias, -similarity)
        for alias, k in enumerate(keys):
            if k == q:
                tier = 0
            elif k.startswith(q):
                tier = 1
            elif f" {q}" in f" {k}":
                tier = 2
            elif q in k or qc in k.replace(" ", ""):
                tier = 3
            else:
                continue
            best = min(best, (tier, min(alias, 1), 0.0))
        if best[0] == 6:
            country = normalise(place.country)
            if country and (q in country or qc in country.replace(" ", "")):
                best = (4, 0, 0.0)
        if best[0] == 6 and len(q) >= 3:
            best = min(best, _fuzzy(q, keys))
        if best[0] < 6:
            ranked.append((*best, place.name.casefold(), place))
    ranked.sort(key=lambda r: r[:4])
    return [r[-1] for r in ranked[:limit]]


def _fuzzy(q: str, keys: list[str]) -> tuple[int, int, float]:
    """(5, alias flag, -similarity) of the closest key, or (6, 1, 0) when none is close.

    A whole key counts from difflib's ratio 0.6 (its usual cutoff); one word of a key
    ("muchachos" of "roque de los muchachos") from 0.75 and only words of 4 letters or more,
    so that short words ("de", "el") do not match every query."""
    matcher = difflib.SequenceMatcher(b=q)
    best = (6, 1, 0.0)
    for alias, k in enumerate(keys):
        words = [w for w in k.split(" ") if len(w) >= 4] if " " in k else []
        for candidate, cutoff in ((k, _CLOSE), *((w, _CLOSE_WORD) for w in words)):
            matcher.set_seq1(candidate)
            ratio = matcher.ratio()
            if ratio >= cutoff:
                best = min(best, (5, min(alias, 1), -ratio))
    return best


# ---------------------------------------------------------------- numbers


def _number(name: str, value: Any) -> float:
    """``float(value)``, refusing booleans, NaN and what is not a number."""
    try:
        if isinstance(value, bool):
            raise TypeError
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(f"{name} must be a number, got {value!r}") from None
    if math.isnan(v):
        raise ParameterError(f"{name} must be a number, got {value!r}")
    return v


def _check_position(lat: Any, lon: Any, elev: Any) -> tuple[float, float, float]:
    """Validated (latitude_deg, longitude_deg in [-180, 180), elevation_m)."""
    lat = check_range("latitude_deg", _number("latitude_deg", lat), -90.0, 90.0, "deg")
    lon_v = _number("longitude_deg", lon)
    if not (-180.0 <= lon_v < 360.0):
        raise ParameterError(
            f"longitude_deg = {lon} deg is outside the valid range [-180, 360) deg"
        )
    if lon_v >= 180.0:
        lon_v = round(lon_v - 360.0, 10)  # 289.6 -> -70.4, not -70.39999999999998
    lo, hi = _ELEVATION_RANGE_M
    elev = check_range("elevation_m", _number("elevation_m", elev), lo, hi, "m")
    return lat, lon_v, elev


_COORDINATES = re.compile(
    r"\s*[-+]?[\d.]+(?:[eE][-+]?\d+)?\s*(?:,\s*[-+]?[\d.]+(?:[eE][-+]?\d+)?\s*){1,2}"
)


def parse_place(value: Place | str | Sequence[float]) -> Place:
    """A :class:`Place` from what a user may give.

    Args:
        value: a Place (returned as it is); a name or alias (see :func:`find_place`); a
            ``(latitude_deg, longitude_deg)`` or ``(latitude_deg, longitude_deg,
            elevation_m)`` tuple, or the same as text (``"35.8989, 14.5146"``). Latitude must
            lie in [-90, 90] deg, longitude in [-180, 360) deg (kept as [-180, 180)),
            elevation in [-1000, 100000] m (default 0).

    Returns:
        The place; one given by numbers is named by its position, ``"35.8989, 14.5146"``,
        with kind ``"coordinates"`` and no country.
    """
    if isinstance(value, Place):
        return value
    if isinstance(value, str):
        if not _COORDINATES.fullmatch(value):
            return find_place(value)
        value = tuple(part.strip() for part in value.split(","))
    if hasattr(value, "tolist") and not isinstance(value, Sequence):
        value = value.tolist()  # a NumPy array of 2 or 3 numbers
    if not isinstance(value, Sequence) or len(value) not in (2, 3):
        raise ParameterError(
            f"place {value!r} must be a name, a Place, or (latitude_deg, longitude_deg"
            f"[, elevation_m])"
        )
    lat, lon, elev = _check_position(*value, *([0.0] if len(value) == 2 else []))
    return Place(
        name=f"{lat:.4f}, {lon:.4f}",
        country="",
        kind="coordinates",
        latitude_deg=lat,
        longitude_deg=lon,
        elevation_m=elev,
    )
