"""`Sky(sun_disk=False)` / `--no-sun-disk`: an environment map without the Sun's disk (for a
renderer that lights the scene with its own Sun lamp), the air lit all the same."""

from __future__ import annotations

import numpy as np
import pytest

from skydome.errors import ParameterError


@pytest.mark.gl
@pytest.mark.parametrize("place", [None, "valletta"])
def test_the_disk_alone_leaves(place):
    # looking at the Sun over 10 deg: with its disk the brightest pixel is the disk's
    # (~1e9 cd/m^2), without it the aureole's (< 1e6); every pixel outside the disk (its
    # 0.27 deg radius and the pixel's 0.16 deg) is the same to the bit
    from skydome import Sky

    where = {"sun_elevation_deg": 30.0} if place is None else {"place": place,
                                                                "time": "2021-06-21T10:00Z"}  # fmt: skip
    frames = {}
    for disk in (True, False):
        with Sky(sun_disk=disk, **where) as sky:
            camera = sky.camera("sun", fov_deg=10)
            frames[disk] = sky.render(camera, 64, 64, exposure=None).data[..., 1]
            x, y = np.meshgrid(np.arange(64) + 0.5, np.arange(64) + 0.5)
            dirs = np.asarray(camera.directions(x, y, 64, 64)[0])[::-1]
            sun = sky.state.sun
    e, a = np.radians(sun.elevation_deg), np.radians(sun.azimuth_deg)
    towards = np.array([np.sin(a) * np.cos(e), np.cos(a) * np.cos(e), np.sin(e)])
    angle = np.degrees(np.arccos(np.clip(dirs @ towards, -1.0, 1.0)))
    outside = angle > 0.27 + 0.2
    assert frames[True].max() > 1e8 and frames[False].max() < 1e6
    assert np.array_equal(frames[True][outside], frames[False][outside])


def test_bad_settings_are_refused():
    from skydome.description import SkyDescription

    with pytest.raises(ParameterError, match="single-scattering model draws its Sun"):
        SkyDescription(model="single", sun_disk=False)
    with pytest.raises(ParameterError, match="sun_disk must be True or False"):
        SkyDescription(sun_disk="no")


@pytest.mark.gl
def test_cli_no_sun_disk(tmp_path):
    # the flag renders; with the single model: one line, status 2, nothing written
    from tests.cli_helpers import run_cli

    out = tmp_path / "env.png"
    r = run_cli("render", "--sun-elevation", "30", "--no-sun-disk", "--size", "32x18",
                "-o", str(out))  # fmt: skip
    assert r.returncode == 0 and out.exists(), r.stderr
    bad = tmp_path / "bad.png"
    r = run_cli("render", "--model", "single", "--sun-elevation", "30", "--no-sun-disk",
                "--size", "32x18", "-o", str(bad))  # fmt: skip
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and not bad.exists()
