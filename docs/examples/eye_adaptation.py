"""How-to (time-lapse): the adapting eye on your own frames. Renders dusk at Valletta every
10 minutes and tone-maps each frame as an adapting eye sees it. Writes eye-*.png to the
output folder (the first argument, or $SKYDOME_EXAMPLES_OUT, or ./out)."""

import os
import sys
from pathlib import Path

import numpy as np

from skydome import Sky
from skydome.display import log_average_luminance, scale_to_ev100, tonemap
from skydome.display.adaptation import EyeAdaptation
from skydome.io import write_outputs

out = Path(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SKYDOME_EXAMPLES_OUT", "out"))
out.mkdir(parents=True, exist_ok=True)


def adapted_images(frames, step_s):
    """Tone-mapped images of frames (in cd/m^2) step_s apart, as an adapting eye sees them."""
    eye = EyeAdaptation()
    for frame in frames:
        eye.update(log_average_luminance(frame, clip_percentile=99.5), dt_s=step_s)
        print(
            f"adapted to {eye.adapted_luminance:8.3g} cd/m^2: EV100 "
            f"{scale_to_ev100(eye.exposure_scale()):5.1f}"
        )
        yield tonemap(frame, "filmic", eye.exposure_scale())


sky = Sky("Valletta", "2018-03-01T16:40Z")
camera = sky.camera("west", fov_deg=90)
times = np.datetime64("2018-03-01T16:40") + np.arange(7) * np.timedelta64(10, "m")
frames = (sky.at(t).render(camera, 160, 90, exposure=None) for t in times)
images = list(adapted_images(frames, step_s=600.0))
write_outputs(out / "eye-dusk-strip.png", None, np.concatenate(images, axis=1))
