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
