"""The progress bar of long runs of outputs (a time-lapse's frames, a batch's jobs): a label,
the bar, done of total, any columns the run adds, the time spent and the time left."""

from __future__ import annotations

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    ProgressColumn,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

__all__ = ["eta_progress"]


def eta_progress(
    console: Console,
    label: str,
    *extra: ProgressColumn,
    enabled: bool = True,
    transient: bool = False,
) -> Progress:
    """A ``rich`` progress bar on ``console``: the ``label`` column (a format string of the
    task, e.g. ``"{task.description}"``), the bar, done of total, ``extra`` columns, the time
    elapsed and the ETA. Shown only when ``enabled`` and the console is a terminal."""
    return Progress(
        TextColumn(label), BarColumn(), MofNCompleteColumn(), *extra, TimeElapsedColumn(),
        TextColumn("ETA"), TimeRemainingColumn(), console=console, transient=transient,
        disable=not (enabled and console.is_terminal),
    )  # fmt: skip
