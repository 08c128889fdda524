"""What a :class:`~skydome.weather.Weather` does to a sky's air and clouds.

The weather package knows no layer; this joins it to them (as ``skydome.description`` joins
every layer):

- the aerosol swells with the humidity (``Weather.aerosol_growth`` on its optical depth) and
  whitens (``Weather.aerosol_whitening``: its Angstrom exponent falls as its particles grow);
- the visibility asked for is met by the droplets of the weather's fog or mist when it has
  one, else by the aerosol (``AtmosphereParams.with_visibility``), after the air, the rain
  and the snow have taken their part: V = 3.912 / (beta_air + beta_aerosol + beta_fog +
  beta_rain + beta_snow) at the ground, 550 nm;
- the fog, the rain and the snow are drawn by the cloud layer (``Clouds.fog_*`` and
  ``precipitation_extinction_per_m``), under the clouds the weather brings (its preset's)
  unless the sky has its own;
- a snow cover turns the ground's albedo towards snow's;
- hazy air scatters light many times: the tables then add orders until an order adds less
  than :data:`ORDER_TOLERANCE` of the light (at most :data:`MAX_ORDERS`), not a fixed four.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from skydome.atmosphere.params import AtmosphereParams, Spectrum
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.clouds.params import Clouds
from skydome.errors import ParameterError
from skydome.physics.droplets import KOSCHMIEDER
from skydome.weather import Weather
from skydome.weather.params import SNOW_ALBEDO

#: Below this visibility (km) of the air the tables' orders run until they converge.
CONVERGE_BELOW_KM = 30.0
ORDER_TOLERANCE = 1e-3
MAX_ORDERS = 50


def weathered(
    weather: Weather | None,
    atmosphere: AtmosphereParams,
    clouds: Clouds | None,
    config: PrecomputeConfig,
) -> tuple[AtmosphereParams, Clouds | None, PrecomputeConfig]:
    """The air, the clouds and the tables of a sky with ``weather`` (module docstring)."""
    if weather is None:
        return atmosphere, clouds, config
    air = atmosphere
    growth = weather.aerosol_growth
    if air.aod_550 > 0 and growth != 1.0:
        air = air.with_aerosol(aod_550=min(air.aod_550 * growth, 5.0))
    if air.aod_550 > 0:
        air = air.with_aerosol_tilt(weather.aerosol_whitening)
    if clouds is None and weather.clouds is not None:
        clouds = Clouds(weather.clouds, wind_m_s=weather.wind_m_s)
    precip = weather.precipitation_extinction_per_m
    if precip > 0 and (clouds is None or clouds.coverage == 0):
        raise ParameterError(
            f"rain and snow fall from clouds: the weather {weather.preset!r} with this sky's "
            "clouds has none (give clouds with a coverage, e.g. nimbostratus)"
        )
    fog = 0.0
    if weather.visibility_km is not None:
        wanted = KOSCHMIEDER / (weather.visibility_km * 1e3)
        rest = wanted - precip
        if weather.has_fog:
            fog = rest - air.ground_extinction_550_per_m
            if fog <= 0:
                raise ParameterError(
                    f"visibility {weather.visibility_km:g} km: this air with its rain and snow "
                    f"sees {_km(air.ground_extinction_550_per_m + precip):.3g} km already; a "
                    "fog or mist needs less"
                )
        else:
            if rest <= 0:
                raise ParameterError(
                    f"visibility {weather.visibility_km:g} km: the rain and snow alone make it "
                    f"{_km(precip):.3g} km"
                )
            air = air.with_visibility(_km(rest))
    elif weather.has_fog:
        raise ParameterError("a fog needs a visibility (km) for its droplets")
    if fog > 0 or precip > 0:
        base = clouds if clouds is not None else Clouds("clear", wind_m_s=weather.wind_m_s)
        clouds = base.with_(
            fog_top_m=weather.fog_top_m if fog > 0 else 0.0,
            fog_extinction_per_m=fog,
            fog_ice=weather.fog_ice and fog > 0,
            fog_droplet_um=weather.fog_droplet_um if fog > 0 else base.fog_droplet_um,
            precipitation_extinction_per_m=precip,
            rain_fraction=weather.rain_extinction_per_m / precip if precip > 0 else 1.0,
            rain_mm_h=weather.rain_mm_h if weather.rain_mm_h > 0 else base.rain_mm_h,
            rain_drop_radius_mm=weather.rain_drop_radius_mm,
        )
    if weather.snow_cover > 0:
        c = weather.snow_cover
        albedo = np.asarray(air.ground_albedo.values, float)
        wavelengths = air.ground_albedo.wavelengths_nm
        air = air.with_albedo(Spectrum(wavelengths, tuple((1.0 - c) * albedo + c * SNOW_ALBEDO)))
    if _km(air.ground_extinction_550_per_m) < CONVERGE_BELOW_KM and config.orders < MAX_ORDERS:
        config = replace(config, orders=MAX_ORDERS, tolerance=ORDER_TOLERANCE)
    return air, clouds, config


def ground_visibility_km(atmosphere: AtmosphereParams, clouds: Clouds | None) -> float:
    """The visibility (km) at the ground of the air and of the fog, rain and snow under the
    clouds (Koschmieder, 550 nm; the precipitation at its full rate)."""
    beta = atmosphere.ground_extinction_550_per_m
    if clouds is not None:
        beta += clouds.fog_extinction_per_m + clouds.precipitation_extinction_per_m
    return _km(beta)


def _km(extinction_per_m: float) -> float:
    return KOSCHMIEDER / (extinction_per_m * 1e3)
