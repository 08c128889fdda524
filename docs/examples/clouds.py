"""How-to: clouds. Fair-weather cumulus over Valletta in the morning, the same sky an hour
later (the wind has moved them), an overcast deck, a weather map of your own, and the
clouds' shadow on a scene (a shadow map). Writes clouds-*.png/.exr to the output folder (the
first argument, or $SKYDOME_EXAMPLES_OUT, or ./out)."""

import os
import sys
from pathlib import Path

import numpy as np

from skydome import Clouds, Sky
from skydome.clouds.layer import CloudLayer
from skydome.io import write_outputs

out = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SKYDOME_EXAMPLES_OUT", "out"))
out.mkdir(parents=True, exist_ok=True)

# Fair-weather cumulus: bases at 1.5 km, 40 % of the sky, a 5 m/s west wind (towards east).
clouds = Clouds("fair", coverage=0.4, base_m=1500, thickness_m=1800, wind_m_s=(5, 0), seed=1)
sky = Sky("Valletta", "2021-06-21T08:00Z", clouds=clouds, night=False)
camera = sky.camera("east", fov_deg=90, pitch_deg=20)
frame = sky.render(camera, 320, 180, tonemap="filmic")
write_outputs([out / "clouds-fair.png", out / "clouds-fair.exr"], frame.data, frame.image)
print(sky.layer("clouds").info(), f"EV100 {frame.info['exposure_ev100']:.2f}")

# The same clouds an hour later: the wind has carried them 18 km, the Sun is higher.
later = sky.at("2021-06-21T09:00Z").render(camera, 320, 180, tonemap="filmic")
write_outputs([out / "clouds-fair-later.png"], later.data, later.image)

# An overcast stratocumulus deck (the presets: fair, overcast, storm, cirrus, clear).
overcast = Sky("Valletta", "2021-06-21T08:00Z", clouds="overcast", night=False)
grey = overcast.render(camera, 320, 180, tonemap="filmic")
write_outputs([out / "clouds-overcast.png"], grey.data, grey.image)

# A weather map of your own: coverage in a (H, W) array over a 20 km tile, here a band of
# cloud running north-south; 'weather=' also takes an image file.
x = np.linspace(0, 1, 256, endpoint=False)
band = np.clip(1.5 - 6 * np.abs(x - 0.5), 0, 1)[None, :].repeat(256, axis=0)
mine = Sky(
    "Valletta",
    "2021-06-21T08:00Z",
    night=False,
    clouds=Clouds("fair", coverage=1.0, weather=band, tile_km=20.0),
)
banded = mine.render(mine.camera("zenith", fov_deg=120), 256, 256, tonemap="filmic")
write_outputs([out / "clouds-own-map.png"], banded.data, banded.image)

# The clouds' shadow on a scene: transmittance towards the Sun at points (east, north, up m).
layer: CloudLayer = sky.layer("clouds")
xs = np.arange(-5000.0, 5001.0, 1000.0)
ground = np.stack([xs, np.zeros_like(xs), np.zeros_like(xs)], axis=-1)
print(
    "sunlight reaching the ground along an east-west line:",
    layer.light_transmittance(ground).round(2),
)
