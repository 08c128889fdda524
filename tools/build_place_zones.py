"""Fill the ``timezone`` column of ``src/skydome/data/places.csv`` from the IANA tz database.

The tz database (public domain) lists each zone of a country with a representative point
(``zone.tab``: country code, position, zone name) and names the countries
(``iso3166.tab``). For each place this tool takes the zones of its country and picks the one
whose point is nearest (great circle); a country with one zone needs no choice. The choice
is then checked by hand for the countries with several zones (``CHECKED`` below: where the
nearest representative point is the wrong zone, e.g. a city near a zone boundary, or the
zone's point is a far-away city) and for places outside any country's list (Antarctica).

With ``timezonefinder`` importable (``pip install --target DIR timezonefinder`` and
``PYTHONPATH=DIR``; it is never a dependency of skydome), every place is also looked up in
its boundary polygons (OpenStreetMap-derived data, ODbL) and the two choices compared: a zone
that keeps the same UTC offsets as the other's through 2020-2026 (Europe/Oslo and
Europe/Berlin) agrees; every other difference is printed, to be settled in ``CHECKED``.

Usage::

    python tools/build_place_zones.py            # rewrite the timezone column
    python tools/build_place_zones.py --check    # only report (exit 1 if the file differs)
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import re
import sys
from datetime import datetime, timedelta, timezone
from importlib import resources
from pathlib import Path
from zoneinfo import ZoneInfo

ROOT = Path(__file__).resolve().parents[1]
PLACES = ROOT / "src" / "skydome" / "data" / "places.csv"

#: Our country names where iso3166.tab spells them otherwise.
COUNTRY_ALIASES = {
    "Bosnia and Herzegovina": "Bosnia & Herzegovina",
    "Czechia": "Czech Republic",
    "Democratic Republic of the Congo": "Congo (Dem. Rep.)",
    "Ivory Coast": "Côte d\u2019Ivoire",
    "Myanmar": "Myanmar (Burma)",
    "North Korea": "Korea (North)",
    "Republic of the Congo": "Congo (Rep.)",
    "South Korea": "Korea (South)",
    "United Kingdom": "Britain (UK)",
    "Vietnam": "Vietnam",
}

#: Zones settled by hand (place name -> zone), with the reason. Every multi-zone country's
#: places were read through; only those where the nearest representative point is not the
#: zone the place keeps are listed.
CHECKED = {
    # Antarctica: the stations keep the time of those that supply them.
    "Amundsen-Scott South Pole Station": "Antarctica/McMurdo",  # NZ time (tzdb's South_Pole link)
    "Concordia Station": "Australia/Perth",  # UTC+8, as timezonefinder's polygon for the sector
    # The nearest representative point is another zone's (the choice keeps the same clock
    # unless said; the tz database names the zone a place belongs to):
    "Alice Springs": "Australia/Darwin",  # Northern Territory (nearest: Eucla, +08:45: wrong)
    "Astana": "Asia/Almaty",  # tzdb: "most of Kazakhstan" (nearest: Qostanay)
    "Atlanta": "America/New_York",  # (nearest: Kentucky/Monticello)
    "Calgary": "America/Edmonton",  # Alberta (nearest: Creston, B.C., no DST: wrong)
    "Dallas": "America/Chicago",  # (nearest: Indiana/Vincennes)
    "Houston": "America/Chicago",  # (nearest: Indiana/Tell_City)
    "Miami": "America/New_York",  # (nearest: Kentucky/Monticello)
    "Minneapolis": "America/Chicago",  # (nearest: Menominee)
    "Seattle": "America/Los_Angeles",  # (nearest: Boise, Mountain time: wrong)
    "Cologne": "Europe/Berlin",  # (nearest: Busingen, the German enclave in Switzerland)
    "Frankfurt": "Europe/Berlin",
    "Munich": "Europe/Berlin",
    "Effelsberg Radio Telescope": "Europe/Berlin",
    "Wendelstein Observatory": "Europe/Berlin",
    "Guadalajara": "America/Mexico_City",  # Jalisco (nearest: Bahia_Banderas)
    "Hong Kong": "Asia/Hong_Kong",  # its own zone (zone.tab lists it under HK, not CN)
    "Lhasa": "Asia/Shanghai",  # China's one official time (nearest: Urumqi, Xinjiang's, UTC+6)
    "Longyearbyen": "Arctic/Longyearbyen",  # Svalbard's own name (Oslo's clock)
    "Calar Alto Observatory": "Europe/Madrid",  # (nearest: Ceuta, in Africa)
    "Sierra Nevada Observatory": "Europe/Madrid",
    "Green Bank Observatory": "America/New_York",  # West Virginia (nearest: Indiana/Vevay)
    "McDonald Observatory": "America/Chicago",  # Jeff Davis County, Texas (nearest: Phoenix)
    "Apache Point Observatory": "America/Denver",  # New Mexico (nearest: Phoenix, no DST)
    "Sunspot Solar Observatory": "America/Denver",  # New Mexico
    "Very Large Array": "America/Denver",  # New Mexico
    "Mont Mégantic Observatory": "America/Toronto",  # Quebec (nearest: Moncton, Atlantic time)
    "Special Astrophysical Observatory": "Europe/Moscow",  # Karachay-Cherkessia (Astrakhan +4)
}


def zone_dir() -> Path:
    """The tz database's tables: the ``tzdata`` wheel's, else the system's."""
    for candidate in (
        Path(str(resources.files("tzdata") / "zoneinfo")),
        Path("/usr/share/zoneinfo"),
    ):
        if (candidate / "zone.tab").is_file() and (candidate / "iso3166.tab").is_file():
            return candidate
    raise SystemExit("no zone.tab / iso3166.tab: install tzdata")


def dms(text: str) -> float:
    """zone.tab's +DDMM[SS] / +DDDMM[SS] to degrees."""
    sign = -1.0 if text[0] == "-" else 1.0
    digits = text[1:]
    seconds = len(digits) in (6, 7)
    deg_len = len(digits) - (4 if seconds else 2)
    deg, minutes = int(digits[:deg_len]), int(digits[deg_len : deg_len + 2])
    sec = int(digits[deg_len + 2 :]) if seconds else 0
    return sign * (deg + minutes / 60 + sec / 3600)


def km(lat1: float, lon1: float, lat2: float, lon2: float) -> float:
    """Great-circle distance (km) on a sphere of 6371 km (haversine)."""
    p1, p2 = math.radians(lat1), math.radians(lat2)
    dp, dl = p2 - p1, math.radians(lon2 - lon1)
    a = math.sin(dp / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    return 2 * 6371.0 * math.asin(math.sqrt(a))


def read_tables(d: Path) -> tuple[dict[str, str], dict[str, list[tuple[str, float, float]]]]:
    """(country name -> code, code -> [(zone, lat, lon)]) from iso3166.tab and zone.tab."""
    codes = {}
    for line in (d / "iso3166.tab").read_text(encoding="utf-8").splitlines():
        if line and not line.startswith("#"):
            code, name = line.split("\t")
            codes[name] = code
    zones: dict[str, list[tuple[str, float, float]]] = {}
    for line in (d / "zone.tab").read_text(encoding="utf-8").splitlines():
        if not line or line.startswith("#"):
            continue
        code, coords, zone = line.split("\t")[:3]
        m = re.fullmatch(r"([+-]\d+)([+-]\d+)", coords)
        zones.setdefault(code, []).append((zone, dms(m.group(1)), dms(m.group(2))))
    return codes, zones


def nearest_zone(row: dict, codes, zones) -> tuple[str, str]:
    """(zone, how) for a place: its country's nearest zone point, or CHECKED's."""
    if row["name"] in CHECKED:
        return CHECKED[row["name"]], "checked"
    country = COUNTRY_ALIASES.get(row["country"], row["country"])
    code = codes.get(country)
    if code is None:
        raise SystemExit(f"{row['name']}: country {row['country']!r} is not in iso3166.tab")
    lat, lon = float(row["latitude_deg"]), float(row["longitude_deg"])
    candidates = zones[code]
    if len(candidates) == 1:
        return candidates[0][0], "only zone"
    zone = min(candidates, key=lambda z: km(lat, lon, z[1], z[2]))[0]
    return zone, f"nearest of {len(candidates)}"


def same_clock(a: str, b: str) -> bool:
    """Whether zones a and b keep the same UTC offset at every 6 hours of 2020-2026."""
    if a == b:
        return True
    za, zb = ZoneInfo(a), ZoneInfo(b)
    t = datetime(2020, 1, 1, tzinfo=timezone.utc)
    while t.year < 2027:
        if t.astimezone(za).utcoffset() != t.astimezone(zb).utcoffset():
            return False
        t += timedelta(hours=6)
    return True


def independent_check(rows: list[dict], chosen: list[str]) -> list[str]:
    """Differences from timezonefinder's polygons (empty without timezonefinder)."""
    try:
        from timezonefinder import TimezoneFinder
    except ImportError:
        print("timezonefinder is not importable: no independent check")
        return []
    finder = TimezoneFinder()
    out = []
    for row, zone in zip(rows, chosen, strict=True):
        lat, lon = float(row["latitude_deg"]), float(row["longitude_deg"])
        other = finder.timezone_at(lng=lon, lat=lat)
        if other is None or not same_clock(zone, other):
            out.append(f"{row['name']} ({row['country']}): ours {zone}, timezonefinder {other}")
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="report only; write nothing")
    args = parser.parse_args(argv)
    codes, zones = read_tables(zone_dir())
    text = PLACES.read_text(encoding="utf-8")
    lines = text.splitlines()
    head = [line for line in lines if line.startswith("#")]
    body = "\n".join(line for line in lines if not line.startswith("#"))
    reader = csv.DictReader(io.StringIO(body))
    fields = list(reader.fieldnames)
    rows = list(reader)
    if "timezone" not in fields:
        fields.insert(fields.index("elevation_m") + 1, "timezone")
    chosen, hows = [], {}
    for row in rows:
        zone, how = nearest_zone(row, codes, zones)
        ZoneInfo(zone)  # known to zoneinfo
        chosen.append(zone)
        hows[how.split(" ")[0]] = hows.get(how.split(" ")[0], 0) + 1
    print(f"{len(rows)} places: {hows}")
    for line in independent_check(rows, chosen):
        print("differs:", line)
    changed = [r["name"] for r, z in zip(rows, chosen, strict=True) if r.get("timezone") != z]
    if args.check:
        print(
            f"{len(changed)} rows differ from the file" + (f": {changed[:10]}" if changed else "")
        )
        return 1 if changed else 0
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=fields, lineterminator="\n")
    writer.writeheader()
    for row, zone in zip(rows, chosen, strict=True):
        row["timezone"] = zone
        writer.writerow(row)
    PLACES.write_text("\n".join(head) + "\n" + out.getvalue(), encoding="utf-8")
    print(f"wrote {PLACES} ({len(changed)} zones changed)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
