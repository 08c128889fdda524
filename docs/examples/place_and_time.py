"""How-to: a sky for a place and a time. Writes place-*.png/.exr to the output folder
(the first argument, or $SKYDOME_EXAMPLES_OUT, or ./out)."""

import os
import sys
from pathlib import Path

from skydome import Sky
from skydome.astro import Observer, events
from skydome.astro.places import find_place, search
from skydome.core.cameras import EquirectCamera, PerspectiveCamera
from skydome.io import write_outputs

out = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SKYDOME_EXAMPLES_OUT", "out"))
out.mkdir(parents=True, exist_ok=True)

# A place: a gazetteer name, (lat_deg, lon_deg[, elevation_m]) or an Observer (which also
# carries the weather that bends the light: pressure and temperature).
paranal = find_place("Paranal")  # what --place accepts; search("chile") lists a country's
print(paranal.name, paranal.latitude_deg, paranal.longitude_deg, paranal.elevation_m, "m")
print([p.name for p in search("chile", limit=5)])
valletta = Observer(
    latitude=35.90, longitude=14.51, elevation_m=50, pressure_hPa=1015, temperature_C=14
)

# A time: ISO 8601 with an offset or Z. Without one it is the place's local time for a
# gazetteer name ("Valletta"), UTC for an Observer or numbers. 20:00 in Malta is 19:00 UTC.
sky = Sky(valletta, "2018-03-01T20:00+01:00")
s = sky.state
print(
    f"Sun {s.sun.elevation_deg:.2f} deg, Moon {s.moon.elevation_deg:.2f} deg at azimuth "
    f"{s.moon.azimuth_deg:.1f} deg, {100 * s.moon_view.illuminated_fraction:.1f} % lit"
)

# Aim a camera: at a body (look="sun"/"moon"), the zenith or a compass point, or give the
# azimuth (yaw) and elevation (pitch) yourself.
moon = sky.render(sky.camera("moon", fov_deg=40), 320, 180, tonemap="filmic")
east = sky.render(
    PerspectiveCamera(fov_deg=90, yaw_deg=90, pitch_deg=10),
    320,
    180,
    exposure=-2.0,
    tonemap="filmic",
)  # a fixed EV100 instead of "auto"
write_outputs(
    [out / "place-moon.png", out / "place-moon.exr"], moon.data, moon.image, metadata=moon.info
)
write_outputs(out / "place-east.png", None, east.image)

# The same place at other times reuses the tables: only the lights move.
for time in ("2018-03-01T05:30Z", "2018-03-01T12:00Z", "2018-03-01T17:10Z"):
    later = sky.at(time)
    frame = later.render(EquirectCamera(), 256, 128, tonemap="filmic")
    name = "place-" + time[11:16].replace(":", "") + ".png"
    write_outputs(out / name, None, frame.image)
    print(
        f"{time}: Sun {later.state.sun.elevation_deg:6.2f} deg, "
        f"auto exposure EV100 {frame.info['exposure_ev100']:.1f}"
    )

# When things happen there (UTC): sunrise, sunset, twilights, moonrise, phases.
for row in events(valletta, "2018-03-01", days=1).as_list():
    print(row["time"], row["event"], row["body"])
