"""How-to: weather. A foggy morning (the Sun a pale disk), the same fog seen from a hill
above it (a fog sea), a rainy day under nimbostratus and snow at dusk, each with its
visibility and the light on the ground; writes weather-*.png to the output folder (the first
argument, or $SKYDOME_EXAMPLES_OUT, or ./out)."""

import os
import sys
from pathlib import Path

from skydome import Sky
from skydome.io import write_outputs
from skydome.weather import Weather

out = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SKYDOME_EXAMPLES_OUT", "out"))
out.mkdir(parents=True, exist_ok=True)
W, H = 320, 180

# A radiation fog 150 m deep, 200 m of visibility, the Sun 15 deg up in the east.
fog = Weather("fog", visibility_km=0.2, fog_top_m=150)
with Sky(sun_elevation_deg=15, sun_azimuth_deg=90, weather=fog) as sky:
    print(f"fog: visibility {sky.description.visibility_km:.2f} km")
    frame = sky.render(sky.camera("east", fov_deg=80, pitch_deg=8), W, H, tonemap="filmic")
    write_outputs([out / "weather-fog.png"], frame.data, frame.image)
    # from a hill 300 m up, the fog is a sea with its top at 150 m
    frame = sky.render(
        sky.camera("east", fov_deg=80, pitch_deg=-5), W, H, altitude_m=300, tonemap="filmic"
    )
    write_outputs([out / "weather-fog-sea.png"], frame.data, frame.image)

# Moderate rain (4 mm/h, Marshall-Palmer drops) under its nimbostratus deck.
with Sky(sun_elevation_deg=30, weather=Weather("rain", rain_mm_h=4)) as sky:
    print(f"rain: visibility {sky.description.visibility_km:.1f} km")
    frame = sky.render(sky.camera("south", fov_deg=90, pitch_deg=10), W, H, tonemap="filmic")
    write_outputs([out / "weather-rain.png"], frame.data, frame.image)

# Snow at dusk: 1 mm/h of water, the ground white.
with Sky(sun_elevation_deg=2, weather="snow") as sky:
    print(f"snow: visibility {sky.description.visibility_km:.1f} km")
    frame = sky.render(sky.camera("west", fov_deg=90, pitch_deg=10), W, H, tonemap="filmic")
    write_outputs([out / "weather-snow-dusk.png"], frame.data, frame.image)
