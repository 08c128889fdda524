"""What lies below the horizon: the ground's kinds (``Sky(ground=...)``, ``--ground``) and the
layer that blacks the ground out for environment maps.

- a number: a grey Lambertian ground of that albedo (0-1), lit by the Sun and the sky and
  seen through the air; the atmosphere's multiple scattering is computed with it too;
- ``"none"``: no ground that reflects (albedo 0 for the surface and the tables): the lower
  hemisphere holds only the light of the air in front of where the ground would be (the
  horizon's haze, the Earth's shadow in it at dusk), dark beneath;
- ``"black"``: exactly zero wherever the camera's ray meets the planet (the sky above keeps
  the atmosphere's own ground light), for HDRIs used with a ground of the user's own;
- None (the default): the atmosphere's own ground albedo.

The horizon is the planet's for the camera's height (a ray below the dip meets the ground),
the same test as the atmosphere's own (``ray_hits_ground``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from skydome.core.cameras import CameraInputs
from skydome.core.layer import BehindInputs, DrawContext, Layer
from skydome.core.services import AirService
from skydome.errors import ParameterError
from skydome.gpu.inputs import ShaderInputs

#: The ground's kinds by name.
GROUND_KINDS = ("none", "black")


def parse_ground(value: str | float | None) -> str | float | None:
    """A ground setting checked: None, "none", "black" or an albedo within [0, 1] (a number
    or its text). ParameterError names the setting otherwise."""
    if value is None:
        return None
    if isinstance(value, bool):
        raise ParameterError(f"ground must be none, black or an albedo 0..1, got {value!r}")
    if isinstance(value, str):
        text = value.strip().lower()
        if text in GROUND_KINDS:
            return text
        try:
            value = float(text)
        except ValueError:
            raise ParameterError(
                f"ground {value!r} must be none, black or an albedo 0..1 (e.g. 0.2)"
            ) from None
    try:
        albedo = float(value)
    except (TypeError, ValueError):
        raise ParameterError(
            f"ground must be none, black or an albedo 0..1, got {value!r}"
        ) from None
    if not (math.isfinite(albedo) and 0.0 <= albedo <= 1.0):
        raise ParameterError(f"ground albedo {value!r} must be within [0, 1]")
    return albedo


def ground_albedo(ground: str | float | None) -> float | None:
    """The albedo the atmosphere is computed with for a ground setting (None: its own)."""
    if ground == "none":
        return 0.0
    if isinstance(ground, float):
        return ground
    return None


@dataclass(frozen=True)
class GroundInputs(ShaderInputs):
    """``atmosphere/ground_black.glsl``: the sine of the ground horizon's dip."""

    u_dip_sin: float


def dip_sin(camera_altitude_m: float, bottom_radius_m: float) -> float:
    """sin of the dip below the horizontal of the horizon of a sphere of ``bottom_radius_m``
    seen from ``camera_altitude_m`` above it (a ray below it meets the sphere)."""
    r = bottom_radius_m + max(float(camera_altitude_m), 0.0)
    return math.sqrt(max(1.0 - (bottom_radius_m / r) ** 2, 0.0))


class BlackGroundLayer(Layer):
    """Zero light wherever the camera's ray meets the ground (volume stage: put it last, after
    the clouds and the weather): the lower hemisphere of an environment map left black. The
    horizon is the atmosphere layer's ground sphere seen from the camera's height."""

    name = "ground"
    stage = "volume"
    shader = "atmosphere/ground_black.glsl"

    def draw(self, frame: DrawContext) -> None:
        air = self.graph.find_service(AirService)
        bottom_m = air.bottom_radius_m if air is not None else 6_371_000.0
        inputs = GroundInputs(u_dip_sin=dip_sin(frame.altitude_m, bottom_m))
        fpass = self.full_screen_pass(
            frame.ctx, self.shader, (CameraInputs, BehindInputs, GroundInputs), frame.camera
        )
        fpass.draw(frame.fbo, frame.view, self.behind_inputs(frame), inputs)
