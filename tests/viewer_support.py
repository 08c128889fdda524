"""An X display for the viewer's window tests: the one in $DISPLAY when glfw can open it,
else a private Xvfb (started here, stopped at the end); the tests are skipped, with the
reason, only where neither can be had."""

from __future__ import annotations

import os
import shutil
import subprocess

import pytest

from skydome.viewer.xvfb import start_xvfb


def _glfw_works() -> bool:
    """Whether glfw can open the display in $DISPLAY (tested in a child process: a failed
    glfw.init leaves the library in a state this process could not retry from)."""
    import sys

    code = "import glfw, sys; sys.exit(0 if glfw.init() else 1)"
    try:
        return subprocess.run([sys.executable, "-c", code], timeout=30).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


@pytest.fixture(scope="session")
def x_display():
    """A DISPLAY value glfw can open (skips when there is none and no Xvfb)."""
    pytest.importorskip("glfw", reason="the viewer's window needs glfw (pip install glfw)")
    if os.environ.get("DISPLAY") and _glfw_works():
        yield os.environ["DISPLAY"]
        return
    if shutil.which("Xvfb") is None:
        pytest.skip("no X display and no Xvfb (apt-get install xvfb) for the viewer's window")
    proc, display = start_xvfb()
    old = os.environ.get("DISPLAY")
    os.environ["DISPLAY"] = display
    try:
        yield display
    finally:
        if old is None:
            os.environ.pop("DISPLAY", None)
        else:
            os.environ["DISPLAY"] = old
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
