"""How-to: the night sky. Paranal on a moonless night: the stars, the planets, the Milky
Way, the airglow and the zodiacal light; then light pollution, night vision and overlays.
Writes night-*.png/.exr to the output folder (the first argument, or
$SKYDOME_EXAMPLES_OUT, or ./out)."""

import os
import sys
from pathlib import Path

from skydome import Sky
from skydome.core.cameras import FisheyeCamera
from skydome.io import write_outputs
from skydome.night import City, LightPollution, luminance_to_mag, zenith_brightness

out = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SKYDOME_EXAMPLES_OUT", "out"))
out.mkdir(parents=True, exist_ok=True)

# A dark site on a moonless night: the galactic centre is high in the sky.
sky = Sky("Paranal", "2024-07-05T04:00Z")
print([layer.name for layer in sky.layers])
allsky = sky.render(FisheyeCamera(), 256, 256, tonemap="filmic")
write_outputs(
    [out / "night-allsky.png", out / "night-allsky.exr"],
    allsky.data,
    allsky.image,
    metadata=allsky.info,
)
zenith = allsky.luminance[128, 128]  # cd/m^2 at the centre of the fisheye: the zenith
print(f"zenith {zenith:.3g} cd/m^2 = {float(luminance_to_mag(zenith)):.2f} mag/arcsec^2")
print("glow layers at the zenith (mag/arcsec^2):", zenith_brightness(sky.state, sky.layers))

# Each layer can be turned off, e.g. to see how much the air's own glow adds (same EV).
south = sky.render(sky.camera("south", fov_deg=100), 320, 180, tonemap="filmic")
for name in ("airglow", "zodiacal_light"):
    sky.layer(name).enabled = False
no_glow = sky.render(
    sky.camera("south", fov_deg=100),
    320,
    180,
    exposure=south.info["exposure_ev100"],
    tonemap="filmic",
)
write_outputs(out / "night-south.png", None, south.image)
write_outputs(out / "night-south-no-glow.png", None, no_glow.image)
for name in ("airglow", "zodiacal_light"):
    sky.layer(name).enabled = True

# Light pollution: a Bortle class (1-9), or a model with a uniform part and city domes.
town = Sky("Paranal", "2024-07-05T04:00Z", light_pollution=8)
glow = LightPollution(
    zenith_mag_arcsec2=21.5,
    lamp="led4000",
    cities=[City(azimuth_deg=300, distance_km=40, population=2e6)],
)
city = Sky("Paranal", "2024-07-05T04:00Z", light_pollution=glow)
for label, s in (("bortle8", town), ("city", city)):
    frame = s.render(s.camera("west", fov_deg=100), 320, 180, tonemap="filmic")
    z = s.render(s.camera("zenith", fov_deg=5), 8, 8, exposure=None).luminance.mean()
    print(
        f"{label}: zenith {float(luminance_to_mag(z)):.2f} mag/arcsec^2, "
        f"auto exposure EV100 {frame.info['exposure_ev100']:.1f}"
    )
    write_outputs(out / f"night-{label}.png", None, frame.image)

# Display passes, on the image only (frame.data stays physical): night vision (colour
# fades, acuity blur, noise) and overlays (constellation lines, names, an alt/az grid).
eye = Sky("Paranal", "2024-07-05T04:00Z", night_vision=True, overlays="lines,labels,grid")
frame = eye.render(eye.camera("south", fov_deg=100), 480, 270, tonemap="filmic")
write_outputs(out / "night-eye.png", None, frame.image)
