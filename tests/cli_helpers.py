"""Running the command line in the test process: the same entry point as the console script
(``skydome.cli.main.run``), without starting a Python and importing NumPy per call."""

from __future__ import annotations

import contextlib
import io
import os
from dataclasses import dataclass


@dataclass
class Result:
    returncode: int
    stdout: str
    stderr: str


def run_cli(*args: str, cwd=None, env: dict[str, str] | None = None) -> Result:
    """Run ``skydome ARGS`` in this process, as ``subprocess.run(..., text=True)`` would
    report it: exit status, stdout and stderr. ``env`` replaces the environment for the call."""
    from skydome.cli.main import run

    out, err = io.StringIO(), io.StringIO()
    old_cwd, old_env = os.getcwd(), dict(os.environ)
    code = 0
    try:
        if cwd is not None:
            os.chdir(cwd)
        if env is not None:
            os.environ.clear()
            os.environ.update(env)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                run([str(a) for a in args])
            except SystemExit as exc:
                code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    finally:
        os.chdir(old_cwd)
        os.environ.clear()
        os.environ.update(old_env)
    return Result(code, out.getvalue(), err.getvalue())


@dataclass
class ProcessResult(Result):
    """A ``python -m skydome`` process: also its wall time (s) and peak resident memory
    (MiB, the kernel's ru_maxrss of that one process)."""

    seconds: float = 0.0
    max_rss_mib: float = 0.0


def cli_env() -> dict[str, str]:
    """This environment with this checkout's ``src`` first on PYTHONPATH, so that a child
    ``python -m skydome`` runs the code under test (not an installed copy)."""
    import pathlib

    src = str(pathlib.Path(__file__).resolve().parents[1] / "src")
    rest = os.environ.get("PYTHONPATH", "")
    return {**os.environ, "PYTHONPATH": src + (os.pathsep + rest if rest else "")}


# Starts the command and reports its wall time and peak RSS as JSON into the file argv[1].
# A small process of its own: a child's ru_maxrss counts the memory of the process it was
# forked from (Linux records the old address space's peak at exec), so a child forked from
# the test process would report the test process's size; from this one, ~10 MiB at most.
_MEASURE = """
import json, os, subprocess, sys, time
t0 = time.perf_counter()
child = subprocess.Popen(sys.argv[2:])
_, status, usage = os.wait4(child.pid, 0)
child.returncode = os.waitstatus_to_exitcode(status)
with open(sys.argv[1], "w") as f:
    json.dump({"rc": child.returncode, "seconds": time.perf_counter() - t0,
               "max_rss_kib": usage.ru_maxrss}, f)
"""


def run_process(*args: str, cwd=None, timeout: float = 120.0) -> ProcessResult:
    """Run ``python -m skydome ARGS`` as a real process and measure it: wall time from start
    to exit and its own peak resident memory (``os.wait4``'s ru_maxrss, taken by a small
    parent process: see _MEASURE). AssertionError (and the process killed) after
    ``timeout`` seconds."""
    import json
    import subprocess
    import sys
    import tempfile

    cmd = [sys.executable, "-m", "skydome", *[str(a) for a in args]]
    with tempfile.TemporaryDirectory() as tmp:
        report = os.path.join(tmp, "measure.json")
        measure = [sys.executable, "-c", _MEASURE, report, *cmd]
        proc = subprocess.Popen(
            measure, cwd=cwd, env=cli_env(), stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
            stderr=subprocess.PIPE, text=True, start_new_session=True,
        )  # fmt: skip
        try:
            out, err = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, 9)
            proc.communicate()
            raise AssertionError(
                f"skydome {' '.join(cmd[3:])} still ran after {timeout} s"
            ) from None
        with open(report) as f:
            m = json.load(f)
    return ProcessResult(m["rc"], out, err, m["seconds"], m["max_rss_kib"] / 1024.0)
