"""How-to: composite a scene with aerial perspective: ridges at 3, 15 and 60 km under a low
Sun. A Sky gives the light scattered in front of each pixel's scene point and the
transmittance to it. Writes aerial-*.png/.exr to the output folder (the first
argument, or $SKYDOME_EXAMPLES_OUT, or ./out)."""

import os
import sys
from pathlib import Path

import numpy as np

from skydome import PerspectiveCamera, Sky
from skydome.display import auto_exposure, tonemap
from skydome.io import write_outputs

out = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SKYDOME_EXAMPLES_OUT", "out"))
out.mkdir(parents=True, exist_ok=True)
W, H = 320, 180

# A Sun 6 deg up in the west-southwest over the default air (tables from the cache, or ~3 s
# on a CPU). The camera stands on a 1500 m summit looking a little down at three ridges.
sky = Sky(sun_elevation_deg=6.0, sun_azimuth_deg=250.0)
camera = PerspectiveCamera(fov_deg=60, yaw_deg=230, pitch_deg=-2)
altitude_m = 1500.0

# Your scene, rendered by anything: its radiance in cd/m^2 (linear sRGB) and, per pixel, the
# distance in metres along the view ray to what the pixel shows (inf: only sky there).
# Distances past the point where a ray meets the ground are taken as that point.
x, y = np.arange(W)[None, :], np.arange(H)[:, None]
depth_m = np.full((H, W), np.inf)
for distance_m, top_row, wave_rows in ((60e3, 70, 4), (15e3, 84, 6), (3e3, 104, 8)):
    top = top_row + wave_rows * np.sin(2 * np.pi * x / W * (1 + distance_m / 2e4))
    depth_m = np.where(y >= top, distance_m, depth_m)  # nearer ridges hide farther ones
scene_rgb = np.where(np.isfinite(depth_m)[..., None], [12.0, 16.0, 9.0], 0.0)  # dark hills

# One call gives the sky where the depth is inf, and in front of the scene the light
# scattered between the camera and the scene point; frame.info["transmittance"] is the
# (H, W, 3) transmittance to that point.
air = sky.render(camera, W, H, altitude_m=altitude_m, depth_m=depth_m, exposure=None)
transmittance = air.info["transmittance"]
composite = scene_rgb * transmittance + air.rgb  # cd/m^2

for distance_m in (3e3, 15e3, 60e3):
    at = depth_m == distance_m
    print(
        f"{distance_m / 1e3:4.0f} km: transmittance (R, G, B) "
        f"{np.round(transmittance[at].mean(axis=0), 3)}, "
        f"in-scattered {air.luminance[at].mean():.0f} cd/m^2"
    )

frame = np.dstack([composite, air.data[..., 3]]).astype(np.float32)  # keep the scotopic
scale = auto_exposure(frame, clip_percentile=99.5)
write_outputs(
    [out / "aerial-composite.png", out / "aerial-composite.exr"],
    frame,
    tonemap(frame, "filmic", scale),
)
no_air = np.where(np.isfinite(depth_m)[..., None], scene_rgb, air.rgb)  # the scene pasted in
write_outputs(
    out / "aerial-without.png",
    None,
    tonemap(np.dstack([no_air, air.data[..., 3]]), "filmic", scale),
)
sky.release()  # the GPU memory now (garbage collection would do it too)
