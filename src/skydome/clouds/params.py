"""What a sky's clouds are: a layer of a cloud type between a base and a top, its coverage,
a cirrus sheet above it, the wind that carries them, and the presets.

>>> from skydome.clouds import Clouds
>>> Clouds("fair", coverage=0.5, base_m=1500, thickness_m=2000, wind_m_s=(5, 0), seed=1)

Extinction from liquid water: sigma_ext = 3 LWC / (2 rho_w r_eff) (Stephens 1978, J. Atmos.
Sci. 35, 2123, eq. 10, extinction efficiency 2 for droplets much larger than the wavelength),
with an effective droplet radius of 10 um and typical liquid water contents per type
(Pruppacher & Klett 1997, "Microphysics of Clouds and Precipitation", table 2.2 ranges:
stratus and stratocumulus 0.1-0.5 g/m^3, cumulus 0.2-1, cumulonimbus 1-3): a cumulus at
0.5 g/m^3 has 75 /km, a 1 km thick one an optical thickness of about 75 where it is dense.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

from skydome.clouds.halos import DEFAULT_HALOS, parse_halos
from skydome.clouds.phase import CLOUD_R_EFF_UM, DEFAULT_RAIN_MM_H
from skydome.errors import ParameterError, check_wind
from skydome.physics.droplets import droplet_extinction_per_m

#: The cloud types of the height profiles and where each sits on the weather map's type axis.
CLOUD_TYPES = {
    "stratus": 0.0,
    "stratocumulus": 1.0 / 3.0,
    "cumulus": 2.0 / 3.0,
    "cumulonimbus": 1.0,
}
#: Typical liquid water content (g/m^3) of each type (module docstring).
LIQUID_WATER_G_M3 = {"stratus": 0.25, "stratocumulus": 0.3, "cumulus": 0.5, "cumulonimbus": 1.0}
#: The map coverages at which WATER_NORMALIZATION is given.
WATER_COVERAGE_NODES = (0.25, 0.5, 0.75, 1.0)
#: The factor on each type's extinction at density 1 (rows: CLOUD_TYPES; columns: the map's
#: coverage at WATER_COVERAGE_NODES) that makes the water what is asked for: the noise
#: shapes where the water is, not how much there is. At coverage 1 the mean optical depth
#: of the columns is the nominal one (extinction_per_m(LWC) x thickness); at a lower
#: coverage the clouds' own columns (those above 1 % of the nominal) hold as much as at 1.
#: Measured by tools/calibrate_cloud_water.py (the column census of CloudLayer through
#: Sky, seeds 1-3, 160 samples per column); tests/test_cloud_water.py holds the user's path
#: to it.
WATER_NORMALIZATION: dict[str, tuple[float, float, float, float]] = {
    "stratus": (12.321, 6.454, 3.689, 2.244),
    "stratocumulus": (18.177, 11.642, 8.737, 6.415),
    "cumulus": (26.062, 15.837, 11.328, 8.051),
    "cumulonimbus": (33.350, 18.319, 8.141, 4.415),
}
#: Effective radius of cloud droplets (m).
EFFECTIVE_RADIUS_M = 10e-6
#: Ice clouds: a cirrus with an ice water content of 0.02 g/m^3 and effective radius 30 um
#: has about 1 /km (Heymsfield & McFarquhar 2002 give 0.1-2 /km for midlatitude cirrus).
CIRRUS_EXTINCTION_PER_M = 1.0e-3


def extinction_per_m(liquid_water_g_m3: float, radius_m: float = EFFECTIVE_RADIUS_M) -> float:
    """Extinction coefficient (1/m) of a cloud of droplets: 3 LWC / (2 rho_w r_eff)."""
    return float(droplet_extinction_per_m(liquid_water_g_m3, radius_m))


#: The presets: what a sky of each looks like (fields of Clouds).
PRESETS: dict[str, dict[str, Any]] = {
    # fair-weather cumulus (humilis / mediocris): bases near 1.5 km, about 1.5 km deep
    "fair": dict(coverage=0.4, cloud_type="cumulus", base_m=1500.0, thickness_m=1800.0),
    # a closed stratus deck: 250 g/m^2 of water (0.25 g/m^3 over 1 km), optical depth 37.5
    "overcast": dict(coverage=1.0, cloud_type="stratus", base_m=600.0, thickness_m=1000.0),
    # a rainy nimbostratus day: a closed sheet 2.5 km deep on a low base, with rain (0.4
    # g/m^3 with it: 1000 g/m^2, optical depth 150)
    "nimbostratus": dict(
        coverage=1.0, cloud_type="stratus", base_m=500.0, thickness_m=2500.0, precipitation=0.3
    ),
    # a stratocumulus deck with breaks
    "broken": dict(coverage=0.95, cloud_type="stratocumulus", base_m=800.0, thickness_m=1000.0),
    # towering cumulonimbus with rain, on a low base, tops near the tropopause
    "storm": dict(
        coverage=0.7,
        cloud_type="cumulonimbus",
        base_m=900.0,
        thickness_m=9000.0,
        precipitation=0.7,
        cirrus=0.3,
    ),  # fmt: skip
    # a cirrus / cirrostratus sheet only
    "cirrus": dict(coverage=0.0, cirrus=0.8),
    "clear": dict(coverage=0.0, cirrus=0.0),
}


def _number(name: str, value: Any, lo: float, hi: float, unit: str = "") -> float:
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(f"cloud {name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or not lo <= v <= hi:
        unit = f" {unit}" if unit else ""
        raise ParameterError(f"cloud {name} must be within [{lo:g}, {hi:g}]{unit}, got {value!r}")
    return v


@dataclass(frozen=True)
class Clouds:
    """A sky's clouds. Unset fields come from the preset.

    Args:
        preset: "fair", "broken", "overcast", "nimbostratus", "storm", "cirrus" or "clear".
        coverage: fraction of the sky the main layer covers (0-1): 0 is no cloud, 1 the whole
            weather map's cloudiness.
        cloud_type: "stratus", "stratocumulus", "cumulus", "cumulonimbus" (or 0-1 between
            them); a weather map's type channel overrides it per place.
        base_m, thickness_m: the main layer's base above the ground and its depth (m).
        precipitation: 0-1, rain in the clouds (denser, darker bases).
        cirrus: coverage (0-1) of the cirrus sheet at ``cirrus_base_m`` (m) of
            ``cirrus_thickness_m`` (m).
        wind_m_s: (east, north) speed of the wind carrying the clouds (m/s).
        seed: the noise's and the generated weather map's seed.
        weather: a ``WeatherMap``, an image path or a NumPy array (coverage, type,
            precipitation, cirrus channels; see skydome.clouds.weather), or None to generate
            one from the seed.
        tile_km: the side of the weather map's repeating tile (km).
        optical_depth: the main layer's optical depth (the droplets', at coverage 1 the mean
            of its columns) instead of the one its type's water content gives (see
            ``nominal_optical_depth``).
        uniform: a plane-parallel deck: the main layer filled with a constant extinction (its
            nominal optical depth over its thickness), no noise, no weather map, no cirrus;
            coverage 1.
        fog_top_m, fog_extinction_per_m: a layer of droplets from the ground to ``fog_top_m``
            (m; 0: none) of extinction ``fog_extinction_per_m`` (1/m, the droplets', as
            ``extinction_per_m``): fog or mist (``skydome.weather`` sets them). Below the main
            layer's base.
        precipitation_extinction_per_m: rain or snow (1/m, extinction efficiency 2) from the
            main layer's base to the ground, where the weather map's precipitation is (the
            value under a cell of the map's full precipitation; its coverage where the layer
            has no precipitation).
        rain_fraction: the share (0-1) of that extinction that is rain (water spheres,
            scattering by geometric optics: ``clouds.phase.RAIN_RENDER_PHASE``); the rest is
            snow, which scatters as the cloud droplets do.
        fog_droplet_um: the effective radius (um) of the fog's droplets, whose single
            scattering takes their phase function (5-20 um tabulated: the fogbow's width and
            radius, the glory's rings); their multiple scattering is the clouds' droplets'.
        fog_ice: the fog layer is of ice crystals (diamond dust): its single scattering by the
            halo table of ``halos`` (skydome.clouds.halos), as the cirrus's.
        rain_mm_h: the rain's rate (mm/h): its drops' sizes (Marshall-Palmer), which set its
            bows' width and paleness (skydome.clouds.phase.RainBows).
        rain_drop_radius_mm: drops of one size (radius mm, a 10 % spread; 0.1-0.5) instead:
            narrow bows with supernumerary arcs inside the primary. None: Marshall-Palmer.
        halos: the cirrus's ice crystals (skydome.clouds.halos): "none" (they scatter as
            the cloud droplets do), or a mixture of "random" (the 22 and 46 deg halos),
            "plates" (sun dogs, the circumzenithal arc, the parhelic circle) and "columns"
            (tangent arcs), with optional weights: "random:0.6,plates:0.4".
    """

    preset: str = "fair"
    coverage: float | None = None
    cloud_type: str | float | None = None
    base_m: float | None = None
    thickness_m: float | None = None
    precipitation: float | None = None
    cirrus: float | None = None
    cirrus_base_m: float = 9000.0
    cirrus_thickness_m: float = 800.0
    wind_m_s: tuple[float, float] = (5.0, 0.0)
    seed: int = 1
    weather: Any = field(default=None, compare=False)
    tile_km: float = 40.0
    optical_depth: float | None = None
    uniform: bool = False
    fog_top_m: float = 0.0
    fog_extinction_per_m: float = 0.0
    precipitation_extinction_per_m: float = 0.0
    rain_fraction: float = 1.0
    fog_droplet_um: float = CLOUD_R_EFF_UM
    fog_ice: bool = False
    rain_mm_h: float = DEFAULT_RAIN_MM_H
    rain_drop_radius_mm: float | None = None
    halos: str = DEFAULT_HALOS

    def __post_init__(self):
        if not isinstance(self.preset, str) or self.preset not in PRESETS:
            raise ParameterError(
                f"cloud preset {self.preset!r} must be one of {', '.join(PRESETS)}"
            )
        base = {"coverage": 0.0, "cloud_type": "cumulus", "base_m": 1500.0,
                "thickness_m": 1500.0, "precipitation": 0.0, "cirrus": 0.0}  # fmt: skip
        base.update(PRESETS[self.preset])
        if self.uniform is True:  # a deck over the whole sky, alone (checked below)
            base.update(coverage=1.0, cirrus=0.0)
        for key, value in base.items():
            if getattr(self, key) is None:
                object.__setattr__(self, key, value)
        object.__setattr__(self, "coverage", _number("coverage", self.coverage, 0.0, 1.0))
        object.__setattr__(
            self, "precipitation", _number("precipitation", self.precipitation, 0.0, 1.0)
        )
        object.__setattr__(self, "cirrus", _number("cirrus coverage", self.cirrus, 0.0, 1.0))
        object.__setattr__(self, "base_m", _number("base", self.base_m, 0.0, 1e7, "m"))
        thickness = _number("thickness", self.thickness_m, -math.inf, 20000.0, "m")
        if thickness <= 0:
            raise ParameterError(f"cloud thickness must be positive, got {self.thickness_m!r} m")
        object.__setattr__(self, "thickness_m", thickness)
        ci_base = _number("cirrus base", self.cirrus_base_m, 0.0, 1e7, "m")
        ci_thick = _number("cirrus thickness", self.cirrus_thickness_m, 1.0, 5000.0, "m")
        object.__setattr__(self, "cirrus_base_m", ci_base)
        object.__setattr__(self, "cirrus_thickness_m", ci_thick)
        object.__setattr__(self, "cloud_type", self.type_value)  # validates
        object.__setattr__(
            self, "tile_km", _number("weather tile", self.tile_km, 1.0, 1000.0, "km")
        )
        object.__setattr__(self, "wind_m_s", check_wind(self.wind_m_s))
        if not isinstance(self.seed, int) or isinstance(self.seed, bool) or self.seed < 0:
            raise ParameterError(f"cloud seed must be a non-negative integer, got {self.seed!r}")
        if self.optical_depth is not None:
            tau = _number("optical depth", self.optical_depth, 0.0, 10000.0)
            object.__setattr__(self, "optical_depth", tau)
        if not isinstance(self.uniform, bool):
            raise ParameterError(f"uniform must be True or False, got {self.uniform!r}")
        if self.uniform:
            if self.coverage != 1.0 or self.weather is not None or self.cirrus > 0:
                raise ParameterError(
                    "a uniform deck covers the whole sky alone: coverage 1, no weather map, "
                    "no cirrus"
                )
            object.__setattr__(self, "coverage", 1.0)
        self._check_ground_layer()
        mixture = parse_halos(self.halos)
        canonical = ",".join(f"{name}:{share:.6g}" for name, share in mixture) or "none"
        object.__setattr__(self, "halos", canonical)

    def _check_ground_layer(self) -> None:
        """The fog and the precipitation under the main layer: numbers in range, the fog
        below the base, precipitation only from a layer."""
        top = _number("fog top", self.fog_top_m, 0.0, 5000.0, "m")
        fog = _number("fog extinction", self.fog_extinction_per_m, 0.0, 1.0, "1/m")
        precip = _number(
            "precipitation extinction", self.precipitation_extinction_per_m, 0.0, 0.1, "1/m"
        )
        object.__setattr__(self, "fog_top_m", top)
        object.__setattr__(self, "fog_extinction_per_m", fog)
        object.__setattr__(self, "precipitation_extinction_per_m", precip)
        rain = _number("rain fraction", self.rain_fraction, 0.0, 1.0, "")
        object.__setattr__(self, "rain_fraction", rain)
        if not isinstance(self.fog_ice, bool):
            raise ParameterError(f"fog_ice must be True or False, got {self.fog_ice!r}")
        droplet = _number("fog droplet radius", self.fog_droplet_um, 1.0, 50.0, "um")
        object.__setattr__(self, "fog_droplet_um", droplet)
        rate = _number("rain rate", self.rain_mm_h, 0.01, 500.0, "mm/h")
        object.__setattr__(self, "rain_mm_h", rate)
        if self.rain_drop_radius_mm is not None:
            radius = _number("rain drop radius", self.rain_drop_radius_mm, 0.1, 0.5, "mm")
            object.__setattr__(self, "rain_drop_radius_mm", radius)
        if (top > 0) != (fog > 0):
            raise ParameterError("a fog needs both a top above the ground and an extinction")
        if top > 0 and self.coverage > 0 and top > self.base_m:
            raise ParameterError(
                f"the fog's top ({top:.0f} m) is above the clouds' base ({self.base_m:.0f} m): "
                "lower it or raise the clouds"
            )
        if precip > 0 and self.coverage == 0:
            raise ParameterError("rain and snow fall from clouds: this sky has no cloud layer")

    @property
    def ground_layer_top_m(self) -> float:
        """The top (m above the ground) of the fog and the precipitation under the clouds (0:
        neither)."""
        rain_top = self.base_m if self.precipitation_extinction_per_m > 0 else 0.0
        return max(self.fog_top_m, rain_top)

    @property
    def type_value(self) -> float:
        """The cloud type on the weather map's axis (0 stratus ... 1 cumulonimbus)."""
        t = self.cloud_type
        if isinstance(t, str):
            if t not in CLOUD_TYPES:
                raise ParameterError(
                    f"cloud type {t!r} must be one of {', '.join(CLOUD_TYPES)} or 0-1"
                )
            return CLOUD_TYPES[t]
        return _number("type", t, 0.0, 1.0)

    @property
    def top_m(self) -> float:
        """The highest cloud (m above the ground): the main layer's or the cirrus sheet's."""
        top = self.base_m + self.thickness_m
        if self.cirrus > 0:
            top = max(top, self.cirrus_base_m + self.cirrus_thickness_m)
        return top

    @property
    def aloft(self) -> bool:
        """Whether there are clouds over the ground (a deck, cirrus or a weather map): without
        them the fog under is the same everywhere, lit by the clear sky."""
        return self.coverage > 0.0 or self.cirrus > 0.0 or self.weather is not None

    @property
    def empty(self) -> bool:
        """No cloud, fog or precipitation at all: the layer draws nothing."""
        return self.coverage == 0.0 and self.cirrus == 0.0 and self.fog_top_m == 0.0

    def check_atmosphere(self, top_of_atmosphere_m: float) -> None:
        """A ParameterError when the clouds reach above the top of the atmosphere
        (``top_of_atmosphere_m`` above the place's ground)."""
        if self.top_m >= top_of_atmosphere_m:
            raise ParameterError(
                f"the clouds reach {self.top_m:.0f} m above the ground, above the top of the "
                f"atmosphere ({top_of_atmosphere_m:.0f} m)"
            )

    @property
    def water_g_m3(self) -> float:
        """The main layer's nominal water content (g/m^3): its type's (interpolated between
        the types of CLOUD_TYPES) with the rain's extra water (x (1 + 2 precipitation))."""
        values = [LIQUID_WATER_G_M3[t] for t in CLOUD_TYPES]
        x = self.type_value * (len(values) - 1)
        i = min(int(x), len(values) - 2)
        lwc = values[i] + (values[i + 1] - values[i]) * (x - i)
        return lwc * (1.0 + 2.0 * self.precipitation)

    @property
    def nominal_optical_depth(self) -> float:
        """The main layer's optical depth (droplets', dimensionless): ``optical_depth`` if
        given, else extinction_per_m(water_g_m3) x thickness. At coverage 1 the mean of its
        columns; at a lower coverage that of its clouds' columns (0 without the layer)."""
        if self.coverage == 0.0:
            return 0.0
        if self.optical_depth is not None:
            return self.optical_depth
        return extinction_per_m(self.water_g_m3) * self.thickness_m

    def type_extinctions_per_km(self) -> tuple[float, float, float, float]:
        """Extinction (1/km) at density 1, before WATER_NORMALIZATION, of each type of
        CLOUD_TYPES, in order (with ``optical_depth``: every type's gives it)."""
        if self.optical_depth is not None:
            tau = self.optical_depth / (1.0 + 2.0 * self.precipitation)  # the rain's added back
            return (tau / (self.thickness_m / 1e3),) * len(CLOUD_TYPES)
        return tuple(extinction_per_m(LIQUID_WATER_G_M3[t]) * 1e3 for t in CLOUD_TYPES)

    def with_(self, **changes) -> Clouds:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)
