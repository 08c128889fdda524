"""``skydome ephemeris`` and ``skydome events``: where the Sun, Moon, planets and stars are.

Both commands print a Rich table, or JSON with ``--json``. Bad input raises
:class:`skydome.errors.ParameterError`, which ``skydome.cli.main`` turns into one line on
stderr and exit status 2.
"""

from __future__ import annotations

import json
import math

import typer

from skydome.errors import ParameterError

DEFAULT_BODIES = "sun,moon,mercury,venus,mars,jupiter,saturn,uranus,neptune"


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
        lat: float = typer.Option(..., "--lat", help="Geodetic latitude, degrees (north +)."),
        lon: float = typer.Option(..., "--lon", help="Longitude, degrees (east +)."),
        time: str = typer.Option(
            ..., "--time", help="ISO 8601 time, e.g. 2024-06-21T12:00:00Z (naive = UTC)."
        ),
        elevation: float = typer.Option(0.0, "--elevation", help="Metres above the ellipsoid."),
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
        from skydome.astro.time import to_time
        from skydome.atmosphere import preset

        preset(atmosphere)  # an unknown name fails here, before any work
        obs = _observer(lat, lon, elevation, pressure, temperature)
        names = [b.strip() for b in bodies.split(",") if b.strip()]
        if not names:
            raise ParameterError(f"--bodies {bodies!r} names no body")
        t = to_time(time)
        if t.shape != ():
            raise ParameterError(f"--time {time!r} must be a single time")
        sky = obs.sky(t, bodies=tuple(names))
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
            title=f"{t.iso()} at {lat:.4f}, {lon:.4f}, {elevation:g} m",
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
        lat: float = typer.Option(..., "--lat", help="Geodetic latitude, degrees (north +)."),
        lon: float = typer.Option(..., "--lon", help="Longitude, degrees (east +)."),
        date: str = typer.Option(..., "--date", help="Start date YYYY-MM-DD (00:00 UTC)."),
        days: int = typer.Option(1, "--days", help="Number of days to search (1-3660)."),
        elevation: float = typer.Option(0.0, "--elevation", help="Metres above the ellipsoid."),
        as_json: bool = typer.Option(False, "--json", help="Print JSON."),
    ) -> None:
        """Sunrise/sunset, transits, twilights, moonrise/moonset and Moon phases (UTC).

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
        obs = _observer(lat, lon, elevation, 1010.0, 10.0)
        ev = find_events(obs, day.isoformat(), days)
        rows = ev.as_list()
        if as_json:
            typer.echo(
                json.dumps(
                    {"date": day.isoformat(), "days": days, "lat": lat, "lon": lon, "events": rows},
                    indent=2,
                )
            )
            return
        from rich.console import Console
        from rich.table import Table

        table = Table(
            title=f"Events from {day.isoformat()} for {days} day(s) at {lat}, {lon} (UTC)"
        )
        for col in ("time (UTC)", "event", "body"):
            table.add_column(col)
        for r in rows:
            if r.get("all_day"):  # a whole day without the event: date only, in words
                table.add_row(r["time"][:10], r["description"], r["body"])
            else:
                table.add_row(r["time"], r["event"], r["body"])
        Console(width=max(Console().width, 110)).print(table)
