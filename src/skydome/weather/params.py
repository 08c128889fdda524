"""A sky's weather: what falls, what hangs in the air near the ground, and how far one sees.

>>> from skydome.weather import Weather
>>> Weather("fog").visibility_km
0.2
>>> round(Weather("rain", rain_mm_h=10).rain_extinction_per_m * 1e3, 3)  # Marshall-Palmer, /km
1.556

The presets (:data:`PRESETS`) set every knob; a knob given overrides its preset's value:

- ``visibility_km``: the meteorological visibility at the ground (Koschmieder, 550 nm) of
  everything there: air, aerosol, droplets, rain and snow. None: what the other knobs give.
- ``humidity_pct``: relative humidity; the aerosol swells with it (``weather.humidity``).
- ``fog_top_m``, ``fog_droplet_um``: a layer of droplets from the ground to its top (fog,
  mist), of droplets of that effective radius. When the weather has one, the visibility is
  the droplets' to make; without, the aerosol's.
- ``fog_ice``: the layer is of ice crystals (diamond dust), which scatter by the halo table of
  the clouds' ``halos`` mixture (skydome.clouds.halos): halos in clear, cold air.
- ``rain_mm_h`` (with ``rain_distribution``), ``snow_mm_h``: precipitation (snow as melted
  water), falling from the clouds' base where their weather map has precipitation.
- ``rain_drop_radius_mm``: the rain's drops all of about one radius (0.1-0.5 mm, a 10 %
  spread) for its optics: narrow bows with supernumerary arcs (None: the rate's
  Marshall-Palmer sizes, whose spread washes the supernumeraries out).
- ``wind_m_s``: (east, north) wind (m/s): it carries the clouds.
- ``snow_cover``: the fraction of the ground under snow (its albedo goes to snow's).
- ``clouds``: the cloud preset the weather brings (None: none), unless a sky gives its own.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Any

from skydome.errors import ParameterError, check_range, check_wind
from skydome.weather.fog import FOG_DROPLET_RADIUS_M, FOG_DROPLET_RANGE_UM
from skydome.weather.humidity import angstrom_change, growth_factor
from skydome.weather.rain import DISTRIBUTIONS, RAIN_RATE_RANGE, rain_extinction_per_m
from skydome.weather.snow import SNOW_RATE_RANGE, snow_extinction_per_m

#: Visibilities (km) a weather may ask for: a dense fog's 20 m to the clearest air's 335 km
#: (Rayleigh scattering alone at sea level).
VISIBILITY_RANGE_KM = (0.02, 335.0)
#: Fog tops (m above the ground).
FOG_TOP_RANGE_M = (5.0, 2000.0)
#: Visible albedo of a fresh snow cover (Warren 1982, Rev. Geophys. 20, 67: 0.9 and above in
#: the visible for new snow; 0.9 taken, a cover a few days old).
SNOW_ALBEDO = 0.9

#: Each numeric knob's valid range and unit.
KNOB_RANGES: dict[str, tuple[float, float, str]] = {
    "visibility_km": (*VISIBILITY_RANGE_KM, "km"),
    "humidity_pct": (0.0, 100.0, "%"),
    "fog_top_m": (*FOG_TOP_RANGE_M, "m"),
    "fog_droplet_um": (*FOG_DROPLET_RANGE_UM, "um"),
    "rain_mm_h": (*RAIN_RATE_RANGE, "mm/h"),
    "snow_mm_h": (*SNOW_RATE_RANGE, "mm/h"),
    "snow_cover": (0.0, 1.0, ""),
    "rain_drop_radius_mm": (0.1, 0.5, "mm"),
}

#: The presets: each knob's value (module docstring). Visibilities: WMO's ranges (haze from
#: 5 km, mist 1-5 km, fog below 1 km); rates: light rain ~1, moderate ~4, heavy >= 8 mm/h
#: (WMO-No. 8 vol. I ch. 6 intensity classes), a thunderstorm's downpour 30 mm/h, snow 1 mm/h
#: of water (moderate).
PRESETS: dict[str, dict[str, Any]] = {
    "sunny": dict(humidity_pct=50.0),
    "hazy": dict(visibility_km=8.0, humidity_pct=75.0),
    "mist": dict(visibility_km=2.5, humidity_pct=97.0, fog_top_m=300.0),
    "fog": dict(visibility_km=0.2, humidity_pct=100.0, fog_top_m=150.0),
    "drizzle": dict(visibility_km=3.0, humidity_pct=98.0, fog_top_m=300.0, rain_mm_h=0.5,
                    clouds="overcast"),
    "rain": dict(humidity_pct=95.0, rain_mm_h=4.0, clouds="nimbostratus"),
    "heavy-rain": dict(humidity_pct=98.0, rain_mm_h=16.0, clouds="nimbostratus"),
    "snow": dict(humidity_pct=90.0, snow_mm_h=1.0, snow_cover=1.0, clouds="nimbostratus"),
    "thunderstorm": dict(humidity_pct=90.0, rain_mm_h=30.0, clouds="storm", wind_m_s=(10.0, 0.0)),
    "diamond-dust": dict(visibility_km=12.0, humidity_pct=85.0, fog_top_m=300.0, fog_ice=True,
                         wind_m_s=(1.0, 0.0)),
}  # fmt: skip


@dataclass(frozen=True)
class Weather:
    """A sky's weather (module docstring): a preset and knobs that override it."""

    preset: str = "sunny"
    visibility_km: float | None = None
    humidity_pct: float | None = None
    fog_top_m: float | None = None
    fog_droplet_um: float | None = None
    rain_mm_h: float | None = None
    snow_mm_h: float | None = None
    rain_distribution: str = "marshall-palmer"
    rain_drop_radius_mm: float | None = None
    fog_ice: bool | None = None
    wind_m_s: tuple[float, float] | None = None
    snow_cover: float | None = None
    clouds: str | None = None

    def __post_init__(self):
        if not isinstance(self.preset, str) or self.preset not in PRESETS:
            raise ParameterError(
                f"unknown weather {self.preset!r}; the weathers are {', '.join(PRESETS)}"
            )
        given = {f.name for f in fields(self) if getattr(self, f.name) is not None}
        for key, value in PRESETS[self.preset].items():
            if key not in given:
                object.__setattr__(self, key, value)
        for name, (lo, hi, unit) in KNOB_RANGES.items():
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, check_range(name, value, lo, hi, unit))
        defaults = dict(humidity_pct=50.0, rain_mm_h=0.0, snow_mm_h=0.0, snow_cover=0.0,
                        fog_droplet_um=FOG_DROPLET_RADIUS_M * 1e6, wind_m_s=(5.0, 0.0))  # fmt: skip
        for key, value in defaults.items():
            if getattr(self, key) is None:
                object.__setattr__(self, key, value)
        if self.rain_distribution not in DISTRIBUTIONS:
            raise ParameterError(
                f"rain_distribution {self.rain_distribution!r} must be one of "
                f"{', '.join(DISTRIBUTIONS)}"
            )
        object.__setattr__(self, "wind_m_s", check_wind(self.wind_m_s))
        if self.fog_ice is None:
            object.__setattr__(self, "fog_ice", False)
        if not isinstance(self.fog_ice, bool):
            raise ParameterError(f"fog_ice must be True or False, got {self.fog_ice!r}")
        if self.fog_ice and self.fog_top_m is None:
            raise ParameterError("ice crystals at the ground (fog_ice) need a layer: a fog_top_m")

    def with_(self, **changes) -> Weather:
        return replace(self, **changes)

    # ------------------------------------------------------------------ what it holds

    @property
    def has_fog(self) -> bool:
        """True when the weather has a layer of droplets at the ground (fog, mist)."""
        return self.fog_top_m is not None

    @property
    def precipitates(self) -> bool:
        return self.rain_mm_h > 0 or self.snow_mm_h > 0

    @property
    def rain_extinction_per_m(self) -> float:
        """The rain's extinction (1/m) at its rate, extinction efficiency 2."""
        return float(rain_extinction_per_m(self.rain_mm_h, self.rain_distribution))

    @property
    def snow_extinction_per_m(self) -> float:
        """The snow's extinction (1/m) at its rate."""
        return float(snow_extinction_per_m(self.snow_mm_h))

    @property
    def precipitation_extinction_per_m(self) -> float:
        return self.rain_extinction_per_m + self.snow_extinction_per_m

    @property
    def aerosol_growth(self) -> float:
        """The aerosol's extinction at this humidity over its extinction at OPAC's 80 %."""
        return growth_factor(self.humidity_pct)

    @property
    def aerosol_whitening(self) -> float:
        """The change of the aerosol's Angstrom exponent at this humidity from OPAC's 80 %."""
        return angstrom_change(self.humidity_pct)

    @property
    def fog_droplet_radius_m(self) -> float:
        return self.fog_droplet_um * 1e-6

    def summary(self) -> dict[str, Any]:
        """The weather's knobs, for a frame's info and ``illuminance --json``."""
        return {
            "weather": self.preset,
            "humidity_pct": self.humidity_pct,
            "rain_mm_h": self.rain_mm_h,
            "snow_mm_h": self.snow_mm_h,
            "fog_top_m": self.fog_top_m,
        }
