"""``skydome illuminance`` and ``skydome precompute``."""

from __future__ import annotations

import json
import time
from types import SimpleNamespace

import typer

from skydome.cli.describe import (
    atmosphere_from_flags,
    config_from_flags,
    precompute_progress,
    weather_from_flags,
    weathered_air_from_flags,
)
from skydome.cli.options import with_flags
from skydome.errors import check_range


def register(app: typer.Typer) -> None:
    @app.command()
    @with_flags("place", "sun", "air", "weather")
    def illuminance(
        when: str = typer.Option(
            None,
            "--time",
            help="ISO 8601 date and time with a place (as for render): without an offset or "
            "Z, the --place's local time (its IANA time zone), UTC with --lat/--lon or --utc.",
        ),
        altitude: float = typer.Option(
            None,
            "--altitude",
            help="Observer altitude above sea level (the atmosphere's ground), metres; default: "
            "the place's ground, its elevation (0 for a Sun alone, and under a --weather, whose "
            "clouds count from the ground).",
        ),
        as_json: bool = typer.Option(False, "--json", help="Print a JSON object."),
        flags=None,
    ) -> None:
        """Horizontal illuminance from the Sun and the sky (lx) and the zenith luminance
        (cd/m^2), for a Sun at --sun-elevation, or at a place (--place, or --lat and --lon)
        and --time, a solar eclipse included (eclipse_fraction: the part of the Sun's
        limb-darkened flux the Moon hides); with a weather, under its clouds, fog, rain or
        snow."""
        from rich.console import Console

        from skydome.cli.describe import place_time_sun
        from skydome.errors import ParameterError
        from skydome.weather_effects import ground_visibility_km

        pts = place_time_sun(flags, when)
        if pts.abstract and flags.sun_elevation is None:
            raise ParameterError(
                "illuminance needs --sun-elevation, or a place (--place or --lat/--lon) and --time"
            )
        sun_elevation = pts.sun_elevation_deg
        params, clouds, config = weathered_air_from_flags(flags)
        weather = weather_from_flags(flags)
        if altitude is not None:
            check_range("--altitude", altitude, 0.0, params.atmosphere_height_m, "m")
            if clouds is not None and not pts.abstract:
                raise ParameterError(
                    "--altitude with a --weather at a place: its light is the place's ground's, "
                    "under clouds that count from there; drop --altitude"
                )
        elif pts.abstract:
            altitude = 0.0
        # else a place's light is its ground's (its elevation), as a render of it stands there
        console = Console(soft_wrap=True)
        with precompute_progress(console) as report:
            from skydome.atmosphere.tables import load_tables
            from skydome.gpu import shared_context

            load_tables(shared_context(), params, config, progress=report)
        eclipse = {}
        if pts.abstract and clouds is None:
            from skydome.eclipse_illuminance import state_illuminance
            from skydome.scene.state import abstract_state

            # the Sun at --sun-elevation as render draws it: the apparent elevation
            sun = abstract_state(sun_elevation, pts.sun_azimuth_deg)
            res = state_illuminance(sun, atmosphere=params, config=config, altitude_m=altitude)
            res.update(sun_elevation_deg=sun_elevation)
            for key in ("eclipse_fraction", "sun_distance_au"):
                res.pop(key)
        elif pts.abstract:
            from skydome.weather_illuminance import weather_illuminance

            res = weather_illuminance(
                sun_elevation, altitude, weather, atmosphere_from_flags(flags)
            )
        else:
            from skydome.cli.describe import report_time
            from skydome.eclipse_illuminance import place_illuminance
            from skydome.weather_illuminance import place_weather_illuminance

            report_time(pts.time, pts.zone)
            if clouds is None:
                res = place_illuminance(
                    pts.observer, pts.time, atmosphere=params, config=config, altitude_m=altitude
                )
            else:
                res = place_weather_illuminance(
                    pts.observer, pts.time, weather, atmosphere_from_flags(flags)
                )
            sun_elevation = res["sun_elevation_deg"]
            eclipse = {"eclipse_fraction": res.pop("eclipse_fraction")}
            res.pop("sky_eclipse_ratio", None)
        res = {**res, **eclipse}
        visibility = ground_visibility_km(params, clouds)
        if as_json:
            out = {"atmosphere": params.name, "visibility_km": visibility}
            if weather is not None:
                out.update(weather.summary())
            typer.echo(json.dumps({**out, **res}, indent=2))
            return
        what = "" if weather is None else f", weather {weather.preset}"
        console.print(
            f"atmosphere {params.name}{what} (visibility {visibility:.3g} km), Sun at "
            f"{sun_elevation:g} deg, altitude {res['altitude_m']:g} m"
        )
        res = SimpleNamespace(**res)
        console.print(f"direct horizontal illuminance (Sun):  {res.direct_horizontal_lux:12.5g} lx")
        console.print(
            f"diffuse horizontal illuminance (sky): {res.diffuse_horizontal_lux:12.5g} lx"
        )
        console.print(f"total horizontal illuminance:         {res.total_horizontal_lux:12.5g} lx")
        if eclipse.get("eclipse_fraction", 0.0) > 0.0:
            console.print(
                f"solar eclipse: {100 * res.eclipse_fraction:.4g} % of the Sun's flux hidden"
            )
        console.print(
            f"zenith luminance:                     {res.zenith_luminance_cd_m2:12.5g} cd/m^2"
        )

    @app.command()
    @with_flags("air", "weather", "tables")
    def precompute(
        output: str = typer.Option(
            None, "-o", "--output", help="Also write the tables to this .lut file."
        ),
        no_cache: bool = typer.Option(
            False, "--no-cache", help="Recompute even if the cache holds the tables."
        ),
        flags=None,
    ) -> None:
        """Precompute the multiple-scattering tables into the cache (and optionally a file)."""
        from rich.console import Console

        from skydome.atmosphere.tables import load_tables, tables_key
        from skydome.core.cache import cache_path
        from skydome.gpu import shared_context
        from skydome.io.lutfile import write_lut_file
        from skydome.io.outputs import check_output_path

        params, _, config = weathered_air_from_flags(flags, config_from_flags(flags))
        orders = config.orders
        # The output is checked before the tables are computed (minutes for fine ones): a
        # .lut file in a writable folder, not a directory or a FIFO.
        out = None if output is None else check_output_path(output, extensions=(".lut",))
        console = Console(soft_wrap=True)
        t0 = time.perf_counter()
        with precompute_progress(console) as report:
            tables, loaded = load_tables(
                shared_context(), params, config, cache=not no_cache, progress=report
            )
        seconds = time.perf_counter() - t0
        key = tables_key(params, config)
        how = "loaded from the cache" if loaded else "computed"
        console.print(
            f"{params.name}: {orders} orders, {len(config.render_wavelengths)} wavelengths, {how} in {seconds:.2f} s"
        )
        for stage, s in tables.timings.items():
            console.print(f"  {stage}: {s:.3f} s")
        console.print(
            f"tables: {tables.memory_bytes() / 2**20:.1f} MiB; cache {cache_path(key, f'sky-{params.name}')}"
        )
        if out is not None:
            write_lut_file(
                out, key, tables.to_arrays(), {"atmosphere": params.name, "orders": orders}
            )
            console.print(f"wrote {out}")
