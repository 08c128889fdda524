"""How-to: an HDRI for Blender. Writes an equirect EXR in cd/m^2 without the Sun's disk, the
same with the disk, and blender-settings.json (world strength, Sun lamp strength, angle and
rotation) to the output folder (the first argument, or $SKYDOME_EXAMPLES_OUT, or ./out)."""

import json
import math
import os
import sys
from pathlib import Path

import numpy as np

from skydome import Sky
from skydome.astro.frames import AU_KM
from skydome.atmosphere.illuminance import horizontal_illuminance
from skydome.core.cameras import EquirectCamera
from skydome.io import read_exr, write_outputs
from skydome.spectra import PHOTOPIC_EFFICACY_LM_PER_W, SRGB_LUMINANCE  # 683 lm/W: Blender's too

out = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SKYDOME_EXAMPLES_OUT", "out"))
out.mkdir(parents=True, exist_ok=True)
WIDTH, HEIGHT = 512, 256  # small for the docs; 4096 x 2048 or more for a real scene

sky = Sky("Valletta", "2018-03-01T09:00Z")
sun = sky.state.sun

# 1. The map without the Sun's disk: Blender's Sun lamp brings the direct light instead
#    (a disk a few pixels wide in a map is noisy to sample). RGB only: any reader sees it.
sky.layer("sun").enabled = False
frame = sky.render(EquirectCamera(), WIDTH, HEIGHT)
write_outputs(out / "sky-no-sun.exr", frame.data[..., :3], metadata=frame.info)

# 2. The same map with the disk, for renderers that sample the map's Sun well.
sky.layer("sun").enabled = True
with_sun = sky.render(EquirectCamera(), WIDTH, HEIGHT)
write_outputs(out / "sky-with-sun.exr", with_sun.data[..., :3], metadata=with_sun.info)

# The Sun lamp: the direct beam at the camera through the same atmosphere, on a surface
# facing the Sun. The air is lit from the Sun's airless (unrefracted) direction.
elevation_true = math.degrees(math.asin(sun.direction_true[2]))
(ill,) = horizontal_illuminance(
    elevation_true, altitude_m=sky.altitude_m(), sun_scale=(AU_KM / sun.distance_km) ** 2
)
direct_normal_lux = ill.direct_horizontal_lux / math.sin(math.radians(elevation_true))

# Its colour: the disk alone (with it minus without it) through a 2-degree camera, summed
# over the pixels' solid angles: the beam's RGB illuminance (lx), whose luminance is the
# same direct-normal illuminance.
zoom = sky.camera("sun", fov_deg=2.0)
disk = sky.render(zoom, 128, 128, exposure=None).rgb
sky.layer("sun").enabled = False
disk = disk - sky.render(zoom, 128, 128, exposure=None).rgb
sky.layer("sun").enabled = True
pixel_sr = (math.radians(2.0) / 128) ** 2  # small field: every pixel ~ the same solid angle
beam_rgb_lux = disk.reshape(-1, 3).sum(axis=0) * pixel_sr
colour = beam_rgb_lux / beam_rgb_lux.max()  # Blender's lamp colour, brightest channel 1

# Check that the map is absolute: its upper hemisphere, weighted by the cosine, is the
# diffuse illuminance on a horizontal surface (lx).
data, _ = read_exr(out / "sky-no-sun.exr")
lum = data @ SRGB_LUMINANCE.astype(np.float32)  # cd/m^2
elev = (0.5 - (np.arange(HEIGHT) + 0.5) / HEIGHT) * math.pi  # pixel-centre elevations
d_omega = (2 * math.pi / WIDTH) * (math.pi / HEIGHT) * np.cos(elev)  # sr per pixel
up = elev > 0
diffuse_from_map = float(np.sum(lum[up] * (np.sin(elev) * d_omega)[up, None]))

settings = {
    "exr": "sky-no-sun.exr",
    "world_strength": 1.0 / PHOTOPIC_EFFICACY_LM_PER_W,  # cd/m^2 -> W/(m^2 sr)
    "mapping_rotation_z_deg": 90.0,  # north on Blender's +Y, east on +X
    "sun_strength_w_m2": direct_normal_lux
    / PHOTOPIC_EFFICACY_LM_PER_W
    / float(colour @ SRGB_LUMINANCE),  # strength x colour keeps the luminance
    "sun_colour_linear_rgb": colour.tolist(),
    "sun_angle_deg": math.degrees(2 * sun.angular_radius_rad),
    "sun_rotation_euler_deg": [90.0 - sun.elevation_deg, 0.0, 180.0 - sun.azimuth_deg],
    "film_exposure_stops": math.log2(PHOTOPIC_EFFICACY_LM_PER_W / 1.2)
    - frame.info["exposure_ev100"],
    "sun_elevation_deg": sun.elevation_deg,
    "sun_azimuth_deg": sun.azimuth_deg,
    "direct_normal_lux": direct_normal_lux,
    "direct_normal_lux_from_disk": float(beam_rgb_lux @ SRGB_LUMINANCE),
    "diffuse_horizontal_lux": ill.diffuse_horizontal_lux,
    "diffuse_horizontal_lux_from_map": diffuse_from_map,
}
(out / "blender-settings.json").write_text(json.dumps(settings, indent=2))
print(json.dumps(settings, indent=2))
