"""How-to: atmospheres and their knobs. Lists the presets, sets aerosol, ozone and albedo on
one, and renders three skies at one exposure. Writes atmosphere-*.png to the output folder
(the first argument, or $SKYDOME_EXAMPLES_OUT, or ./out)."""

import os
import sys
from pathlib import Path

import numpy as np

from skydome import PerspectiveCamera, Sky
from skydome.atmosphere import PRESETS, preset
from skydome.atmosphere.illuminance import horizontal_illuminance
from skydome.display import ev100_to_scale, tonemap
from skydome.errors import ParameterError
from skydome.io import write_outputs

out = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SKYDOME_EXAMPLES_OUT", "out"))
out.mkdir(parents=True, exist_ok=True)

# The presets, read back by the same integrals the knobs use.
for name in PRESETS:
    p = preset(name)
    print(f"{name:15s} AOD(550) {p.aod_550:6.3f}  ozone {p.ozone_du:5.0f} DU  {p.description}")

# Knobs on top of a preset, as a Blender or pvlib user sets them: aerosol optical depth at
# 550 nm, its Angstrom exponent, total ozone (Dobson units), ground albedo.
smoky = preset("earth", aod_550=0.4, angstrom=1.8, ozone_du=280, albedo=0.15)
print(
    f"smoky: AOD {smoky.aod_550:.3f}, Angstrom {smoky.angstrom_exponent:.2f}, "
    f"ozone {smoky.ozone_du:.0f} DU"
)
# Or one knob at a time, or any field of AtmosphereParams (validated again).
forward = preset("earth").with_aerosol(ssa=0.9).with_(mie_g=0.8)
print(f"forward-scattering aerosol: g = {forward.mie_g}")
try:
    preset("earth", aod_550=7.0)
except ParameterError as exc:  # bad values name the valid range
    print("ParameterError:", exc)

# The same Sun through three atmospheres, at one exposure (EV100 13).
camera = PerspectiveCamera(fov_deg=90, yaw_deg=250, pitch_deg=10)
panels = []
for label, params in (("earth", "earth"), ("hazy", "hazy"), ("smoky", smoky)):
    with Sky(sun_elevation_deg=10, sun_azimuth_deg=250, atmosphere=params) as sky:
        frame = sky.render(camera, 320, 180, exposure=None)
    panels.append(tonemap(frame, "filmic", ev100_to_scale(13.0)))
    (ill,) = horizontal_illuminance(10.0, atmosphere=params)
    print(
        f"{label:6s} Sun 10 deg: direct {ill.direct_horizontal_lux:7.0f} lx, "
        f"diffuse {ill.diffuse_horizontal_lux:6.0f} lx, zenith "
        f"{ill.zenith_luminance_cd_m2:5.0f} cd/m^2"
    )
write_outputs(out / "atmosphere-earth-hazy-smoky.png", None, np.concatenate(panels, axis=1))
