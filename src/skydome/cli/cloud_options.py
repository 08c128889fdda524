"""The cloud flags of ``render``, ``timelapse`` and ``view``: one function per option, a
decorator that adds them all to a command (:func:`with_cloud_options`), and the
``CloudFlags`` that turns them into a ``Clouds`` (or None), with errors that name the flag."""

from __future__ import annotations

import functools
import inspect
import math
from dataclasses import dataclass, fields

import typer

from skydome.errors import ParameterError


def clouds_option():
    return typer.Option(
        None,
        "--clouds",
        help="Clouds of a preset: fair | overcast | storm | cirrus | clear (default: none).",
    )


def coverage_option():
    return typer.Option(None, "--coverage", help="Cloud coverage 0..1 (with --clouds).")


def cloud_base_option():
    return typer.Option(None, "--cloud-base", help="Cloud base above the ground, metres.")


def cloud_thickness_option():
    return typer.Option(None, "--cloud-thickness", help="Cloud layer depth, metres.")


def cloud_type_option():
    return typer.Option(
        None, "--cloud-type", help="stratus | stratocumulus | cumulus | cumulonimbus."
    )


def cirrus_option():
    return typer.Option(None, "--cirrus", help="Cirrus sheet coverage 0..1 (with --clouds).")


def wind_option():
    return typer.Option(
        None,
        "--wind",
        help="SPEED,FROM: wind speed (m/s) and the direction it blows from (degrees, 90 = "
        "from the east), carrying the clouds (time-lapses animate them).",
    )


def cloud_seed_option():
    return typer.Option(None, "--cloud-seed", help="Seed of the cloud noise and weather map.")


def weather_option():
    return typer.Option(
        None,
        "--weather",
        help="A weather-map image (PNG/JPEG/TIFF: R coverage, G type, B rain, A cirrus; or "
        "grey = coverage) instead of a generated one.",
    )


def parse_wind(text: str) -> tuple[float, float]:
    """'SPEED,FROM' -> (east, north) velocity in m/s (meteorological: FROM is where the wind
    comes from, degrees from north through east)."""
    parts = text.split(",")
    try:
        speed, frm = (float(p) for p in parts)
    except ValueError:
        raise ParameterError(f"--wind must be SPEED,FROM (m/s, degrees), got {text!r}") from None
    if not (math.isfinite(speed) and 0 <= speed <= 200 and math.isfinite(frm)):
        raise ParameterError(f"--wind speed must be within [0, 200] m/s, got {text!r}")
    a = math.radians(frm)
    return (-speed * math.sin(a), -speed * math.cos(a))


@dataclass
class CloudFlags:
    """The cloud flags as given (None: not given)."""

    preset: str | None = None
    coverage: float | None = None
    base_m: float | None = None
    thickness_m: float | None = None
    cloud_type: str | None = None
    cirrus: float | None = None
    wind: str | None = None
    seed: int | None = None
    weather: str | None = None

    def clouds(self):
        """The ``Clouds`` the flags describe, or None without --clouds (other cloud flags
        then are an error)."""
        named = {
            "--coverage": self.coverage, "--cloud-base": self.base_m,
            "--cloud-thickness": self.thickness_m, "--cloud-type": self.cloud_type,
            "--cirrus": self.cirrus, "--wind": self.wind, "--cloud-seed": self.seed,
            "--weather": self.weather,
        }  # fmt: skip
        if self.preset is None:
            given = [flag for flag, v in named.items() if v is not None]
            if given:
                raise ParameterError(f"{given[0]} needs --clouds PRESET (e.g. --clouds fair)")
            return None
        from skydome.clouds.params import PRESETS, Clouds
        from skydome.errors import check_choice

        check_choice("--clouds", self.preset, PRESETS, "cloud preset")
        if self.cloud_type is not None:
            from skydome.clouds.params import CLOUD_TYPES

            check_choice("--cloud-type", self.cloud_type, CLOUD_TYPES, "cloud type")
        kwargs = {
            "coverage": self.coverage, "base_m": self.base_m, "thickness_m": self.thickness_m,
            "cloud_type": self.cloud_type, "cirrus": self.cirrus,
        }  # fmt: skip
        kwargs = {k: v for k, v in kwargs.items() if v is not None}
        if self.wind is not None:
            kwargs["wind_m_s"] = parse_wind(self.wind)
        if self.seed is not None:
            kwargs["seed"] = self.seed
        if self.weather is not None:
            from skydome.clouds.weather import WeatherMap

            kwargs["weather"] = WeatherMap.from_image(self.weather, tile_km=40.0)
        return Clouds(self.preset, **kwargs)


#: (parameter name, type, option) of each cloud flag, in the order of CloudFlags' fields.
CLOUD_FLAGS = (
    ("clouds", str, clouds_option),
    ("coverage", float, coverage_option),
    ("cloud_base", float, cloud_base_option),
    ("cloud_thickness", float, cloud_thickness_option),
    ("cloud_type", str, cloud_type_option),
    ("cirrus", float, cirrus_option),
    ("wind", str, wind_option),
    ("cloud_seed", int, cloud_seed_option),
    ("weather", str, weather_option),
)


def with_cloud_options(command):
    """Give a typer command the cloud flags: they are added after its own options, and the
    command receives them as one keyword argument ``cloud_flags`` (a CloudFlags)."""
    signature = inspect.signature(command)
    own = [p for p in signature.parameters.values() if p.name != "cloud_flags"]
    added = [
        inspect.Parameter(name, inspect.Parameter.POSITIONAL_OR_KEYWORD, default=option(),
                          annotation=kind)
        for name, kind, option in CLOUD_FLAGS
    ]  # fmt: skip
    names = [name for name, _, _ in CLOUD_FLAGS]
    field_names = [f.name for f in fields(CloudFlags)]

    @functools.wraps(command)
    def run(*args, **kwargs):
        given = {field: kwargs.pop(name) for name, field in zip(names, field_names, strict=True)}
        return command(*args, cloud_flags=CloudFlags(**given), **kwargs)

    run.__signature__ = signature.replace(parameters=own + added)
    return run
