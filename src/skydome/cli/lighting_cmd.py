"""``skydome lighting``: light for a 3D scene from the sky (skydome.lighting)."""

from __future__ import annotations

import json

import typer

from skydome.cli.describe import (
    place_time_sun,
    precompute_progress,
    report_light_pollution,
    report_time,
    sky_description,
)
from skydome.cli.options import with_flags
from skydome.cli.parsing import check_int, parse_size
from skydome.errors import ParameterError

#: The map files the command writes (the sky alone, in cd/m^2).
MAP_EXTENSIONS = (".exr", ".hdr", ".npy")


def register(app: typer.Typer) -> None:
    @app.command()
    @with_flags("place", "sun", "air", "tables", "night", "clouds", "weather")
    def lighting(
        when: str = typer.Option(
            None,
            "--time",
            help="ISO 8601 date and time with a place (as for render): without an offset or "
            "Z, the --place's local time (its IANA time zone), UTC with --lat/--lon or --utc.",
        ),
        size: str = typer.Option(
            "256x128", "--size", help="The equirect map measured, WIDTHxHEIGHT (2:1)."
        ),
        lights: int = typer.Option(16, "--lights", help="Directional lights, 1..64."),
        as_json: bool = typer.Option(False, "--json", help="Print a JSON object."),
        output: list[str] = typer.Option(
            None,
            "-o",
            "--output",
            help="Also write the sky map (the disks split out) in cd/m^2: .exr, .hdr or .npy. "
            "Repeatable.",
        ),
        flags=None,
    ) -> None:
        """Light for a 3D scene: the Sun and the Moon as lights (direction, angular radius,
        RGB illuminance at the ground after the air and the clouds), the sky's irradiance as
        9 spherical-harmonic coefficients (lx: E(n) = sum sh[i] Y_i(n), Ramamoorthi-Hanrahan
        order; x east, y north, z up) and directional lights that reproduce it, for a Sun at
        --sun-elevation or a place (--place, or --lat and --lon) and --time."""
        from rich.console import Console
        from rich.table import Table

        from skydome.io import check_output_path, write_outputs
        from skydome.sky import Sky

        pts = place_time_sun(flags, when)
        if pts.abstract and flags.sun_elevation is None:
            raise ParameterError(
                "lighting needs --sun-elevation, or a place (--place or --lat/--lon) and --time"
            )
        width, height = parse_size(size)
        if width != 2 * height or width < 16 or width > 4096:
            raise ParameterError(f"--size {size} must be a 2:1 map 16 to 4096 pixels wide")
        check_int("--lights", lights, 1, 64)
        outputs = [check_output_path(p, MAP_EXTENSIONS) for p in (output or [])]
        description = sky_description(flags, pts)
        console = Console(soft_wrap=True, stderr=True)
        if not pts.abstract:
            report_time(pts.time, pts.zone)
            report_light_pollution(description, pts.place, flags.bortle)
        with precompute_progress(console) as report:
            sky = Sky(description, progress=report)
        with sky:
            light = sky.lighting((width, height), lights)
        if outputs:
            write_outputs(outputs, light.sky_map.data, metadata=light.sky_map.info)
        if as_json:
            typer.echo(json.dumps(light.as_dict(), indent=2))
            return
        out = Console(soft_wrap=True)
        table = Table(title="Lights (lx on a surface facing each; x east, y north, z up)")
        for col in ("light", "direction", "R", "G", "B", "Y (lx)"):
            table.add_column(col)
        rows = [("sun", light.sun), ("moon", light.moon)]
        rows += [(f"sky {i + 1}", li) for i, li in enumerate(light.lights)]
        for name, li in rows:
            if li is None:
                continue
            rgb = li.illuminance_rgb
            y = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
            table.add_row(name, " ".join(f"{v:+.3f}" for v in li.direction),
                          *(f"{v:.4g}" for v in rgb), f"{y:.4g}")  # fmt: skip
        out.print(table)
        out.print("sky irradiance, 9 SH coefficients (lx, R G B):")
        for i, row in enumerate(light.sh):
            out.print(f"  sh[{i}] " + " ".join(f"{v:12.5g}" for v in row))
        for p in outputs:
            out.print(f"wrote {p}")
