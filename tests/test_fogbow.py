"""The fogbow through Sky: a fog's droplets scatter by their own size's phase function
(Clouds.fog_droplet_um from Weather(fog_droplet_um=)), so the fogbow's radius follows them."""

from __future__ import annotations

import numpy as np
import pytest


@pytest.mark.gl
def test_the_fogbow_follows_the_droplets_size():
    # a shallow fog (40 m, 300 m of visibility) lit by a Sun 10 deg up behind the camera,
    # seen along the antisolar vertical: the fog brightens towards the horizon, the bows ride
    # on it. The frame of 5 um droplets over that of 20 um ones peaks where the small drops'
    # fogbow is and dips where the large ones' is (Airy: 144.6 and 140.5 deg from the Sun;
    # measured ~144 and 140.4): the small drops' bow more than 2 deg nearer the antisolar
    # point, by 2 % or more of the light
    from skydome import Sky
    from skydome.weather import Weather
    from tests.antisolar_strip import antisolar_strip

    camera, w, h, theta = antisolar_strip()
    bow = (theta > 136.0) & (theta < 150.0)
    light = {}
    for droplet_um in (5.0, 20.0):
        weather = Weather("fog", visibility_km=0.3, fog_top_m=40.0, fog_droplet_um=droplet_um)
        with Sky(sun_elevation_deg=10.0, sun_azimuth_deg=270.0, weather=weather) as sky:
            light[droplet_um] = sky.render(camera, w, h, exposure=None).data[:, 2, 1]
    ratio = (light[5.0] / light[20.0])[bow]
    small, large = theta[bow][np.argmax(ratio)], theta[bow][np.argmin(ratio)]
    assert small - large > 2.0, (small, large)
    assert ratio.max() - ratio.min() > 0.02
