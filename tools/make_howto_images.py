"""Run the how-to examples that have no pictures of their own in the gallery and keep what
they write as the pages' images: docs/gallery/howto-*.png.

    python tools/make_howto_images.py

Each example runs as a user runs it (``python docs/examples/X.py OUT`` or ``bash X.sh`` with
``$OUT``), so the images are exactly the pages' code's output.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "docs" / "examples"
GALLERY = ROOT / "docs" / "gallery"

#: example -> (files it writes, joined side by side in this order) -> gallery name.
PICTURES = {
    "place_and_time.py": {"howto-place-and-time.png": ["place-moon.png", "place-east.png"]},
    "timelapse.sh": {"howto-timelapse-ev8.png": ["dusk-ev8/frame_*.png"]},
    "lighting.py": {
        "howto-lighting.png": ["lighting-preview.png"],
        "howto-lighting-cube.png": ["lighting-cube.png"],
    },
}


def run(example: str, out: Path) -> None:
    env = {
        **os.environ,
        "OUT": str(out),
        "PATH": f"{Path(sys.executable).parent}:{os.environ['PATH']}",
    }
    path = EXAMPLES / example
    cmd = ["bash", str(path)] if path.suffix == ".sh" else [sys.executable, str(path), str(out)]
    subprocess.run(cmd, check=True, env=env, cwd=out)


def strip(files: list[Path], height: int = 180) -> np.ndarray:
    """The images side by side at one height (RGB)."""
    parts = []
    for f in files:
        im = Image.open(f).convert("RGB")
        w = round(im.width * height / im.height)
        parts.append(np.asarray(im.resize((w, height), Image.Resampling.LANCZOS)))
    return np.concatenate(parts, axis=1)


def main() -> None:
    for example, pictures in PICTURES.items():
        with tempfile.TemporaryDirectory() as tmp:
            out = Path(tmp)
            run(example, out)
            for name, patterns in pictures.items():
                files = [f for p in patterns for f in sorted(out.glob(p))]
                picture = Image.open(files[0]) if len(files) == 1 else Image.fromarray(strip(files))
                picture.save(GALLERY / name)
                print(f"docs/gallery/{name}: {', '.join(f.name for f in files)}")


if __name__ == "__main__":
    main()
