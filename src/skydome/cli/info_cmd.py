"""``skydome info``: the package version and the OpenGL device."""

from __future__ import annotations

import typer


def register(app: typer.Typer) -> None:
    @app.command()
    def info() -> None:
        """Print the skydome version, the OpenGL renderer and version, and whether it is software."""
        from skydome.gpu import gl_info, shared_context
        from skydome.version import __version__

        gi = gl_info(shared_context())
        typer.echo(f"skydome {__version__}")
        typer.echo(f"OpenGL renderer: {gi.renderer}")
        typer.echo(f"OpenGL vendor:   {gi.vendor}")
        typer.echo(f"OpenGL version:  {gi.version}")
        typer.echo(f"software:        {'yes (CPU rasterizer)' if gi.software else 'no (GPU)'}")
