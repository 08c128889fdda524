"""The command line's shared flags, declared once.

``render``, ``timelapse`` and ``view`` (and, in part, ``illuminance`` and ``precompute``)
take the same flags for the place, the Sun, the air, the night and the clouds. Each flag is
declared here once (:data:`FLAGS`), in groups (:data:`GROUPS`); ``@with_flags("place",
"air", ...)`` adds the groups' options to a command, which receives them as one argument,
``flags`` (attribute access: ``flags.place``, ``flags.aod``). What they describe is built
by :mod:`skydome.cli.describe`.

The help's ranges are written out (the command line starts without NumPy);
``tests/test_cli_knobs.py`` checks that they agree with the library's.
"""

from __future__ import annotations

import functools
import inspect
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any

import typer


@dataclass(frozen=True)
class Flag:
    """One command-line option: the parameter's name and type, its default, its flag
    spellings and its help."""

    annotation: type
    default: Any
    names: tuple[str, ...]
    help: str

    def option(self):
        return typer.Option(self.default, *self.names, help=self.help)


FLAGS: dict[str, Flag] = {
    # the place
    "place": Flag(str, None, ("--place",),
                  "A city or observatory of the built-in gazetteer (skydome places)."),
    "lat": Flag(float, None, ("--lat",), "Latitude, degrees north (-90..90)."),
    "lon": Flag(float, None, ("--lon",), "Longitude, degrees east (-180..360)."),
    "elevation": Flag(float, None, ("--elevation",),
                      "Elevation above sea level, metres (default: the place's, or 0)."),
    "utc": Flag(bool, False, ("--utc",),
                "Read a time without an offset as UTC, not as the --place's local time."),
    # the Sun without a place
    "sun_elevation": Flag(float, None, ("--sun-elevation",),
                          "Sun elevation above the horizon as seen (refracted), degrees "
                          "(-90..90; default 30), without a place and time."),
    "sun_azimuth": Flag(float, None, ("--sun-azimuth",),
                        "Sun azimuth from north through east, degrees (default 180), without a "
                        "place."),
    # the air
    "atmosphere": Flag(str, "earth", ("--atmosphere",),
                       "Preset: earth | typical | hazy | urban | maritime | desert | "
                       "earth_bruneton | earth_nishita | mars."),
    "albedo": Flag(float, None, ("--albedo",),
                   "Ground albedo, 0..1, on top of --atmosphere (default: the preset's, earth "
                   "grassland's spectral albedo, 0.12 in luminance)."),
    "aod": Flag(float, None, ("--aod",),
                "Aerosol optical depth at 550 nm, 0..5, on top of --atmosphere (default: the "
                "preset's, earth 0.1, typical 0.151, hazy 0.27, earth_bruneton 0.0053)."),
    "visibility": Flag(float, None, ("--visibility",),
                       "Meteorological visibility at the ground, km (Koschmieder, 550 nm; "
                       "0.02..335): made by the --weather's fog or mist droplets when it has "
                       "them, else by the aerosol of --atmosphere (earth: from 1.9 km); instead "
                       "of --aod."),
    "angstrom": Flag(float, None, ("--angstrom",),
                     "Angstrom exponent of the aerosol optical depth, -0.5..3 (0 grey, 1.3 "
                     "continental haze, 2+ smoke), on top of --atmosphere (default: the "
                     "preset's spectrum)."),
    "ozone": Flag(float, None, ("--ozone",),
                  "Total ozone column, Dobson units, 0..700, on top of --atmosphere (default: "
                  "the preset's, earth 300 DU)."),
    # the tables
    "orders": Flag(int, 4, ("--orders",), "Scattering orders of the precomputed tables (1..20)."),
    "spectral": Flag(str, "accurate", ("--spectral",),
                     "Wavelength set: accurate (16) | fast (4)."),
    # the night
    "bortle": Flag(int, None, ("--bortle",),
                   "Light pollution of a Bortle class, 1 (darkest) to 9 (inner city), with a "
                   "place (default: the --place's own: a city's estimated from its population, "
                   "an observatory's dark sky; none with --lat/--lon)."),
    "night_vision": Flag(bool, False, ("--night-vision",),
                         "Show the image as a dark-adapted eye sees it: colour fades, blur, "
                         "noise (the image only; EXR/HDR/NPY keep the physical frame)."),
    "overlay": Flag(str, None, ("--overlay",),
                    "Draw over the image, comma separated: lines (constellations), labels, "
                    "grid."),
    # the clouds
    "clouds": Flag(str, None, ("--clouds",),
                   "Clouds of a preset: fair | broken | overcast | nimbostratus | storm | "
                   "cirrus | clear (default: none)."),
    "coverage": Flag(float, None, ("--coverage",), "Cloud coverage 0..1 (with --clouds)."),
    "cloud_base": Flag(float, None, ("--cloud-base",), "Cloud base above the ground, metres."),
    "cloud_thickness": Flag(float, None, ("--cloud-thickness",), "Cloud layer depth, metres."),
    "cloud_type": Flag(str, None, ("--cloud-type",),
                       "stratus | stratocumulus | cumulus | cumulonimbus."),
    "cirrus": Flag(float, None, ("--cirrus",), "Cirrus sheet coverage 0..1 (with --clouds)."),
    "halos": Flag(str, None, ("--halos",),
                  "The ice crystals of the cirrus: none, or random (22/46 deg halos), plates (sun "
                  "dogs, circumzenithal arc), columns (tangent arcs) with optional weights, "
                  "e.g. random:0.6,plates:0.4 (default random:0.6,plates:0.25,columns:0.15); "
                  "also diamond dust's (--weather diamond-dust)."),
    "wind": Flag(str, None, ("--wind",),
                 "SPEED,FROM: wind speed (m/s) and the direction it blows from (degrees, 90 = "
                 "from the east), carrying the clouds (time-lapses animate them)."),
    "cloud_seed": Flag(int, None, ("--cloud-seed",), "Seed of the cloud noise and weather map."),
    "weather_map": Flag(str, None, ("--weather-map",),
                    "A weather-map image (PNG/JPEG/TIFF: R coverage, G type, B rain, A "
                    "cirrus; or grey = coverage) instead of a generated one."),
    # the weather
    "weather": Flag(str, None, ("--weather",),
                    "Weather preset: sunny | hazy | mist | fog | drizzle | rain | heavy-rain | "
                    "snow | thunderstorm | diamond-dust (brings its clouds unless --clouds is given)."),
    "humidity": Flag(float, None, ("--humidity",),
                     "Relative humidity, % (0..100): the aerosol swells with it."),
    "fog_top": Flag(float, None, ("--fog-top",),
                    "Top of the fog or mist layer above the ground, metres (5..2000)."),
    "fog_droplet": Flag(float, None, ("--fog-droplet",),
                        "Effective radius of the fog's droplets, micrometres (1..50; default "
                        "10)."),
    "rain": Flag(float, None, ("--rain",), "Rain rate, mm/h (0..300)."),
    "rain_drop": Flag(float, None, ("--rain-drop",),
                      "Rain drops all of one radius, mm (0.1..0.5): narrow rainbows with "
                      "supernumerary arcs (default: the rate's Marshall-Palmer sizes)."),
    "snow": Flag(float, None, ("--snow",), "Snowfall rate, mm/h of melted water (0..50)."),
    "snow_cover": Flag(float, None, ("--snow-cover",),
                       "Fraction of the ground under snow, 0..1 (its albedo goes to snow's)."),
    "shutter": Flag(float, None, ("--shutter",),
                    "Shutter time of the camera, seconds (1e-5..1; default 1/60): how long the "
                    "falling rain's and snow's streaks are."),
    # the camera
    "look": Flag(str, None, ("--look",),
                 "Aim the camera: sun | moon | antisun (the antisolar point: rainbows) | "
                 "zenith | north | east | south | west (default: the Sun, or at night the "
                 "Moon when it is up; a time-lapse looks south)."),
    "camera": Flag(str, "perspective", ("--camera",),
                   "perspective | fisheye | equirect | cubemap."),
    "fov": Flag(float, 90.0, ("--fov",),
                "Horizontal field of view of the perspective camera, degrees."),
    "yaw": Flag(float, None, ("--yaw",),
                "View azimuth from north through east, degrees (default: by --look)."),
    "pitch": Flag(float, None, ("--pitch",),
                  "View elevation, degrees (default 15, or the --look target's)."),
    "altitude": Flag(float, None, ("--altitude",),
                     "Camera altitude above the ground, metres (default 1.7 m above the "
                     "place)."),
    # the display
    "compensation": Flag(float, 0.0, ("--exposure-compensation",), "EV added to the exposure."),
    "metering": Flag(str, "eye", ("--metering",),
                     "How --exposure auto measures: eye (default: a dark-adapted eye's key, "
                     "Krawczyk et al. 2005, dark night skies in the eye's blue-grey; above "
                     "1.25 cd/m^2 as average) | average | center (centre-weighted) | spot (the "
                     "central 2.5 %: what the camera looks at, e.g. the Moon)."),
    "glare": Flag(str, "eye", ("--glare",),
                  "Glare on the image (not on EXR/HDR/NPY data): eye (default: the eye's point "
                  "spread function, CIE 146:2002) | lens (a camera lens's veiling glare) | off."),
    "no_sun_disk": Flag(bool, False, ("--no-sun-disk",),
                        "Leave the Sun's disk out of the image (an environment map for a "
                        "renderer with its own Sun lamp); the air stays sunlit."),
    "ground": Flag(str, None, ("--ground",),
                   "Below the horizon: none (a ground that reflects nothing: the air in "
                   "front of it only) | black (zero: HDRIs lit with a ground of your own) | "
                   "an albedo 0..1 | a surface's spectral albedo: grassland, cropland, "
                   "forest, desert, snow, ocean, urban (default: the atmosphere's; earth: "
                   "grassland) | a landscape panorama "
                   "(.png/.jpg/.tif, equirect 2:1, north at the left edge, transparent sky)."),
    "tonemap": Flag(str, "filmic", ("--tonemap",),
                    "filmic | reinhard | exponential | hvs | linear."),
}  # fmt: skip

GROUPS: dict[str, tuple[str, ...]] = {
    "place": ("place", "lat", "lon", "elevation", "utc"),
    "sun": ("sun_elevation", "sun_azimuth"),
    "air": ("atmosphere", "albedo", "aod", "visibility", "angstrom", "ozone"),
    "tables": ("orders", "spectral"),
    "night": ("bortle", "night_vision", "overlay"),
    "clouds": (
        "clouds", "coverage", "cloud_base", "cloud_thickness", "cloud_type", "cirrus", "halos",
        "wind", "cloud_seed", "weather_map",
    ),
    "weather": (
        "weather", "humidity", "fog_top", "fog_droplet", "rain", "rain_drop", "snow", "snow_cover",
        "shutter",
    ),
    "camera": ("look", "camera", "fov", "yaw", "pitch", "altitude"),
    "display": ("compensation", "tonemap", "no_sun_disk", "ground", "metering", "glare"),
}  # fmt: skip


def with_flags(*groups: str):
    """Give a typer command the options of ``groups`` (before its own): the command receives
    them as one keyword argument ``flags``, a namespace of the values given (None where not
    given and without a default)."""
    names = [name for group in groups for name in GROUPS[group]]

    def decorate(command):
        signature = inspect.signature(command)
        own = [p for p in signature.parameters.values() if p.name != "flags"]
        clash = {p.name for p in own} & set(names)
        if clash:
            raise TypeError(f"{command.__name__} declares shared flags itself: {sorted(clash)}")
        added = [
            inspect.Parameter(name, inspect.Parameter.POSITIONAL_OR_KEYWORD,
                              default=FLAGS[name].option(), annotation=FLAGS[name].annotation)
            for name in names
        ]  # fmt: skip

        @functools.wraps(command)
        def run(*args, **kwargs):
            given = {name: kwargs.pop(name) for name in names}
            return command(*args, flags=SimpleNamespace(**given), **kwargs)

        run.__signature__ = signature.replace(parameters=added + own)
        return run

    return decorate


def flag_name(param: str) -> str:
    """The command-line spelling of a shared flag (``"cloud_base"`` -> ``"--cloud-base"``)."""
    return FLAGS[param].names[0]
