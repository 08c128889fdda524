"""Illuminance on the ground from the Sun and the sky, and the zenith luminance.

Evaluated on the GPU from the precomputed tables (``precompute_probe``), for arrays of Sun
elevations. Horizontal surfaces; tilted ones via ``precompute_probe.sun_and_sky_irradiance``.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from skydome.atmosphere import precompute_probe as probe
from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.atmosphere.presets import preset
from skydome.atmosphere.tables import shared_tables
from skydome.errors import check_range
from skydome.gpu import shared_context
from skydome.spectra import SRGB_LUMINANCE


@dataclass(frozen=True)
class Illuminance:
    """Horizontal illuminance (lx) and zenith luminance (cd/m^2) for one Sun elevation."""

    sun_elevation_deg: float
    altitude_m: float
    direct_horizontal_lux: float
    diffuse_horizontal_lux: float
    total_horizontal_lux: float
    zenith_luminance_cd_m2: float
    #: Scotopic counterparts (scotopic lx, scotopic cd/m^2), for night vision.
    total_horizontal_scotopic_lux: float
    zenith_scotopic_luminance: float

    def to_dict(self) -> dict[str, float]:
        return asdict(self)


def horizontal_illuminance(
    sun_elevation_deg,
    *,
    altitude_m: float = 0.0,
    atmosphere: str | AtmosphereParams = "earth",
    config: PrecomputeConfig | None = None,
    sun_scale: float = 1.0,
    beam_elevation_deg=None,
    beam_scale=1.0,
    ctx=None,
) -> list[Illuminance]:
    """Direct (Sun) and diffuse (sky) illuminance on a horizontal surface, and the zenith
    luminance, for each Sun elevation (degrees, -90..90). ``sun_scale`` multiplies the
    params' solar irradiance (e.g. (1 AU / distance)^2).

    ``beam_elevation_deg`` (one per Sun elevation; default: the same): the elevation the
    direct beam arrives from, the refracted (apparent) one: its transmittance
    and its cosine on the surface are that direction's (the straight ray at the apparent
    elevation stands for the bent one, whose air mass is a function of the apparent elevation:
    Kasten & Young 1989), while the sky is lit by the Sun's airless direction, as the tables
    hold it. Within 0.3 deg of the horizon this is what lets a Sun that is seen, drawn above
    it, light the ground. ``beam_scale`` (one per Sun elevation; default 1) multiplies the
    direct beam: the refraction's flattening of a low Sun (``place_illuminance``)."""
    params = preset(atmosphere) if isinstance(atmosphere, str) else atmosphere
    els = np.atleast_1d(np.asarray(sun_elevation_deg, dtype=np.float64))
    beams = (
        els
        if beam_elevation_deg is None
        else np.broadcast_to(np.asarray(beam_elevation_deg, dtype=np.float64), els.shape)
    )
    scales = np.broadcast_to(np.asarray(beam_scale, dtype=np.float64), els.shape)
    for e in (*els, *beams):
        check_range("sun elevation", e, -90.0, 90.0, "deg")
    check_range("altitude", altitude_m, 0.0, params.atmosphere_height_m, "m")
    # the set in GPU memory for a sky that holds it (else loaded, and freed after the call:
    # a loop of calls, a batch of thousands, leaks nothing)
    tables, _ = shared_tables(ctx or shared_context(), params, config)
    sun_scale = sun_scale * params.solar_scale  # the tables hold the tabulated (1 AU) Sun
    up = np.tile([0.0, 0.0, 1.0], (len(els), 1))
    out = []
    for el, beam_el, beam_scale_el in zip(els, beams, scales, strict=True):
        sun = _direction(el)
        direct, sky = probe.sun_and_sky_irradiance(tables, up[:1], sun, altitude_m=altitude_m)
        if beam_el != el:
            direct, _ = probe.sun_and_sky_irradiance(
                tables, up[:1], _direction(beam_el), altitude_m=altitude_m
            )
        direct = direct * beam_scale_el
        zenith, _ = probe.sky_radiance(tables, up[:1], sun, altitude_m=altitude_m)
        d = float(direct[0, :3] @ SRGB_LUMINANCE) * sun_scale
        s = float(sky[0, :3] @ SRGB_LUMINANCE) * sun_scale
        out.append(
            Illuminance(
                sun_elevation_deg=float(el),
                altitude_m=float(altitude_m),
                direct_horizontal_lux=max(d, 0.0),
                diffuse_horizontal_lux=max(s, 0.0),
                total_horizontal_lux=max(d, 0.0) + max(s, 0.0),
                zenith_luminance_cd_m2=float(zenith[0, :3] @ SRGB_LUMINANCE) * sun_scale,
                total_horizontal_scotopic_lux=float(direct[0, 3] + sky[0, 3]) * sun_scale,
                zenith_scotopic_luminance=float(zenith[0, 3]) * sun_scale,
            )
        )
    return out


def _direction(elevation_deg: float) -> np.ndarray:
    """The unit vector at ``elevation_deg`` above the horizon (azimuth: x)."""
    e = math.radians(elevation_deg)
    return np.array([math.cos(e), 0.0, math.sin(e)])
