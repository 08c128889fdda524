"""``skydome lighting``: light for a 3D scene from the sky (skydome.lighting)."""

from __future__ import annotations

import json
import math

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
#: The prefiltered cube map's files (skydome.lighting_ibl).
CUBE_EXTENSIONS = (".dds", ".ktx2")


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
            help="Also write the sky map (the disks split out) in cd/m^2: .exr, .hdr or .npy; "
            "or .dds / .ktx2: the prefiltered GGX cube map (split sum: faces +X -X +Y -Y +Z "
            "-Z = east, west, up, down, north, south; mip k at roughness k/(levels-1), "
            "RGBA16F, cd/m^2). "
            "Repeatable.",
        ),
        cube_size: int = typer.Option(
            128, "--cube-size", help="The cube map's face size, a power of two 8..2048."
        ),
        cube_scale: float = typer.Option(
            1.0,
            "--cube-scale",
            help="Multiply the cube map's values (cd/m^2) by this (half floats hold up to 65504).",
        ),
        brdf_table: str = typer.Option(
            None,
            "--brdf-table",
            help="Also write the split sum's BRDF table (.exr: R = scale, G = bias of F0; "
            "columns n.v, rows roughness, 128x128, Schlick-GGX visibility as Karis 2013).",
        ),
        flags=None,
    ) -> None:
        """Light for a 3D scene: the Sun and the Moon as lights (direction, angular radius,
        RGB illuminance at the ground after the air and the clouds), the sky's irradiance as
        9 spherical-harmonic coefficients (lx: E(n) = sum sh[i] Y_i(n), Ramamoorthi-Hanrahan
        order; x east, y north, z up) and directional lights that reproduce it, for a Sun at
        --sun-elevation or a place (--place, or --lat and --lon) and --time; with -o env.dds
        or env.ktx2 the prefiltered GGX cube map (split sum), with --brdf-table its table."""
        from rich.console import Console
        from rich.table import Table

        from skydome import lighting_ibl
        from skydome.io import atomic_write, check_output_path, write_outputs
        from skydome.io.dds import dds_cube_bytes
        from skydome.io.ktx2 import ktx2_cube_bytes
        from skydome.io.table_exr import write_table_exr
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
        if isinstance(cube_size, bool) or not 8 <= cube_size <= 2048 or cube_size & (cube_size - 1):
            raise ParameterError(f"--cube-size {cube_size} must be a power of two from 8 to 2048")
        if not (math.isfinite(cube_scale) and cube_scale > 0.0):
            raise ParameterError(f"--cube-scale {cube_scale} must be a positive number")
        paths = [check_output_path(p, MAP_EXTENSIONS + CUBE_EXTENSIONS) for p in (output or [])]
        outputs = [p for p in paths if p.suffix.lower() in MAP_EXTENSIONS]
        cubes = [p for p in paths if p.suffix.lower() in CUBE_EXTENSIONS]
        table_path = None if brdf_table is None else check_output_path(brdf_table, (".exr",))
        description = sky_description(flags, pts)
        console = Console(soft_wrap=True, stderr=True)
        if not pts.abstract:
            report_time(pts.time, pts.zone)
            report_light_pollution(description, pts.place, flags.bortle)
        with precompute_progress(console) as report:
            sky = Sky(description, progress=report)
        with sky:
            light = sky.lighting((width, height), lights)
            cube = light.prefiltered(sky.graph.ctx, face_size=cube_size) if cubes else None
            table = lighting_ibl.brdf_table(sky.graph.ctx) if table_path is not None else None
        blobs = {}  # made (and checked: half floats) before anything is written
        for p in cubes:
            make = dds_cube_bytes if p.suffix.lower() == ".dds" else ktx2_cube_bytes
            blobs[p] = make(cube.levels, cube_scale)
        if outputs:
            write_outputs(outputs, light.sky_map.data, metadata=light.sky_map.info)
        for p in cubes:
            atomic_write(p, lambda tmp, blob=blobs[p]: tmp.write_bytes(blob))
        if table is not None:
            write_table_exr(table_path, table, lighting_ibl.TABLE_DESCRIPTION)
        outputs += cubes + ([] if table_path is None else [table_path])
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
