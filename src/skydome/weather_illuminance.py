"""Illuminance on the ground under a weather's clouds, fog, rain or snow.

The clear sky's is the tables' (``skydome.eclipse_illuminance.state_illuminance``, for the
sky's own lights: its Sun's apparent elevation the direct beam's, the airless one the sky's);
under a weather the
light is what the sky that is drawn gives: a sky with that weather (``Sky``) is set up for
the Sun's elevation, and its cloud layer's probe (``CloudLayer.sky_probe``: the whole sky
seen from the ground, clouds, fog and precipitation marched over the clear sky) gives the
diffuse illuminance and the zenith luminance; the direct illuminance is the clear sky's times
the clouds' and the weather's transmittance towards the Sun at the observer
(``CloudLayer.light_transmittance``; the droplets' forward peak counts as direct light).
At a place and time the sky is the place's (:func:`place_weather_illuminance`), its light its
ground's, a solar eclipse included (:func:`ground_illuminance`, the batch manifest's too).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from skydome.atmosphere.params import AtmosphereParams
from skydome.core.cameras import EquirectCamera
from skydome.description import SkyDescription
from skydome.eclipse_illuminance import state_illuminance
from skydome.sky import Sky
from skydome.spectra import SRGB_LUMINANCE
from skydome.weather import Weather

__all__ = ["ground_illuminance", "place_weather_illuminance", "weather_illuminance"]


def weather_illuminance(
    sun_elevation_deg: float,
    altitude_m: float,
    weather: Weather,
    atmosphere: AtmosphereParams,
) -> dict[str, float]:
    """Direct, diffuse and total horizontal illuminance (lx) and the zenith luminance
    (cd/m^2) at ``altitude_m`` above the ground under ``weather`` (the keys of
    ``Illuminance.to_dict``, photopic), for a Sun at ``sun_elevation_deg`` (its apparent
    elevation, as ``render --sun-elevation`` draws it)."""
    description = SkyDescription.of(
        sun_elevation_deg=sun_elevation_deg, atmosphere=atmosphere, weather=weather, night=False
    )
    with Sky(description) as sky:
        sky.render(EquirectCamera(), 16, 8, altitude_m=altitude_m, exposure=None)
        out = _ground_light(sky, altitude_m)
    out.pop("eclipse_fraction")  # a Sun alone has none
    out["sun_elevation_deg"] = float(sun_elevation_deg)
    return out


def _ground_light(sky: Sky, altitude_m: float | None = None) -> dict[str, float]:
    """The light under ``sky`` at ``altitude_m`` above sea level (default: its ground, a
    place's elevation) with the keys of :func:`weather_illuminance` and ``eclipse_fraction``:
    a clear sky's from the tables (``eclipse_illuminance.state_illuminance`` of its lights,
    an eclipse included); under its clouds, fog or precipitation the diffuse light and the
    zenith from the cloud layer's sky probe (the uneclipsed part), the direct light the
    clear sky's times their transmittance towards the Sun there. The cloud layer's probe
    must have been drawn (a frame rendered from there)."""
    air, _, config = sky.description.effective
    clear = state_illuminance(sky.state, atmosphere=air, config=config, altitude_m=altitude_m)
    eclipse = float(clear["eclipse_fraction"])
    out = {
        "sun_elevation_deg": float(clear["sun_elevation_deg"]),  # the airless one
        "altitude_m": float(clear["altitude_m"]),
        "direct_horizontal_lux": float(clear["direct_horizontal_lux"]),
        "diffuse_horizontal_lux": float(clear["diffuse_horizontal_lux"]),
        "zenith_luminance_cd_m2": float(clear["zenith_luminance_cd_m2"]),
    }
    clouds = next((la for la in sky.layers if la.name == "clouds"), None)
    if clouds is not None:
        probe = clouds.sky_probe()
        # the point above the ground (the clouds count from it)
        above_ground_m = clear["altitude_m"] - sky.state.ground_m
        through = float(clouds.light_transmittance(np.array([0.0, 0.0, above_ground_m])))
        luminance = np.asarray(SRGB_LUMINANCE, float)
        keep = 1.0 - eclipse
        out["direct_horizontal_lux"] *= through
        out["diffuse_horizontal_lux"] = float(luminance @ probe.irradiance[:3]) * keep
        out["zenith_luminance_cd_m2"] = (
            float(luminance @ probe.radiance[0, :, :3].mean(axis=0)) * keep
        )
        out["sun_transmittance"] = through
    out["total_horizontal_lux"] = out["direct_horizontal_lux"] + out["diffuse_horizontal_lux"]
    out["eclipse_fraction"] = eclipse
    return out


def ground_illuminance(sky: Sky) -> dict[str, float]:
    """Horizontal illuminance at the ground (lx) under ``sky``, as ``skydome illuminance``
    computes it (the batch manifest's columns): ``direct_horizontal_lux`` (the Sun),
    ``diffuse_horizontal_lux`` (the sky), ``global_horizontal_lux`` (their sum),
    ``zenith_luminance_cd_m2`` and ``eclipse_fraction`` (see :func:`_ground_light`; a sky
    with clouds must have drawn a frame)."""
    light = _ground_light(sky)
    return {
        "direct_horizontal_lux": light["direct_horizontal_lux"],
        "diffuse_horizontal_lux": light["diffuse_horizontal_lux"],
        "global_horizontal_lux": light["total_horizontal_lux"],
        "zenith_luminance_cd_m2": light["zenith_luminance_cd_m2"],
        "eclipse_fraction": light["eclipse_fraction"],
    }


def place_weather_illuminance(
    observer, time: Any, weather: Weather, atmosphere: AtmosphereParams
) -> dict[str, float]:
    """The light at the ground of a place (``observer``, its elevation) at ``time`` under
    ``weather``: the keys of :func:`weather_illuminance` and ``eclipse_fraction``, from the
    place's own sky (its Sun at its distance, a solar eclipse, the clouds counted from the
    place's ground), as a render of it draws them."""
    description = SkyDescription.of(
        observer, time, atmosphere, weather=weather, night=False, light_pollution=None
    )
    with Sky(description) as sky:
        sky.render(EquirectCamera(), 16, 8, exposure=None)
        return _ground_light(sky)
