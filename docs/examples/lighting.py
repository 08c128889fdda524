"""How-to: light for a 3D scene. For Valletta at 10:00 local time with fair-weather cumulus:
the Sun and the Moon as lights, the sky's 9 spherical-harmonic coefficients and 16
directional lights, written as lighting.json, the sky map (the disks split out) as
lighting-sky.exr, and a preview, lighting-preview.png: the map tone mapped, each light a
circle at its direction, its area proportional to its illuminance; then the prefiltered GGX
cube map (split sum) as lighting-env.dds, its BRDF table as lighting-brdf.exr, and a preview
of the cube, lighting-cube.png: three of its mip levels as crosses (the output folder is the
first argument, or $SKYDOME_EXAMPLES_OUT, or ./out)."""

import json
import math
import os
import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from skydome import Sky
from skydome.display import auto_exposure, tonemap
from skydome.io import write_outputs
from skydome.io.dds import write_dds_cube
from skydome.io.table_exr import write_table_exr
from skydome.lighting_ibl import TABLE_DESCRIPTION, brdf_table

out = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SKYDOME_EXAMPLES_OUT", "out"))
out.mkdir(parents=True, exist_ok=True)

with Sky("Valletta", "2018-03-01T10:00", clouds="fair") as sky:
    light = sky.lighting(size=(256, 128))
    cube = light.prefiltered(sky.graph.ctx)  # the sky alone: 128-texel faces, 6 mip levels
    table = brdf_table(sky.graph.ctx)  # 128 x 128: (scale, bias) of F0

(out / "lighting.json").write_text(json.dumps(light.as_dict(), indent=2))
write_outputs([out / "lighting-sky.exr"], light.sky_map.data, metadata=light.sky_map.info)
sun = light.sun
print(f"Sun: {sun.illuminance_lux:.0f} lx facing it, {sun.angular_radius_deg:.3f} deg radius")
print(
    f"sky on a horizontal surface: {light.irradiance([[0, 0, 1]])[0] @ [0.2126, 0.7152, 0.0722]:.0f} lx"
)
for li in light.lights:
    print(
        " light",
        np.round(li.direction, 3),
        f"{np.dot(li.illuminance_rgb, [0.2126, 0.7152, 0.0722]):.0f} lx",
    )

# The preview: the map (north at the left edge, east a quarter across) and the lights.
frame = light.sky_map
image = Image.fromarray(tonemap(frame, "filmic", auto_exposure(frame))).resize((768, 384))
draw = ImageDraw.Draw(image)
peak = max(np.dot(li.illuminance_rgb, [0.2126, 0.7152, 0.0722]) for li in light.lights)
for li in [*light.lights, sun]:
    x, y, z = li.direction
    u = (math.degrees(math.atan2(x, y)) % 360.0) / 360.0 * image.width
    v = (0.5 - math.degrees(math.asin(z)) / 180.0) * image.height
    lux = np.dot(li.illuminance_rgb, [0.2126, 0.7152, 0.0722])
    r = 4 if li is sun else 3 + 14 * math.sqrt(lux / peak)
    draw.ellipse(
        [u - r, v - r, u + r, v + r],
        outline=(255, 80, 40) if li is sun else (40, 220, 255),
        width=2,
    )
image.save(out / "lighting-preview.png")

# The prefiltered cube map (cd/m^2, half floats) and the BRDF table, for a renderer.
write_dds_cube(out / "lighting-env.dds", cube.levels)
write_table_exr(out / "lighting-brdf.exr", table, TABLE_DESCRIPTION)
print(
    "cube levels (roughness: mean luminance, cd/m^2):",
    ", ".join(f"{r:.1f}: {cube.mean_luminance(k):.0f}" for k, r in enumerate(cube.roughness)),
)

# Its preview: levels 0, 2 and 5 (roughness 0, 0.4, 1) as crosses, one exposure for all.
crosses = [np.kron(cube.cross(k), np.ones((2**k, 2**k, 1))) for k in (0, 2, 5)]
strip = np.concatenate(crosses, axis=1)
hdr = np.concatenate([strip, np.zeros((*strip.shape[:2], 1))], axis=-1).astype(np.float32)
ldr = tonemap(hdr, "filmic", auto_exposure(frame))
Image.fromarray(ldr).save(out / "lighting-cube.png")
