"""The ``skydome`` command: a Typer app whose sub-commands live in sibling modules.

Each command module exposes ``register(app)``. Errors of the SkydomeError family and usage
errors (an unknown option, a value of the wrong type) become one line on stderr and exit
status 2, with no traceback; a SkydomeWarning (e.g. a damaged cache file being rebuilt)
becomes one ``skydome: warning:`` line, and other libraries' warnings are not shown.
"""

from __future__ import annotations

import importlib
import sys
import warnings

import typer
import typer.core

from skydome.errors import SkydomeError, SkydomeWarning
from skydome.version import __version__

# Typer >= 0.2x carries its own copy of Click as typer._click; older releases use click.
_click = getattr(typer.core, "_click", None) or importlib.import_module("click")

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
    "skydome.cli.timelapse_cmd",
    "skydome.cli.places_cmd",
    "skydome.cli.atmosphere_cmds",
    "skydome.cli.astro_cmds",
    "skydome.cli.view_cmd",
    "skydome.cli.lighting_cmd",
    "skydome.cli.batch_cmd",
]

for _name in COMMAND_MODULES:
    importlib.import_module(_name).register(app)


def _print_version(value: bool) -> None:
    if value:
        typer.echo(f"skydome {__version__}")
        raise typer.Exit()


@app.callback()
def _main(
    version: bool = typer.Option(
        False,
        "--version",
        is_eager=True,
        callback=_print_version,
        help="Print the skydome version and exit.",
    ),
) -> None:
    """Physically based skies in absolute units."""


def fail(message: str) -> None:
    """Print one error line on stderr and exit with status 2."""
    typer.echo(f"skydome: error: {message}", err=True)
    raise typer.Exit(2)


def one_line(text: object) -> str:
    """``text`` with every run of whitespace, newlines included, made one space."""
    return " ".join(str(text).split())


def show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """``warnings.showwarning`` for the CLI: a SkydomeWarning (skydome's own, e.g. a damaged
    cache file being rebuilt) becomes one line ``skydome: warning: <message>`` on stderr;
    any other warning (NumPy's RuntimeWarnings, Pillow, moderngl...) is not shown: it is
    about code the user does not run, and Python's format spans several lines. Warnings the
    filters turn into errors (``python -W error``) still raise."""
    if issubclass(category, SkydomeWarning):
        out = sys.stderr if file is None else file
        try:
            out.write(f"skydome: warning: {one_line(message)}\n")
        except (OSError, ValueError):  # stderr gone or closed, as the default showwarning does
            pass


def run(argv: list[str] | None = None) -> None:
    """Entry point of the console script: run the command, exit 0 on success and 2 (one
    line on stderr) for bad input."""
    with warnings.catch_warnings():
        warnings.showwarning = show_warning
        try:
            status = app(args=argv, standalone_mode=False)
        except SkydomeError as exc:
            typer.echo(f"skydome: error: {one_line(exc)}", err=True)
            sys.exit(2)
        except _click.exceptions.UsageError as exc:
            if exc.ctx is not None and not argv_given(argv):
                typer.echo(exc.ctx.get_help())  # no arguments at all: the help, as before
                sys.exit(2)
            hint = f" (see {exc.ctx.command_path} --help)" if exc.ctx is not None else ""
            typer.echo(f"skydome: error: {one_line(exc.format_message())}{hint}", err=True)
            sys.exit(exc.exit_code)
        except typer.Abort:
            typer.echo("skydome: aborted", err=True)
            sys.exit(1)
    sys.exit(status if isinstance(status, int) else 0)


def argv_given(argv: list[str] | None) -> bool:
    """Whether the command line has any argument after the program name."""
    return bool(sys.argv[1:] if argv is None else argv)


if __name__ == "__main__":
    run()
