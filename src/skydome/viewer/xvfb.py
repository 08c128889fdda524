"""A virtual X display (Xvfb) for the viewer's window where there is no display: tests,
benchmarks and ``xvfb-run``-less scripts."""

from __future__ import annotations

import os
import subprocess
import time


def start_xvfb(screen: str = "1920x1080x24") -> tuple[subprocess.Popen, str]:
    """Start Xvfb on a free display number (it writes the number to a pipe) with one
    ``screen`` (WIDTHxHEIGHTxDEPTH); returns the process (terminate it when done) and the
    DISPLAY value. Raises OSError when Xvfb is not installed (apt-get install xvfb)."""
    read_fd, write_fd = os.pipe()
    proc = subprocess.Popen(
        ["Xvfb", "-displayfd", str(write_fd), "-screen", "0", screen, "-nolisten", "tcp"],
        pass_fds=(write_fd,),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    os.close(write_fd)
    number = b""
    deadline = time.monotonic() + 20.0
    with os.fdopen(read_fd, "rb") as pipe:
        while time.monotonic() < deadline and not number.endswith(b"\n"):
            chunk = pipe.read(1)
            if not chunk:
                break
            number += chunk
    if not number.strip():
        proc.kill()
        raise RuntimeError("Xvfb did not report a display number")
    return proc, f":{int(number)}"
