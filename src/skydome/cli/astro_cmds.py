"""``skydome ephemeris`` and ``skydome events``: where the Sun, Moon, planets and stars are.

Both commands print a Rich table, or JSON with ``--json``. Bad input raises
:class:`skydome.errors.ParameterError`, which ``skydome.cli.main`` turns into one line on
stderr and exit status 2.
"""

from __future__ import annotations

import json
import math
from types import SimpleNamespace

import typer

from skydome.errors import ParameterError

DEFAULT_BODIES = "sun,moon,mercury,venus,mars,jupiter,saturn,uranus,neptune"


#: --place / --utc of ephemeris and events, and what --time / --date then mean.
_PLACE_HELP = (
    "A city or observatory of the gazetteer (skydome places), instead of --lat/--lon: a time "
    "without an offset is its local time, and times are shown in it too."
)
_UTC_HELP = "Read a time without an offset as UTC, not as the --place's local time."


def _where(place, lat, lon, elevation, utc):
    """(lat, lon, elevation_m, zone, place) of --place or --lat/--lon (one of them): the
    zone (a ZoneInfo) is the place's, None (UTC) with --lat/--lon or --utc."""
    if place is not None and (lat is not None or lon is not None):
        raise ParameterError("--place and --lat/--lon both give the place: use one of them")
    if place is None:
        if lat is None or lon is None:
            raise ParameterError("give --place NAME, or --lat and --lon")
        return lat, lon, 0.0 if elevation is None else elevation, None, None
    from skydome.cli.describe import place_from_flags

    p = place_from_flags(SimpleNamespace(place=place))
    height = p.elevation_m if elevation is None else elevation
    return p.latitude_deg, p.longitude_deg, height, None if utc else p.zone, p


def _local(iso_utc: str, zone):
    """An ISO time in UTC (``...Z``) as an aware datetime in the zone, or None."""
    import datetime as dt

    try:
        t = dt.datetime.fromisoformat(iso_utc.replace("Z", "+00:00"))
    except (ValueError, AttributeError, TypeError):
        return None
    if t.tzinfo is None:
        t = t.replace(tzinfo=dt.timezone.utc)
    return t.astimezone(zone)


def _observer(lat, lon, elevation, pressure, temperature):
    from skydome.astro import Observer

    return Observer(lat, lon, elevation, pressure, temperature)


#: Bodies whose light is sunlight (the Sun, and reflected by the Moon and the planets):
#: their ground illuminance uses the transmittance weighted by the solar spectrum.
_SUNLIT_BODIES = ("sun", "moon", "mercury", "venus", "mars", "jupiter", "saturn", "uranus",
                  "neptune")  # fmt: skip


def ground_direct_horizontal_lux(
    atmosphere: str, apparent_alt_deg: float, elevation_m: float, normal_lux: float
) -> float:
    """Direct-beam illuminance (lx) on a horizontal surface at the ground from a source of
    sunlight of ``normal_lux`` outside the atmosphere, seen at ``apparent_alt_deg``.

    E = normal_lux * T * sin(h), T the transmittance of the ``atmosphere`` preset from the
    observer (``elevation_m`` above the preset's ground, clamped at 0) to the top along the
    apparent direction (the refracted ray's last direction stands for its path), weighted
    by the ASTM G-173 solar spectrum and V(lambda) on a 1 nm grid; column densities from the
    float64 quadrature of ``skydome.atmosphere.columns`` (no GL). Zero at and below
    the horizon, and where the ray meets the ground. Diffuse skylight is not included.
    """
    if apparent_alt_deg <= 0.0:
        return 0.0
    import numpy as np

    from skydome.atmosphere import columns as ref
    from skydome.atmosphere import preset
    from skydome.spectra import photopic_efficiency, solar_irradiance

    params = preset(atmosphere)
    r_m = min(params.bottom_radius_m + max(elevation_m, 0.0), params.top_radius_m)
    mu = math.sin(math.radians(apparent_alt_deg))
    if ref.ray_hits_ground(params, r_m, mu):
        return 0.0
    column_m = ref.column_to_top(params, r_m, mu)
    wl = np.arange(360.0, 831.0, 1.0)
    c = params.coefficients(wl)
    tau = ref.optical_depth(c, column_m)
    weight = solar_irradiance(wl) * photopic_efficiency(wl)
    transmittance = float(np.sum(weight * np.exp(-tau)) / np.sum(weight))
    return float(normal_lux) * transmittance * mu


def _finite(x):
    """JSON has no inf/NaN: map them to None."""
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def register(app: typer.Typer) -> None:
    @app.command()
    def ephemeris(
        lat: float = typer.Option(None, "--lat", help="Geodetic latitude, degrees (north +)."),
        lon: float = typer.Option(None, "--lon", help="Longitude, degrees (east +)."),
        place: str = typer.Option(None, "--place", help=_PLACE_HELP),
        time: str = typer.Option(
            ...,
            "--time",
            help="ISO 8601 time, e.g. 2024-06-21T14:00 or 2024-06-21T12:00:00Z: without an "
            "offset or Z, the --place's local time (its IANA time zone), UTC with --lat/--lon "
            "or --utc.",
        ),
        utc: bool = typer.Option(False, "--utc", help=_UTC_HELP),
        elevation: float = typer.Option(
            None, "--elevation", help="Metres above the ellipsoid (default: the place's, or 0)."
        ),
        pressure: float = typer.Option(1010.0, "--pressure", help="hPa, for refraction."),
        temperature: float = typer.Option(10.0, "--temperature", help="deg C, for refraction."),
        bodies: str = typer.Option(
            DEFAULT_BODIES, "--bodies", help="Comma-separated bodies or star names."
        ),
        atmosphere: str = typer.Option(
            "earth", "--atmosphere", help="Atmosphere preset for the illuminance at the ground."
        ),
        as_json: bool = typer.Option(False, "--json", help="Print JSON keyed by body name."),
    ) -> None:
        """Apparent positions, distances and brightness of the Sun, Moon, planets or stars.

        Illuminance: outside the atmosphere on a surface facing the body
        (``illuminance_lux``), and, for the Sun, Moon and planets, the direct beam on a
        horizontal surface at the ground through the ``--atmosphere`` preset
        (``ground_direct_horizontal_lux``; zero below the horizon; no skylight).
        """
        from skydome.astro.time import format_local
        from skydome.atmosphere import preset
        from skydome.cli.describe import report_time
        from skydome.cli.parsing import parse_time

        preset(atmosphere)  # an unknown name fails here, before any work
        lat, lon, elevation, zone, where = _where(place, lat, lon, elevation, utc)
        obs = _observer(lat, lon, elevation, pressure, temperature)
        names = [b.strip() for b in bodies.split(",") if b.strip()]
        if not names:
            raise ParameterError(f"--bodies {bodies!r} names no body")
        t = parse_time("--time", time, zone)
        sky = obs.sky(t, bodies=tuple(names))
        report_time(t, zone)
        result = {}
        for name, pos in sky.bodies.items():
            d = {k: _finite(v) for k, v in pos.as_dict().items()}
            if "magnitude" not in d:
                d["magnitude"] = None
            d["ground_direct_horizontal_lux"] = (
                ground_direct_horizontal_lux(atmosphere, d["alt"], elevation, d["illuminance_lux"])
                if name in _SUNLIT_BODIES
                else None
            )
            result[name] = d
        if as_json:
            payload = {
                "time_utc": str(t.iso()),
                **({} if zone is None else {"time_local": format_local(t, zone)}),
                **({} if where is None else {"place": where.name, "timezone": where.timezone}),
                "observer": {
                    "lat": lat,
                    "lon": lon,
                    "elevation_m": elevation,
                    "pressure_hPa": pressure,
                    "temperature_C": temperature,
                },
                "atmosphere": atmosphere,
                "definitions": {
                    "illuminance_lux": "outside the atmosphere, on a surface facing the body",
                    "ground_direct_horizontal_lux": (
                        "direct beam on a horizontal surface at the ground through the"
                        " atmosphere's transmittance (0 below the horizon, no skylight;"
                        " null for stars)"
                    ),
                },
                "bodies": list(result),
            }
            payload.update(result)
            typer.echo(json.dumps(payload, indent=2))
            return
        from rich.console import Console
        from rich.table import Table

        table = Table(
            title=(f"{format_local(t, zone)} = " if zone is not None else "")
            + f"{t.iso()} at "
            + (f"{where.name}, " if where is not None else "")
            + f"{lat:.4f}, {lon:.4f}, {elevation:g} m",
            caption=(
                "lux outside atm.: facing the body, above the atmosphere; lux at ground:"
                f" direct beam on a horizontal surface through the {atmosphere!r}"
                " atmosphere (no skylight)"
            ),
        )
        cols = ("body", "alt", "az", "RA", "Dec", "distance km", "mag", "lux outside atm.",
                "lux at ground", "phase")  # fmt: skip
        for col in cols:
            table.add_column(col, justify="right" if col != "body" else "left")
        for name, d in result.items():
            mag = d.get("magnitude")
            frac = d.get("illuminated_fraction")
            ground = d["ground_direct_horizontal_lux"]
            table.add_row(
                name,
                f"{d['alt']:.3f}",
                f"{d['az']:.3f}",
                f"{d['ra'] / 15:.4f}h",
                f"{d['dec']:+.3f}",
                "inf" if d["distance_km"] is None else f"{d['distance_km']:.6g}",
                "" if mag is None else f"{mag:.2f}",
                f"{d['illuminance_lux']:.3g}",
                "" if ground is None else f"{ground:.3g}",
                "" if frac is None else f"{frac:.3f}",
            )
        Console(width=max(Console().width, 110)).print(table)

    @app.command()
    def events(
        lat: float = typer.Option(None, "--lat", help="Geodetic latitude, degrees (north +)."),
        lon: float = typer.Option(None, "--lon", help="Longitude, degrees (east +)."),
        place: str = typer.Option(None, "--place", help=_PLACE_HELP),
        date: str = typer.Option(
            ...,
            "--date",
            help="Start date YYYY-MM-DD: from its 00:00 local time at a --place, 00:00 UTC "
            "with --lat/--lon or --utc.",
        ),
        utc: bool = typer.Option(False, "--utc", help=_UTC_HELP),
        days: int = typer.Option(1, "--days", help="Number of days to search (1-3660)."),
        elevation: float = typer.Option(
            None, "--elevation", help="Metres above the ellipsoid (default: the place's, or 0)."
        ),
        as_json: bool = typer.Option(False, "--json", help="Print JSON."),
    ) -> None:
        """Sunrise/sunset, transits, twilights, moonrise/moonset and Moon phases: in UTC, and
        in the place's local time with --place (its zone's abbreviation and offset).

        Days on which the Sun or the Moon never rises or never sets, or the Sun never gets
        dark or light enough for a twilight, are listed by date, in words.
        """
        import datetime as dt

        from skydome.astro.events import events as find_events

        try:
            day = dt.date.fromisoformat(date)
        except ValueError:
            raise ParameterError(f"--date {date!r} is not a date YYYY-MM-DD") from None
        if not 1 <= days <= 3660:
            raise ParameterError(f"--days {days} is outside the valid range [1, 3660]")
        lat, lon, elevation, zone, where = _where(place, lat, lon, elevation, utc)
        obs = _observer(lat, lon, elevation, 1010.0, 10.0)
        # the day's first instant: local midnight, or where a zone skips midnight (Chile's
        # clocks go from 24:00 to 01:00) the instant its clocks jump
        first = dt.datetime.combine(day, dt.time()).replace(tzinfo=zone or dt.timezone.utc)
        start = first.astimezone(dt.timezone.utc)
        from skydome.astro.time import to_time
        from skydome.cli.describe import report_time

        ev = find_events(obs, start.isoformat(), days)
        report_time(to_time(start), zone)
        rows = ev.as_list()
        if zone is not None:
            for r in rows:
                local = _local(r.get("time"), zone)
                if local is not None:
                    r["time_local"] = local.isoformat()
        if as_json:
            where_json = {} if where is None else {"place": where.name, "timezone": where.timezone}
            typer.echo(
                json.dumps(
                    {
                        "date": day.isoformat(),
                        "days": days,
                        "lat": lat,
                        "lon": lon,
                        **where_json,
                        "events": rows,
                    },
                    indent=2,
                )
            )
            return
        from rich.console import Console
        from rich.table import Table

        at = f"{where.name} ({lat}, {lon})" if where is not None else f"{lat}, {lon}"
        table = Table(
            title=f"Events from {day.isoformat()} for {days} day(s) at {at} "
            + (f"({zone.key} and UTC)" if zone is not None else "(UTC)")
        )
        cols = ("time (UTC)", "event", "body")
        if zone is not None:
            cols = (f"local time ({zone.key})", *cols)
        for col in cols:
            table.add_column(col)
        for r in rows:
            local = _local(r.get("time"), zone) if zone is not None else None
            shown = [] if zone is None else [""]
            if local is not None:
                shown = [f"{local:%Y-%m-%d %H:%M:%S} {local.tzname()}"]
            if r.get("all_day"):  # a whole day without the event: date only, in words
                if local is not None:
                    shown = [f"{local:%Y-%m-%d}"]
                table.add_row(*shown, r["time"][:10], r["description"], r["body"])
            else:
                note = f" ({r['note']})" if r.get("note") else ""  # eclipses: kind, altitude
                table.add_row(*shown, r["time"], r["event"] + note, r["body"])
        Console(width=max(Console().width, 110)).print(table)
