"""Illuminance on the ground under a weather's clouds, fog, rain or snow.

The clear sky's is the tables' (``skydome.atmosphere.illuminance``); under a weather the
light is what the sky that is drawn gives: a sky with that weather (``Sky``) is set up for
the Sun's elevation, and its cloud layer's probe (``CloudLayer.sky_probe``: the whole sky
seen from the ground, clouds, fog and precipitation marched over the clear sky) gives the
diffuse illuminance and the zenith luminance; the direct illuminance is the clear sky's times
the clouds' and the weather's transmittance towards the Sun at the observer
(``CloudLayer.light_transmittance``; the droplets' forward peak counts as direct light).
"""

from __future__ import annotations

import numpy as np

from skydome.atmosphere.illuminance import horizontal_illuminance
from skydome.atmosphere.params import AtmosphereParams
from skydome.core.cameras import EquirectCamera
from skydome.description import SkyDescription
from skydome.sky import Sky
from skydome.spectra import SRGB_LUMINANCE
from skydome.weather import Weather


def weather_illuminance(
    sun_elevation_deg: float,
    altitude_m: float,
    weather: Weather,
    atmosphere: AtmosphereParams,
) -> dict[str, float]:
    """Direct, diffuse and total horizontal illuminance (lx) and the zenith luminance
    (cd/m^2) at ``altitude_m`` above the ground under ``weather`` (the keys of
    ``Illuminance.to_dict``, photopic), for a Sun at ``sun_elevation_deg``."""
    description = SkyDescription.of(
        sun_elevation_deg=sun_elevation_deg, atmosphere=atmosphere, weather=weather, night=False
    )
    air, _, config = description.effective
    (clear,) = horizontal_illuminance(
        sun_elevation_deg, altitude_m=altitude_m, atmosphere=air, config=config
    )
    with Sky(description) as sky:
        sky.render(EquirectCamera(), 16, 8, altitude_m=altitude_m, exposure=None)
        clouds = sky.layer("clouds")
        probe = clouds.sky_probe()
        through = float(clouds.light_transmittance(np.array([0.0, 0.0, altitude_m])))
    luminance = np.asarray(SRGB_LUMINANCE, float)
    diffuse = float(luminance @ probe.irradiance[:3])
    direct = clear.direct_horizontal_lux * through
    zenith = float(luminance @ probe.radiance[0, :, :3].mean(axis=0))
    return {
        "sun_elevation_deg": float(sun_elevation_deg),
        "altitude_m": float(altitude_m),
        "direct_horizontal_lux": direct,
        "diffuse_horizontal_lux": diffuse,
        "total_horizontal_lux": direct + diffuse,
        "zenith_luminance_cd_m2": zenith,
        "sun_transmittance": through,
    }
