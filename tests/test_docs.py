"""The documentation site: every example in docs/examples/ runs and writes sane files, the
site builds with ``mkdocs build --strict`` (warnings are errors), and the generated CLI
reference (docs/cli.md) is current.

The examples are the how-to pages' code (the pages include the files with pymdownx.snippets),
so a page cannot show code that does not run. They run as the user would run them, each in
its own process (``python example.py OUT`` or ``bash example.sh`` with ``$OUT``), sharing
the test session's table cache, at small sizes (a few seconds each on llvmpipe).
"""

from __future__ import annotations

import importlib.util
import json
import os
import re
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
EXAMPLES = DOCS / "examples"

#: Each example -> the files (globs under its output folder) it must write, at least one
#: match per glob. A new example must be listed here (test_every_example_is_listed).
EXPECTED = {
    "tour.py": ["tour-sunset.png", "tour-sunset.exr", "tour-night-allsky.png", "tour-sun5.*"],
    "tour_cli.sh": ["cli-sunset.png", "cli-sunset.exr", "cli-sun8.png"],
    "place_and_time.py": ["place-moon.png", "place-moon.exr", "place-east.png", "place-1200.png"],
    "blender_cli.sh": ["sky.exr", "sky.hdr", "sky-preview.png", "sky-black-ground.exr"],
    "blender_hdri.py": ["sky-no-sun.exr", "sky-with-sun.exr", "blender-settings.json"],
    "timelapse.sh": ["dusk.mp4", "dusk-frames/frame_*.exr", "dusk-ev8/frame_*.png"],
    "eye_adaptation.py": ["eye-dusk-strip.png"],
    "aerial_perspective.py": ["aerial-composite.png", "aerial-composite.exr", "aerial-without.png"],
    "night_sky.py": ["night-allsky.png", "night-allsky.exr", "night-bortle8.png", "night-eye.png"],
    "atmospheres.py": ["atmosphere-earth-hazy-smoky.png"],
    "cie_sky.py": ["cie-sky-types.csv", "cie-sky-types.png"],
    "lighting.py": ["lighting.json", "lighting-sky.exr", "lighting-preview.png"],
    "batch.sh": ["batch/manifest.csv", "batch/manifest.parquet", "batch/*.exr", "batch/*.png"],
    "weather.py": [
        "weather-fog.png",
        "weather-fog-sea.png",
        "weather-rain.png",
        "weather-snow-dusk.png",
    ],
    "exposure_glare.sh": [
        "night-eye.png",
        "night-camera.png",
        "moon-center.png",
        "sunset-glare.png",
        "sunset.exr",
        "sunset-no-glare.png",
    ],
    "clouds.py": [
        "clouds-fair.png",
        "clouds-fair.exr",
        "clouds-overcast.png",
        "clouds-own-map.png",
    ],
}
EXAMPLE_FILES = sorted(p.name for p in EXAMPLES.glob("*") if p.suffix in (".py", ".sh"))


def _environment(out: Path, bin_dir: Path) -> dict[str, str]:
    """The examples' environment: this interpreter's skydome first on PATH (a shim, so a
    shell example runs the code under test), src/ importable, outputs to ``out``."""
    bin_dir.mkdir(exist_ok=True)
    shim = bin_dir / "skydome"
    shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m skydome "$@"\n')
    shim.chmod(shim.stat().st_mode | stat.S_IXUSR)
    env = dict(os.environ)  # carries the session's SKYDOME_CACHE (tests/conftest.py)
    env["PATH"] = f"{bin_dir}{os.pathsep}{env.get('PATH', '')}"
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"), env.get("PYTHONPATH")]))
    env["OUT"] = env["SKYDOME_EXAMPLES_OUT"] = str(out)
    return env


def _check_png(path: Path) -> None:
    from PIL import Image

    image = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64)
    assert image.ndim == 3 and min(image.shape[:2]) >= 8, (path, image.shape)
    # Not black, not flat: a sky image has lit pixels (> 10 of 255 somewhere) and structure.
    assert image.max() > 10.0, f"{path.name} is black"
    assert image.std() > 1.0, f"{path.name} is flat"


def _check_exr(path: Path) -> None:
    from skydome.io import read_exr
    from skydome.spectra import SRGB_LUMINANCE

    data, header = read_exr(path)
    assert np.all(np.isfinite(data)), f"{path.name} has NaN or Inf"
    luminance = data[..., :3] @ SRGB_LUMINANCE.astype(np.float32)
    assert luminance.max() > 0.0, f"{path.name} is black"
    assert np.mean(luminance >= 0.0) == 1.0, f"{path.name} has negative luminance"


def _check_hdr(path: Path) -> None:
    from skydome.io import read_hdr

    data, _ = read_hdr(path)  # cd/m^2
    assert np.all(np.isfinite(data)) and data.max() > 0.0, f"{path.name} is black or not finite"


def _check_mp4(path: Path) -> None:
    import imageio_ffmpeg

    reader = imageio_ffmpeg.read_frames(str(path))
    meta = next(reader)
    w, h = meta["size"]
    first = np.frombuffer(next(reader), dtype=np.uint8).reshape(h, w, 3)
    reader.close()
    assert first.max() > 10, f"{path.name}'s first frame is black"


CHECKS = {".png": _check_png, ".exr": _check_exr, ".hdr": _check_hdr, ".mp4": _check_mp4}


def test_every_example_is_listed_and_shown():
    # An example not in EXPECTED would run unchecked; one no page includes is dead code.
    assert sorted(EXPECTED) == EXAMPLE_FILES
    pages = "\n".join(p.read_text(encoding="utf-8") for p in DOCS.rglob("*.md"))
    for name in EXAMPLE_FILES:
        assert f'--8<-- "docs/examples/{name}"' in pages, f"no page includes {name}"


@pytest.mark.parametrize("name", EXAMPLE_FILES)
def test_example_runs_and_writes_sane_files(name, tmp_path):
    out = tmp_path / "out"
    env = _environment(out, tmp_path / "bin")
    script = EXAMPLES / name
    cmd = ["bash", str(script)] if script.suffix == ".sh" else [sys.executable, str(script)]
    if script.suffix == ".py":
        cmd.append(str(out))
    proc = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"{name} failed:\n{proc.stdout[-2000:]}\n{proc.stderr[-4000:]}"
    for pattern in EXPECTED[name]:
        paths = sorted(out.glob(pattern))
        assert paths, f"{name} wrote no {pattern} (it wrote {sorted(os.listdir(out))})"
        for path in paths:
            assert path.stat().st_size > 0, path
            check = CHECKS.get(path.suffix)
            if check is not None:
                check(path)
    if name == "blender_hdri.py":
        _check_blender_settings(json.loads((out / "blender-settings.json").read_text()))


def _check_blender_settings(s: dict) -> None:
    """The HDRI is in absolute units: its cosine-weighted upper hemisphere is the diffuse
    horizontal illuminance of the tables, and the disk's own light is the direct beam used
    for the Sun lamp (measured 0.06 % and 0.16 % apart; 2 % allows for the 512x256 map's
    quadrature and the 2-degree camera's pixels)."""
    assert s["world_strength"] == pytest.approx(1.0 / 683.0, rel=1e-12)
    assert s["diffuse_horizontal_lux_from_map"] == pytest.approx(
        s["diffuse_horizontal_lux"], rel=0.02
    )
    assert s["direct_normal_lux_from_disk"] == pytest.approx(s["direct_normal_lux"], rel=0.02)
    # The lamp's strength x colour carries the beam's luminance: E / 683 W/m^2.
    from skydome.spectra import SRGB_LUMINANCE

    lum = float(np.asarray(s["sun_colour_linear_rgb"]) @ SRGB_LUMINANCE)
    assert s["sun_strength_w_m2"] * lum * 683.0 == pytest.approx(s["direct_normal_lux"], rel=1e-9)
    assert max(s["sun_colour_linear_rgb"]) == pytest.approx(1.0)
    assert 0.5 < s["sun_angle_deg"] < 0.56  # the Sun's 0.52-0.54 deg over the year


def test_command_lines_on_the_pages_are_the_readmes():
    # Single `skydome ...` lines in the pages' sh blocks (outside the included examples) are
    # copies of the README's, which tests/test_readme_snippets.py runs: a line that drifts
    # from them would be untested.
    from tests.test_readme_snippets import SH_BLOCKS, fenced_blocks

    def command(line: str) -> str:
        return " ".join(line.split(" #")[0].split())  # without a trailing comment

    readme = {command(line) for _, block in SH_BLOCKS for line in block.splitlines()}
    seen = 0
    for page in DOCS.rglob("*.md"):
        for _, block in fenced_blocks(page.read_text(encoding="utf-8"), "sh"):
            for line in block.splitlines():
                if line.startswith("skydome "):
                    seen += 1
                    assert command(line) in readme, f"{page.relative_to(ROOT)}: {line}"
    assert seen >= 10


def test_cli_reference_is_current():
    spec = importlib.util.spec_from_file_location(
        "make_cli_docs", ROOT / "tools" / "make_cli_docs.py"
    )
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    text = tool.render()
    assert (DOCS / "cli.md").read_text(encoding="utf-8") == text, (
        "docs/cli.md is out of date: run python tools/make_cli_docs.py"
    )
    # It documents every command, each with its options table.
    from skydome.cli.main import COMMAND_MODULES

    commands = re.findall(r"^## skydome (\w+)$", text, flags=re.MULTILINE)
    assert len(commands) >= len(COMMAND_MODULES)
    assert {"render", "timelapse", "ephemeris"} <= set(commands)


def test_doctest_fences():
    spec = importlib.util.spec_from_file_location(
        "griffe_docstrings", ROOT / "tools" / "griffe_docstrings.py"
    )
    if importlib.util.find_spec("griffe") is None:
        pytest.skip("griffe (mkdocstrings-python) is not installed: pip install '.[docs]'")
    ext = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ext)
    text = (
        "Use it:\n>>> x = [1][:1]\n>>> x\n[1]\n\nSee :class:`~skydome.scene.Sky` and :func:`f`::\n"
    )
    assert ext.markdown_docstring(text) == (
        "Use it:\n\n```pycon\n>>> x = [1][:1]\n>>> x\n[1]\n```\n\nSee `Sky` and `f`:\n"
    )


def test_site_builds_strict(tmp_path):
    missing = [
        m
        for m in ("mkdocs", "material", "mkdocstrings", "mkdocstrings_handlers.python")
        if importlib.util.find_spec(m.split(".")[0]) is None
    ]
    if missing:
        pytest.skip(f"{', '.join(missing)} not installed: pip install '.[docs]'")
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "mkdocs",
            "build",
            "--strict",
            "-f",
            str(ROOT / "mkdocs.yml"),
            "-d",
            str(tmp_path / "site"),
        ],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-6000:]
    site = tmp_path / "site"
    # The pages are there, with the examples' code pasted in and the API rendered.
    tour = (site / "tour.html").read_text(encoding="utf-8")
    assert "write_outputs" in tour and "--8&lt;--" not in tour
    api = (site / "api" / "scene.html").read_text(encoding="utf-8")
    assert "skydome.sky.Sky" in api and "def render" not in api  # rendered, not source
    assert (site / "gallery" / "night-milky-way.png").exists()


@pytest.mark.gl
def test_the_example_notebook_runs_and_shows_its_outputs(tmp_path):
    # docs/examples/notebook.ipynb run in a fresh kernel (tools/run_notebooks.py, what `make
    # docs` does) gives a page with its three pictures (the equirect repr, the Moon, the
    # HDRI) that are pictures, and the HDRI's black ground (0.0 cd/m^2 below the horizon)
    pytest.importorskip("nbclient", reason="the docs extra runs the notebooks")
    pytest.importorskip("ipykernel", reason="the docs extra runs the notebooks")
    from PIL import Image

    from tests.tools_module import load_tool

    assert load_tool("run_notebooks").main(["notebook.ipynb", "--out", str(tmp_path)]) == 0
    text = (tmp_path / "notebook.md").read_text()
    assert "below the horizon: max 0.0 cd/m^2" in text
    assert "*(a live widget: run the notebook to look around)*" in text
    pictures = sorted(tmp_path.glob("notebook-*.png"))
    assert len(pictures) == 3
    for p in pictures:
        assert np.asarray(Image.open(p).convert("RGB")).std() > 2.0, p
        assert f"]({p.name})" in text
