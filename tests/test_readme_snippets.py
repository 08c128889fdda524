"""Every code example in README.md runs: each ```python block, and each `skydome ...` line of
its ```sh blocks.

The blocks are read from the README itself, so an example that drifts from the API (an
undefined name, a renamed argument, a shape the renderer refuses) fails here. Python blocks
run in a fresh namespace, compiled with their README line numbers so that a traceback points
at the README line; files they write go to a temporary directory.
"""

from __future__ import annotations

import re
import shlex
import time
from pathlib import Path

import numpy as np
import pytest

README = Path(__file__).parents[1] / "README.md"
_FENCE = re.compile(r"^```(\w*)\s*$")


def fenced_blocks(text: str, language: str) -> list[tuple[int, str]]:
    """(first line number, source) of every ```language fenced block of a Markdown text;
    line numbers are 1-based and count the line after the opening fence."""
    blocks: list[tuple[int, str]] = []
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        m = _FENCE.match(lines[i])
        if m is None:
            i += 1
            continue
        end = next(
            (j for j in range(i + 1, len(lines)) if lines[j].strip() == "```"),
            len(lines),
        )
        if m.group(1) == language:
            blocks.append((i + 2, "\n".join(lines[i + 1 : end]) + "\n"))
        i = end + 1
    return blocks


PYTHON_BLOCKS = fenced_blocks(README.read_text(encoding="utf-8"), "python")
SH_BLOCKS = fenced_blocks(README.read_text(encoding="utf-8"), "sh")


def test_readme_has_the_expected_examples():
    # Guards the extraction itself: the README has three Python examples (library,
    # astronomy, precomputed renderer) and a block of `skydome` command lines. A broken
    # fence regex would otherwise pass every parametrized test below by finding nothing.
    assert len(PYTHON_BLOCKS) >= 3
    assert sum(line.startswith("skydome ") for _, b in SH_BLOCKS for line in b.splitlines()) >= 8


@pytest.mark.parametrize(
    "line, source", PYTHON_BLOCKS, ids=[f"README.md:{line}" for line, _ in PYTHON_BLOCKS]
)
def test_python_snippet_runs(line, source, tmp_path, monkeypatch):
    from skydome.core.frame import Frame

    monkeypatch.chdir(tmp_path)  # the snippets write files (sky.png, ...) to the cwd
    code = compile("\n" * (line - 1) + source, str(README), "exec")
    namespace: dict[str, object] = {"__name__": "__readme__"}
    exec(code, namespace)  # raises -> the test fails with the README's line numbers
    # Every frame a snippet renders is a real image in absolute units: finite, with
    # non-negative luminance (negative RGB components are out-of-gamut colours and allowed).
    for name, value in namespace.items():
        if isinstance(value, Frame):
            assert np.all(np.isfinite(value.data)), name
            assert np.all(value.luminance >= 0.0), name
            assert float(value.luminance.max()) > 0.0, name


#: Commands measured to take more than 10 s on the 2-core llvmpipe machine (prefix of the
#: command line after "skydome" -> the measurement). They are not run; their options are
#: still checked by parsing the line with --help added (Click rejects an unknown option
#: while parsing, before the eager --help prints and exits).
SLOW_COMMANDS: dict[str, str] = {
    "precompute --atmosphere hazy --orders 6": "21 s of CPU, 52 s wall (2 shared cores)",
    "timelapse --place Valletta --start 2018-03-01T00:00Z": "1441 frames: 49 s wall (2 cores)",
    # (its spec a path of the repository; tests/test_docs.py runs docs/examples/batch.sh)
    "batch docs/examples/batch_spec.toml": "a Dask cluster of 2 workers, 12 skies: ~40 s",
}
_OUTPUT_OPTIONS = ("-o", "--output")


def cli_examples() -> list[tuple[int, list[str]]]:
    """(README line, argv after "skydome") of every `skydome ...` line in ```sh blocks;
    trailing comments are removed."""
    out = []
    for first, block in SH_BLOCKS:
        for k, raw in enumerate(block.splitlines()):
            words = shlex.split(raw, comments=True)
            if words[:1] == ["skydome"]:
                out.append((first + k, words[1:]))
    return out


def with_outputs_in(argv: list[str], directory: Path) -> list[str]:
    """argv with each output path (-o / --output) moved into ``directory``."""
    out = list(argv)
    for i, word in enumerate(out[:-1]):
        if word in _OUTPUT_OPTIONS:
            out[i + 1] = str(directory / Path(out[i + 1]).name)
    return out


def test_cli_examples_run(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    from skydome.cli.main import app

    monkeypatch.chdir(tmp_path)
    runner = CliRunner()
    failures, timings = [], []
    examples = cli_examples()
    for line, argv in examples:
        command = " ".join(argv)
        slow = any(command.startswith(prefix) for prefix in SLOW_COMMANDS)
        t0 = time.perf_counter()
        result = runner.invoke(app, with_outputs_in(argv, tmp_path) + (["--help"] if slow else []))
        timings.append((round(time.perf_counter() - t0, 2), line, command))
        if result.exit_code != 0:
            failures.append((line, command, result.exit_code, result.output, result.exception))
    assert not failures, failures
    # Each command that names outputs (and ran) wrote them, non-empty.
    for _, argv in examples:
        if any(" ".join(argv).startswith(prefix) for prefix in SLOW_COMMANDS):
            continue
        for i, word in enumerate(argv[:-1]):
            if word in _OUTPUT_OPTIONS:
                assert (tmp_path / Path(argv[i + 1]).name).stat().st_size > 0, argv
    print("seconds, README line, command:", sorted(timings, reverse=True))
