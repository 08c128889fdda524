"""Quick tour: the Python API in a few lines. Writes tour-*.png/.exr to the output folder
(the first argument, or $SKYDOME_EXAMPLES_OUT, or ./out)."""

import os
import sys
from pathlib import Path

from skydome import FisheyeCamera, PerspectiveCamera, Sky
from skydome.display import auto_exposure, tonemap
from skydome.io import write_outputs

out = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SKYDOME_EXAMPLES_OUT", "out"))
out.mkdir(parents=True, exist_ok=True)

# 1. A sky for a place and a time: the Sun, the Moon, the stars where they are.
# --8<-- [start:sky]
sky = Sky("Valletta", "2018-03-01T16:52Z")  # a gazetteer name; naive times are UTC
frame = sky.render(sky.camera("sun", fov_deg=60), 320, 180, tonemap="filmic")
# --8<-- [end:sky]
print(sky)
print("frame.data", frame.data.shape, frame.data.dtype, "(linear sRGB, Y in cd/m^2, scotopic)")
print(
    f"Sun at {frame.info['sun_elevation_deg']:.2f} deg, exposure EV100 "
    f"{frame.info['exposure_ev100']:.1f}, brightest pixel {frame.luminance.max():.3g} cd/m^2"
)
write_outputs(
    [out / "tour-sunset.png", out / "tour-sunset.exr"], frame.data, frame.image, metadata=frame.info
)

# 2. The same sky later: the tables are reused, only the lights move.
night = sky.at("2018-03-01T20:00Z")
frame = night.render(FisheyeCamera(), 256, 256, tonemap="filmic")
write_outputs(out / "tour-night-allsky.png", None, frame.image)

# 3. A Sun alone (no place, no time), the frame in cd/m^2 tone mapped in NumPy.
with Sky(sun_elevation_deg=5, sun_azimuth_deg=250) as sun_alone:  # its GPU memory freed after
    camera = PerspectiveCamera(fov_deg=90, yaw_deg=250, pitch_deg=10)
    frame = sun_alone.render(camera, 320, 180, exposure=None)
image = tonemap(frame, "filmic", auto_exposure(frame, clip_percentile=99.5))
write_outputs(
    [out / "tour-sun5.png", out / "tour-sun5.exr"], frame.data, image, metadata=frame.info
)
print(f"Sun 5 deg: its disk peaks at {frame.luminance.max():.3g} cd/m^2")
