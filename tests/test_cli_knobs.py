"""Atmosphere knob options of the command line: --albedo, --aod, --angstrom, --ozone on
``render``, ``illuminance`` and ``precompute`` (errors, help, effect, table cache)."""

import re

import numpy as np
import pytest

from tests.cli_helpers import run_cli

Y = np.array([0.2126, 0.7152, 0.0722])  # linear sRGB -> luminance


def run(*args, cwd=None, env=None):
    # In this process (the console script's own entry point): a subprocess per case costs
    # seconds of Python and NumPy start-up. test_cli.py keeps a few real subprocesses.
    return run_cli(*args, cwd=cwd, env=env)


COMMANDS = {
    "render": ["render", "--size", "8x8"],
    "illuminance": ["illuminance", "--sun-elevation", "10"],
    "precompute": ["precompute", "--orders", "1"],
}
BAD = [
    ("--albedo", "1.5", 0, 1),
    ("--albedo", "-0.2", 0, 1),
    ("--aod", "9", 0, 5),
    ("--aod", "-1", 0, 5),
    ("--angstrom", "3.5", -0.5, 3),
    ("--angstrom", "-2", -0.5, 3),
    ("--ozone", "900", 0, 700),
    ("--ozone", "-10", 0, 700),
]


def range_words(lo: float, hi: float) -> str:
    """The range as an error names it: '0 to 5' or '[0.0, 5.0]'."""
    return rf"({lo:g} to {hi:g}|\[{float(lo)}, {float(hi)}\])"


# Every bad value on render; on the other two commands one of each flag (same helper).
CASES = [("render", *bad) for bad in BAD] + [
    (command, *bad) for command in ("illuminance", "precompute") for bad in BAD[::2]
]


@pytest.mark.parametrize(("command", "flag", "value", "lo", "hi"), CASES)
def test_bad_knob_is_one_line_naming_flag_and_range(tmp_path, command, flag, value, lo, hi):
    out = tmp_path / "sky.png"
    extra = ["-o", str(out)] if command == "render" else []
    res = run(*COMMANDS[command], flag, value, *extra, cwd=tmp_path)
    assert res.returncode == 2, (res.stdout, res.stderr)
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert re.search(rf"{flag} =? ?{re.escape(value)}(\.0)? .*{range_words(lo, hi)}", lines[0])
    assert "Traceback" not in res.stderr and not out.exists()
    assert not list(tmp_path.iterdir())  # nothing written


def test_help_names_each_knob_with_its_range():
    from skydome.atmosphere import ALBEDO_RANGE, ANGSTROM_RANGE, AOD_550_RANGE, OZONE_DU_RANGE
    from skydome.cli.options import FLAGS

    KNOB_HELP = {FLAGS[k].names[0]: FLAGS[k].help for k in ("albedo", "aod", "angstrom", "ozone")}

    # The help's ranges (written out so the CLI starts without NumPy) are the library's.
    for flag, (lo, hi) in {
        "--albedo": ALBEDO_RANGE,
        "--aod": AOD_550_RANGE,
        "--angstrom": ANGSTROM_RANGE,
        "--ozone": OZONE_DU_RANGE,
    }.items():
        assert f"{lo:g}..{hi:g}" in KNOB_HELP[flag], flag
    assert "550 nm" in KNOB_HELP["--aod"] and "Dobson" in KNOB_HELP["--ozone"]
    for command in COMMANDS:
        res = run(command, "--help")
        assert res.returncode == 0, res.stderr
        for flag in KNOB_HELP:
            assert flag in res.stdout, (command, flag)


def render_npy(tmp_path, name: str, *knobs: str) -> np.ndarray:
    """A 64x32 equirect frame (cd/m^2), single scattering, 4 wavelengths, Sun at 30°."""
    out = tmp_path / f"{name}.npy"
    res = run(
        "render",
        "--model",
        "single",
        "--spectral",
        "fast",
        "--camera",
        "equirect",
        "--size",
        "64x32",
        "--sun-elevation",
        "30",
        "--exposure",
        "10",
        *knobs,
        "-o",
        str(out),
    )
    assert res.returncode == 0, res.stderr
    return np.load(out)


def test_render_knobs_act_on_the_frame(tmp_path):
    base = render_npy(tmp_path, "base")
    # Single scattering lights the Lambertian ground with the direct Sun only, seen over
    # 1.7 m of air: its radiance is proportional to the albedo (0.3 -> 0.6: x2, to 0.5 %).
    # (a grey ground: the default grassland's albedo depends on the light's colour)
    grey_ground = render_npy(tmp_path, "grey_ground", "--albedo", "0.3")
    nadir = (grey_ground[-1, :, :3] @ Y).mean()
    bright = render_npy(tmp_path, "albedo", "--albedo", "0.6")
    assert (bright[-1, :, :3] @ Y).mean() / nadir == pytest.approx(2.0, rel=5e-3)
    # AOD 0.1 (earth: OPAC clean continental, the preset's definition) -> 0.5, keeping the
    # type's spectrum (Ångström 1.39): Δτ = 0.53 at 440 nm to 0.32 at 650 nm. The Sun's beam
    # on the ground at 30° loses the luminance-weighted Beer-Lambert transmittance at air
    # mass 2 (beam_transmittance_ratio, which for the seeds' grey aerosol was exp(-Δτ / sin
    # 30°) = 0.372 from 0.005328): 0.4586 (measured 0.4592); 1 % bound.
    from skydome.atmosphere import preset
    from tests.test_atmosphere_knobs import beam_transmittance_ratio

    hazy = render_npy(tmp_path, "aod", "--aod", "0.5", "--albedo", "0.3")
    assert preset("earth").aod_550 == pytest.approx(0.1, rel=1e-6)
    expected = beam_transmittance_ratio(preset("earth"), preset("earth", aod_550=0.5), 2.0)
    assert (hazy[-1, :, :3] @ Y).mean() / nadir == pytest.approx(expected, rel=0.01)
    # At the same AOD at 550 nm, a steep Ångström exponent (2, fine smoke) dims blue more
    # than red on the way to the ground: the sunlit ground is redder than with grey haze.
    smoke = render_npy(tmp_path, "smoke", "--aod", "0.5", "--angstrom", "2")
    grey = render_npy(tmp_path, "grey", "--aod", "0.5", "--angstrom", "0")
    assert (
        smoke[-1, :, 2].mean() / smoke[-1, :, 0].mean()
        < grey[-1, :, 2].mean() / grey[-1, :, 0].mean()
    )
    # Ozone absorbs in the Chappuis band (500-700 nm): more ozone, a bluer zenith
    # (linear sRGB blue/red measured on the measured earth 1.85 at 0 DU, 1.98 at its 300 DU,
    # 2.13 at 600 DU; on the seeds' Earth it was 2.78 at 0 DU, 3.23 at 600 DU).
    no_ozone = render_npy(tmp_path, "o0", "--ozone", "0")
    much_ozone = render_npy(tmp_path, "o600", "--ozone", "600")

    def zenith_blue_red(frame):
        return frame[0, :, 2].mean() / frame[0, :, 0].mean()

    assert zenith_blue_red(no_ozone) < zenith_blue_red(base) < zenith_blue_red(much_ozone)


def cache_file(res) -> str:
    m = re.search(r"cache (\S+\.lut)", res.stdout)
    assert m, res.stdout
    return m.group(1)


def test_precompute_knobs_key_the_tables(tmp_path):
    # A knob at the preset's own value (earth: 300 DU) is the same atmosphere and reuses its
    # tables; another value is another atmosphere with its own tables.
    args = ["precompute", "--orders", "1", "--spectral", "fast"]
    first = run(*args)
    assert first.returncode == 0, first.stderr
    same = run(*args, "--ozone", "300")
    assert same.returncode == 0, same.stderr
    assert "loaded from the cache" in same.stdout and cache_file(same) == cache_file(first)
    other = run(*args, "--ozone", "250", "--aod", "0.1")
    assert other.returncode == 0, other.stderr
    assert "computed" in other.stdout and cache_file(other) != cache_file(first)


def test_visibility_sets_the_aerosol_and_the_json_reports_it(tmp_path):
    # --visibility (Koschmieder at the ground, 550 nm) on illuminance: the JSON's
    # visibility_km is the one asked for, and the hazier air (AOD 0.1 -> 0.27) passes less
    # light at a Sun 30 deg up; earth's own is 3.912 / its ground extinction, 74.4 km
    import json

    default = run("illuminance", "--sun-elevation", "30", "--json", cwd=tmp_path)
    hazy = run("illuminance", "--sun-elevation", "30", "--visibility", "20", "--json",
               cwd=tmp_path)  # fmt: skip
    assert default.returncode == 0 and hazy.returncode == 0, (default.stderr, hazy.stderr)
    a, b = json.loads(default.stdout), json.loads(hazy.stdout)
    assert a["visibility_km"] == pytest.approx(74.36, abs=0.01)
    assert b["visibility_km"] == pytest.approx(20.0, rel=1e-9)
    assert b["total_horizontal_lux"] < a["total_horizontal_lux"]


@pytest.mark.parametrize(
    "args, words",
    [
        (["--visibility", "1"], "1.9 km is the least"),
        (["--visibility", "500"], "outside the valid range 0.02 to 335 km"),
        (["--visibility", "10", "--aod", "0.2"], "give one of them"),
    ],
)
def test_bad_visibility_is_one_line(tmp_path, args, words):
    out = tmp_path / "sky.png"
    res = run("render", "--size", "8x8", *args, "-o", str(out), cwd=tmp_path)
    assert res.returncode == 2 and words in res.stderr, (res.returncode, res.stderr)
    assert len(res.stderr.strip().splitlines()) == 1 and not out.exists()
