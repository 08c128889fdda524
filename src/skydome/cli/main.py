"""The ``skydome`` command: a Typer app whose sub-commands live in sibling modules.

Each command module exposes ``register(app)``. Errors of the SkydomeError family
become one line on stderr and exit status 2, with no traceback.
"""

from __future__ import annotations

import importlib
import sys

import typer

from skydome.errors import SkydomeError

app = typer.Typer(
    name="skydome",
    help="Physically based skies in absolute units.",
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
)

# Command modules, each with a register(app) function. Add new ones here.
COMMAND_MODULES = [
    "skydome.cli.info_cmd",
    "skydome.cli.render_cmd",
    "skydome.cli.atmosphere_cmds",
    "skydome.cli.astro_cmds",
]

for _name in COMMAND_MODULES:
    importlib.import_module(_name).register(app)


def fail(message: str) -> None:
    """Print one error line on stderr and exit with status 2."""
    typer.echo(f"skydome: error: {message}", err=True)
    raise typer.Exit(2)


def run(argv: list[str] | None = None) -> None:
    """Entry point of the console script."""
    try:
        app(args=argv, standalone_mode=True)
    except SkydomeError as exc:
        typer.echo(f"skydome: error: {exc}", err=True)
        sys.exit(2)


if __name__ == "__main__":
    run()
