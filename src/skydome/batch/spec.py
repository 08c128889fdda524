"""A batch spec: what to render, as TOML or YAML, checked whole before anything is drawn.

Each list is an axis of the product (places x times x weathers x clouds x atmospheres x
cameras x sizes; or, without a place, Sun elevations x azimuths); a single value is an axis
of one. Every key is checked; a bad one raises :class:`~skydome.errors.ParameterError`
naming it (``sky.places[1]``, ``output.camera``), so the command line prints one line and
exits with status 2 before it renders anything or makes a folder.

.. code-block:: toml

    [sky]
    places = ["Valletta", [48.8566, 2.3522]]       # gazetteer names or [lat, lon(, elev m)]
    times = { start = "2018-06-21T05:00", stop = "2018-06-21T21:00", step = "2h" }
    weather = ["sunny", "fog"]                     # or "none"
    clouds = ["none", "fair"]
    [output]
    camera = ["equirect", { type = "perspective", fov = 60, look = "sun" }]
    size = "512x256"
    formats = ["exr", "png"]                       # exr, png, npy; or "none"

Times without an offset are each place's local time (its IANA zone in the gazetteer; UTC
for a place given by numbers, or everywhere with ``utc = true``), as on the command line. A
range ``{start, stop, step}`` runs from ``start`` to ``stop`` (included when it falls on a
step) every ``step`` (``30s``, ``10min``, ``2h``, ``1d``), in absolute time.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from skydome.astro.places import Place, parse_place, time_zone
from skydome.astro.time import to_time
from skydome.atmosphere.presets import PRESETS as ATMOSPHERES
from skydome.clouds.params import PRESETS as CLOUD_PRESETS
from skydome.core.cameras import CAMERAS, FOV_RANGE_DEG, PITCH_RANGE_DEG, YAW_RANGE_DEG
from skydome.display import TONEMAPS
from skydome.errors import ParameterError
from skydome.weather.params import PRESETS as WEATHER_PRESETS

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10: the same parser as the tomli package
    try:
        import tomli as tomllib
    except ModuleNotFoundError:
        tomllib = None

__all__ = [
    "FORMATS",
    "BatchSpec",
    "CameraSpec",
    "PlaceSpec",
    "load_spec",
    "parse_spec",
]

#: The files a job can write (by format name), "none" for no image: the manifest's
#: physical quantities, the spherical harmonics and the lights only.
FORMATS = ("exr", "png", "npy")
#: Where ``look`` can aim a perspective camera (:data:`skydome.sky.LOOKS`).
LOOKS = ("sun", "moon", "antisun", "zenith", "north", "east", "south", "west")
#: Most jobs one spec may expand to.
MAX_JOBS = 1_000_000
#: Longest side of a frame (pixels), as the command line's ``--size``.
MAX_SIDE = 16384

#: The keys of each table, with their other spelling (plural or singular).
SKY_KEYS = {
    "places": "place", "times": "time", "utc": None, "sun_elevation": None,
    "sun_azimuth": None, "atmosphere": "atmospheres", "weather": "weathers",
    "clouds": None, "bortle": None, "night": None,
}  # fmt: skip
OUTPUT_KEYS = {
    "camera": "cameras", "size": "sizes", "formats": "format", "exposure": None,
    "tonemap": None, "lighting_size": None, "lights": None,
}  # fmt: skip
CAMERA_KEYS = ("type", "fov", "yaw", "pitch", "look", "name")
TIME_RANGE_KEYS = ("start", "stop", "step")
_UNITS_S = {
    "s": 1.0, "sec": 1.0, "second": 1.0, "seconds": 1.0, "min": 60.0, "minute": 60.0,
    "minutes": 60.0, "m": 60.0, "h": 3600.0, "hour": 3600.0, "hours": 3600.0, "d": 86400.0,
    "day": 86400.0, "days": 86400.0,
}  # fmt: skip


@dataclass(frozen=True)
class PlaceSpec:
    """A place of the spec: ``label`` as given (a name, or "lat, lon"), the gazetteer
    ``Place`` it is, and ``zone``: the IANA zone its times are read in ("" for UTC)."""

    label: str
    place: Place
    zone: str

    @property
    def given_as_numbers(self) -> bool:
        return self.place.kind == "coordinates"


@dataclass(frozen=True)
class CameraSpec:
    """A camera of the spec: ``type`` (the command line's camera names), and for the
    perspective camera its ``fov`` (deg), ``yaw``/``pitch`` (deg; None: aimed by ``look``)
    and ``look``; ``name``: a label for file names (default: the type)."""

    type: str
    fov: float = 90.0
    yaw: float | None = None
    pitch: float | None = None
    look: str | None = None
    name: str = ""


@dataclass(frozen=True)
class BatchSpec:
    """A checked spec (see the module docstring): the axes, each a tuple.

    ``places`` with ``times`` (a tuple of UTC ISO strings per place, in the order of
    ``places``), or ``suns`` ((elevation, azimuth) in degrees) for the abstract mode.
    """

    places: tuple[PlaceSpec, ...]
    times: tuple[tuple[str, ...], ...]
    suns: tuple[tuple[float, float], ...]
    atmospheres: tuple[str, ...]
    weathers: tuple[str | None, ...]
    clouds: tuple[str | None, ...]
    bortles: tuple[int | str | None, ...]
    night: bool
    cameras: tuple[CameraSpec, ...]
    sizes: tuple[tuple[int, int], ...]
    formats: tuple[str, ...]
    exposure: str | float
    tonemap: str
    lighting_size: tuple[int, int]
    lights: int

    @property
    def abstract(self) -> bool:
        """True without places: Suns at elevations and azimuths."""
        return not self.places

    def count(self) -> int:
        """How many jobs the spec expands to."""
        where = sum(len(t) for t in self.times) if self.places else len(self.suns)
        return (
            where * len(self.atmospheres) * len(self.weathers) * len(self.clouds)
            * len(self.bortles) * len(self.cameras) * len(self.sizes)
        )  # fmt: skip


def load_spec(path: str | os.PathLike) -> BatchSpec:
    """Read and check a spec file: ``.toml`` (tomllib), or ``.yaml``/``.yml`` (PyYAML, if
    installed). Raises ParameterError (one line, naming the file or the key)."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in (".toml", ".yaml", ".yml"):
        raise ParameterError(f"spec {str(p)!r} must be a .toml, .yaml or .yml file")
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise ParameterError(f"spec {str(p)!r} cannot be read: {exc.strerror or exc}") from None
    if suffix == ".toml":
        if tomllib is None:
            raise ParameterError(f"spec {str(p)!r}: TOML needs Python 3.11 or tomli")
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise ParameterError(f"spec {str(p)!r} is not valid TOML: {exc}") from None
    else:
        try:
            import yaml  # optional: PyYAML
        except ImportError:
            raise ParameterError(
                f"spec {str(p)!r}: YAML needs PyYAML (pip install pyyaml), or write it in TOML"
            ) from None
        try:
            data = yaml.safe_load(text)
        except yaml.YAMLError as exc:
            first = " ".join(str(exc).split())
            raise ParameterError(f"spec {str(p)!r} is not valid YAML: {first}") from None
    return parse_spec(data)


def parse_spec(data: Any) -> BatchSpec:
    """Check a spec given as a mapping (a parsed TOML or YAML file; see the module
    docstring); raises ParameterError naming the first bad key."""
    if not isinstance(data, dict):
        raise ParameterError("spec must be a table with [sky] and [output]")
    _known("", data, {"sky": None, "output": None})
    sky = data.get("sky", {})
    output = data.get("output", {})
    for key, table in (("sky", sky), ("output", output)):
        if not isinstance(table, dict):
            raise ParameterError(f"spec key {key!r} must be a table")
    sky = _canonical("sky", sky, SKY_KEYS)
    output = _canonical("output", output, OUTPUT_KEYS)

    utc = _bool("sky.utc", sky.get("utc", False))
    night = _bool("sky.night", sky.get("night", True))
    places: tuple[PlaceSpec, ...] = ()
    times: tuple[tuple[str, ...], ...] = ()
    suns: tuple[tuple[float, float], ...] = ()
    has_place = "places" in sky
    has_sun = "sun_elevation" in sky or "sun_azimuth" in sky
    if has_place and has_sun:
        raise ParameterError(
            "spec key 'sky.sun_elevation': a place and a time set the Sun; give places and "
            "times, or sun_elevation (and sun_azimuth), not both"
        )
    if has_place:
        places = tuple(
            _place(f"sky.places[{i}]", v, utc) for i, v in enumerate(_axis("sky.places", sky))
        )
        if "times" not in sky:
            raise ParameterError("spec key 'sky.times' is missing: places need times")
        times = tuple(_times(sky["times"], p) for p in places)
    else:
        if "times" in sky:
            raise ParameterError("spec key 'sky.times' needs places (sky.places)")
        if "sun_elevation" not in sky:
            raise ParameterError(
                "spec key 'sky.places' is missing: give places and times, or sun_elevation"
            )
        els = [
            _number(f"sky.sun_elevation[{i}]", v, -90.0, 90.0)
            for i, v in enumerate(_axis("sky.sun_elevation", sky))
        ]
        azs = [
            _number(f"sky.sun_azimuth[{i}]", v, -360.0, 360.0)
            for i, v in enumerate(_axis("sky.sun_azimuth", sky, [180.0]))
        ]
        suns = tuple((e, a) for e in els for a in azs)
    atmospheres = tuple(
        _choice(f"sky.atmosphere[{i}]", v, ATMOSPHERES)
        for i, v in enumerate(_axis("sky.atmosphere", sky, ["earth"]))
    )
    weathers = tuple(
        _optional_choice(f"sky.weather[{i}]", v, WEATHER_PRESETS)
        for i, v in enumerate(_axis("sky.weather", sky, [None]))
    )
    clouds = tuple(
        _optional_choice(f"sky.clouds[{i}]", v, CLOUD_PRESETS)
        for i, v in enumerate(_axis("sky.clouds", sky, [None]))
    )
    bortles = tuple(
        _bortle(f"sky.bortle[{i}]", v, bool(places))
        for i, v in enumerate(_axis("sky.bortle", sky, ["auto"]))
    )
    cameras = tuple(
        _camera(f"output.camera[{i}]", v, bool(places))
        for i, v in enumerate(_axis("output.camera", output, ["equirect"]))
    )
    names = [c.name for c in cameras]
    if len(set(names)) != len(names):
        raise ParameterError(
            "spec key 'output.camera': two cameras share a name; give each a different 'name'"
        )
    sizes = tuple(
        _size(f"output.size[{i}]", v)
        for i, v in enumerate(_axis("output.size", output, ["512x256"]))
    )
    formats = _formats(_axis("output.formats", output, ["exr"]))
    exposure = output.get("exposure", "auto")
    if not (exposure == "auto" or _is_number(exposure)):
        raise ParameterError(
            f"spec key 'output.exposure' {exposure!r} must be \"auto\" or an EV100 number"
        )
    if exposure != "auto":
        exposure = _number("output.exposure", exposure, -20.0, 40.0)
    tonemap = _choice("output.tonemap", output.get("tonemap", "filmic"), TONEMAPS)
    lighting_size = _size("output.lighting_size", output.get("lighting_size", "256x128"))
    if lighting_size[0] != 2 * lighting_size[1] or not 16 <= lighting_size[0] <= 4096:
        raise ParameterError(
            "spec key 'output.lighting_size' must be a 2:1 map 16 to 4096 pixels wide"
        )
    lights = output.get("lights", 16)
    if isinstance(lights, bool) or not isinstance(lights, int) or not 1 <= lights <= 64:
        raise ParameterError(f"spec key 'output.lights' {lights!r} must be an integer 1 to 64")
    spec = BatchSpec(
        places=places, times=times, suns=suns, atmospheres=atmospheres, weathers=weathers,
        clouds=clouds, bortles=bortles, night=night, cameras=cameras, sizes=sizes,
        formats=formats, exposure=exposure, tonemap=tonemap, lighting_size=lighting_size,
        lights=lights,
    )  # fmt: skip
    if spec.count() > MAX_JOBS:
        raise ParameterError(f"spec expands to {spec.count()} jobs; at most {MAX_JOBS}")
    return spec


# ---------------------------------------------------------------------------- the checks


def _known(prefix: str, table: dict, keys: dict) -> None:
    valid = sorted(k for pair in keys.items() for k in pair if k)
    for key in table:
        if key not in valid:
            name = f"{prefix}{key}" if prefix else str(key)
            raise ParameterError(f"spec key {name!r} is unknown (valid: {', '.join(valid)})")


def _canonical(name: str, table: dict, keys: dict) -> dict:
    """``table`` with every key in its first spelling (``place`` -> ``places``)."""
    _known(f"{name}.", table, keys)
    out = {}
    for key, other in keys.items():
        given = [k for k in (key, other) if k and k in table]
        if len(given) == 2:
            raise ParameterError(f"spec keys '{name}.{key}' and '{name}.{other}': give one")
        if given:
            out[key] = table[given[0]]
    return out


def _axis(key: str, table: dict, default: list | None = None) -> list:
    """The values of an axis: a list as it is, one value as a list of one; never empty."""
    name = key.split(".", 1)[1]
    if name not in table:
        if default is None:
            raise ParameterError(f"spec key {key!r} is missing")
        return list(default)
    value = table[name]
    values = list(value) if isinstance(value, list) else [value]
    if not values:
        raise ParameterError(f"spec key {key!r} is an empty list")
    return values


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _number(key: str, value: Any, lo: float, hi: float) -> float:
    if not _is_number(value) or not math.isfinite(value) or not lo <= value <= hi:
        raise ParameterError(f"spec key {key!r} {value!r} must be a number from {lo:g} to {hi:g}")
    return float(value)


def _bool(key: str, value: Any) -> bool:
    if not isinstance(value, bool):
        raise ParameterError(f"spec key {key!r} {value!r} must be true or false")
    return value


def _choice(key: str, value: Any, valid) -> str:
    if not isinstance(value, str) or value not in valid:
        raise ParameterError(f"spec key {key!r} {value!r} must be one of {', '.join(valid)}")
    return value


def _optional_choice(key: str, value: Any, valid) -> str | None:
    if value is None or value == "none":
        return None
    return _choice(key, value, ["none", *valid])


def _bortle(key: str, value: Any, placed: bool) -> int | str | None:
    if value == "auto":
        return "auto"
    if value is None or value == "none":
        return None
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= 9:
        raise ParameterError(f'spec key {key!r} {value!r} must be "auto", "none" or 1 to 9')
    if not placed:
        raise ParameterError(f"spec key {key!r}: light pollution needs places and times")
    return value


def _place(key: str, value: Any, utc: bool) -> PlaceSpec:
    if isinstance(value, list):
        if not all(_is_number(v) for v in value):
            raise ParameterError(f"spec key {key!r} {value!r} must be [lat, lon(, elevation)]")
        label = ", ".join(f"{float(v):g}" for v in value)
        given: Any = tuple(float(v) for v in value)
    elif isinstance(value, str):
        label, given = value, value
    else:
        raise ParameterError(f"spec key {key!r} {value!r} must be a name or [lat, lon]")
    try:
        place = parse_place(given)
    except ParameterError as exc:
        raise ParameterError(f"spec key {key!r}: {exc}") from None
    zone = "" if utc or place.kind == "coordinates" or not place.timezone else place.timezone
    return PlaceSpec(label, place, zone)


def parse_duration(key: str, text: Any) -> float:
    """Seconds from a duration (``30s``, ``10min``, ``2h``, ``1d``; a number: seconds), > 0."""
    if _is_number(text):
        seconds = float(text)
    else:
        m = re.fullmatch(r"\s*(\d+(?:\.\d*)?|\.\d+)\s*([a-zA-Z]*)\s*", str(text))
        unit = (m.group(2).lower() or "s") if m else ""
        if not m or unit not in _UNITS_S:
            raise ParameterError(
                f"spec key {key!r} {text!r} must be a duration such as 30s, 10min, 2h or 1d"
            )
        seconds = float(m.group(1)) * _UNITS_S[unit]
    if not (math.isfinite(seconds) and seconds > 0):
        raise ParameterError(f"spec key {key!r} {text!r} must be longer than zero")
    return seconds


def _instant(key: str, text: Any, place: PlaceSpec):
    """One instant (skydome Time) of a spec's time text, in the place's zone."""
    if not isinstance(text, str):
        text = text.isoformat() if hasattr(text, "isoformat") else text  # TOML/YAML datetimes
    if not isinstance(text, str):
        raise ParameterError(f"spec key {key!r} {text!r} must be an ISO 8601 date and time")
    try:
        t = to_time(text, zone=time_zone(place.zone) if place.zone else None)
    except ParameterError as exc:
        raise ParameterError(f"spec key {key!r} ({place.label}): {exc}") from None
    if t.shape != ():
        raise ParameterError(f"spec key {key!r} {text!r} must be one instant")
    return t


def _times(value: Any, place: PlaceSpec) -> tuple[str, ...]:
    """The UTC instants (ISO 8601, ...Z, to the second) of ``sky.times`` at ``place``."""
    if isinstance(value, dict):
        _known("sky.times.", value, dict.fromkeys(TIME_RANGE_KEYS))
        for k in TIME_RANGE_KEYS:
            if k not in value:
                raise ParameterError(f"spec key 'sky.times.{k}' is missing (a range has {k})")
        t0 = _instant("sky.times.start", value["start"], place)
        t1 = _instant("sky.times.stop", value["stop"], place)
        step_s = parse_duration("sky.times.step", value["step"])
        # to the millisecond: a JD in float64 holds time to ~40 microseconds
        span_s = round((float(t1.jd_utc) - float(t0.jd_utc)) * 86400.0, 3)
        if span_s < 0:
            raise ParameterError(
                f"spec key 'sky.times.stop' {value['stop']!r} is before start "
                f"{value['start']!r} at {place.label}: the range is empty"
            )
        n = int(math.floor(span_s / step_s + 1e-6)) + 1
        if n > MAX_JOBS:
            raise ParameterError(f"spec key 'sky.times.step': {n} times; at most {MAX_JOBS}")
        jd = float(t0.jd_utc) + (step_s / 86400.0) * np.arange(n)
        return tuple(str(s) for s in to_time(jd).iso())
    values = value if isinstance(value, list) else [value]
    if not values:
        raise ParameterError("spec key 'sky.times' is an empty list")
    out = [str(_instant(f"sky.times[{i}]", v, place).iso()) for i, v in enumerate(values)]
    return tuple(dict.fromkeys(out))  # the same instant twice is one job


def _camera(key: str, value: Any, placed: bool) -> CameraSpec:
    if isinstance(value, str):
        value = {"type": value}
    if not isinstance(value, dict):
        raise ParameterError(f"spec key {key!r} {value!r} must be a camera name or a table")
    _known(f"{key}.", value, dict.fromkeys(CAMERA_KEYS))
    kind = _choice(f"{key}.type", value.get("type", "perspective"), tuple(CAMERAS))
    if kind != "perspective":
        extra = sorted(set(value) - {"type", "name"})
        if extra:
            raise ParameterError(f"spec key '{key}.{extra[0]}': only a perspective camera has it")
    fov = _number(f"{key}.fov", value.get("fov", 90.0), *FOV_RANGE_DEG)
    yaw = value.get("yaw")
    pitch = value.get("pitch")
    if yaw is not None:
        yaw = _number(f"{key}.yaw", yaw, *YAW_RANGE_DEG)
    if pitch is not None:
        pitch = _number(f"{key}.pitch", pitch, *PITCH_RANGE_DEG)
    look = value.get("look")
    if look is not None:
        look = _choice(f"{key}.look", look, LOOKS)
        if look == "moon" and not placed:
            raise ParameterError(f"spec key '{key}.look': the Moon needs places and times")
    name = value.get("name", kind)
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_-]{0,39}", name):
        raise ParameterError(
            f"spec key '{key}.name' {name!r} must be letters, digits, - and _ (1-40)"
        )
    return CameraSpec(kind, fov, yaw, pitch, look, name)


def _size(key: str, value: Any) -> tuple[int, int]:
    m = re.fullmatch(r"\s*(\d+)\s*[xX×]\s*(\d+)\s*", value) if isinstance(value, str) else None
    if not m:
        raise ParameterError(f"spec key {key!r} {value!r} must look like WIDTHxHEIGHT, 512x256")
    w, h = int(m.group(1)), int(m.group(2))
    if not (1 <= w <= MAX_SIDE and 1 <= h <= MAX_SIDE):
        raise ParameterError(f"spec key {key!r} {value!r}: sides of 1 to {MAX_SIDE} pixels")
    return w, h


def _formats(values: list) -> tuple[str, ...]:
    out = []
    for i, v in enumerate(values):
        _choice(f"output.formats[{i}]", v, (*FORMATS, "none"))
        if v not in out:
            out.append(v)
    if "none" in out:
        if len(out) > 1:
            raise ParameterError("spec key 'output.formats': \"none\" goes alone (no images)")
        return ()
    return tuple(out)
