"""``skydome places``: the built-in gazetteer of cities and observatories."""

from __future__ import annotations

import typer


def register(app: typer.Typer) -> None:
    @app.command()
    def places(
        query: str = typer.Argument(None, help="Search text (name, alias or country)."),
        limit: int = typer.Option(20, "--limit", help="Most places listed for a search."),
    ) -> None:
        """List the places --place accepts, or search them."""
        from rich.console import Console
        from rich.table import Table

        from skydome.astro.places import places as all_places
        from skydome.astro.places import search
        from skydome.cli.render_cmd import check_int

        check_int("--limit", limit, 1, 10_000)
        found = search(query, limit) if query else list(all_places())
        console = Console(soft_wrap=True)
        if not found:
            console.print(f"no place matches {query!r}")
            return
        table = Table("name", "country", "kind", "lat", "lon", "elevation (m)", "time zone")
        for p in found:
            table.add_row(
                p.name, p.country, p.kind, f"{p.latitude_deg:.4f}", f"{p.longitude_deg:.4f}",
                f"{p.elevation_m:.0f}", p.timezone,
            )  # fmt: skip
        console.print(table)
