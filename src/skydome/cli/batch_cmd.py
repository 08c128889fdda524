"""``skydome batch SPEC``: skies by the thousand (skydome.batch), in this process or on Dask."""

from __future__ import annotations

import re

import typer

from skydome.errors import ParameterError


def parse_resources(text: str | None) -> dict[str, float] | None:
    """``GPU=1,MEM=4e9`` -> ``{"GPU": 1.0, "MEM": 4e9}`` (Dask worker resources)."""
    if text is None:
        return None
    out = {}
    for part in text.split(","):
        m = re.fullmatch(r"\s*([A-Za-z_][\w-]*)\s*=\s*([0-9.eE+-]+)\s*", part)
        try:
            value = float(m.group(2)) if m else -1.0
        except ValueError:
            value = -1.0
        if not m or not value > 0:
            raise ParameterError(f"--resources {text} must be NAME=AMOUNT[,...], e.g. GPU=1")
        out[m.group(1)] = value
    return out


def register(app: typer.Typer) -> None:
    @app.command()
    def batch(
        spec: str = typer.Argument(..., help="The spec: a .toml or .yaml file."),
        out: str = typer.Option(
            "batch-out", "-o", "--out", help="Folder of the files and the manifest."
        ),
        workers: int = typer.Option(
            None,
            "--workers",
            help="Dask worker processes of a local cluster (default: the CPU count); 0 runs "
            "in this process (as --serial).",
        ),
        scheduler: str = typer.Option(
            None,
            "--scheduler",
            help="Address of a running Dask scheduler (tcp://host:8786) instead of a local "
            "cluster.",
        ),
        resources: str = typer.Option(
            None,
            "--resources",
            help="What each job needs of a worker, e.g. GPU=1 (Dask worker resources; a "
            "local cluster's workers get as much each).",
        ),
        serial: bool = typer.Option(
            False, "--serial", help="Render in this process, one job after another (no Dask)."
        ),
        retries: int = typer.Option(
            2, "--retries", help="Reruns of a job whose task failed on a worker (0..10)."
        ),
        dry_run: bool = typer.Option(
            False, "--dry-run", help="Check the spec and list the jobs; render nothing."
        ),
    ) -> None:
        """Render a spec's skies (places x times x weathers x clouds x cameras; or Sun
        elevations x azimuths) into a folder, with a manifest in Parquet and CSV (the
        parameters, the illuminance at the ground, the Sun's place, the sky's 9 spherical
        harmonics, timings, failures). Complete jobs (by the checksums in the manifest)
        are skipped: run it again to finish an interrupted batch."""
        from pathlib import Path

        from rich.console import Console

        from skydome.batch import expand_jobs, load_spec, render_many
        from skydome.cli.parsing import check_int

        # everything is checked before anything is made
        parsed = load_spec(spec)
        if workers is not None:
            check_int("--workers", workers, 0, 4096)
        check_int("--retries", retries, 0, 10)
        needs = parse_resources(resources)
        if (serial or workers == 0) and (scheduler is not None or needs is not None):
            raise ParameterError("--serial runs in this process: no --scheduler or --resources")
        if scheduler is not None and workers is not None:
            raise ParameterError("--scheduler uses its cluster's workers: drop --workers")
        folder = Path(out).expanduser()
        if folder.exists() and not folder.is_dir():
            raise ParameterError(f"--out {out}: it is a file, not a folder")
        jobs = expand_jobs(parsed)
        console = Console(soft_wrap=True, stderr=True)
        if dry_run:
            for job in jobs:
                typer.echo(job.name)
            console.print(f"{len(jobs)} jobs; nothing rendered (--dry-run)")
            return
        result = render_many(
            jobs, folder, workers=workers, scheduler=scheduler, serial=serial,
            resources=needs, retries=retries,
        )  # fmt: skip
        console.print(
            f"{len(jobs)} jobs: {result.rendered} rendered ({len(result.failed)} failed), "
            f"{result.skipped} complete before; {result.wall_s:.1f} s; manifest "
            + ", ".join(str(p) for p in result.manifest or [folder / "manifest.csv"])
        )
        for row in result.failed[:10]:
            console.print(f"failed: {row['job']}: {row['error']}")
        if result.failed:
            raise typer.Exit(1)
