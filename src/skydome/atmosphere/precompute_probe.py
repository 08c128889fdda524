"""Evaluate the precomputed-atmosphere lookups at given points and directions (GPU).

A thin driver of ``shaders/atmosphere/precompute_probe.glsl``: one texel per query, read back as NumPy.
For tests, benchmarks and for numbers such as the illuminance at a place (not for images: the
frame pass calls ``atmosphere/precomputed_lookup.glsl`` itself).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from skydome.atmosphere.inputs import LookupInputs
from skydome.atmosphere.precompute import PrecomputedAtmosphere, _program
from skydome.errors import ParameterError
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.textures import release_all
from skydome.physics.constants import M_PER_KM

_MAX_WIDTH = 4096


@dataclass(frozen=True)
class ProbeInputs(ShaderInputs):
    """``atmosphere/precompute_probe.glsl``: the Sun's direction, the shadowed length (km),
    the queries' points (km, planet centred) and directions with distances (textures)."""

    u_sun_direction: tuple[float, float, float]
    u_shadow_length: float
    u_probe_points: object
    u_probe_dirs: object


def _as_rows(a, name: str) -> np.ndarray:
    a = np.asarray(a, dtype=np.float64)
    if a.ndim == 1:
        a = a[None]
    if a.ndim != 2 or a.shape[1] != 3 or not np.all(np.isfinite(a)):
        raise ParameterError(f"{name} must be a finite (N, 3) array, got shape {a.shape}")
    return a


def _run(
    pa: PrecomputedAtmosphere,
    mode: int,
    points_km,
    dirs,
    distances_km,
    sun_direction,
    shadow_length_km: float,
    ground: int,
) -> tuple[np.ndarray, np.ndarray]:
    ctx = pa.ctx
    n = len(dirs)
    w = min(n, _MAX_WIDTH)
    h = -(-n // w)
    pts = np.zeros((h * w, 4), dtype="f4")
    dv = np.zeros((h * w, 4), dtype="f4")
    pts[:n, :3] = points_km
    dv[:n, :3] = dirs
    dv[:n, 3] = distances_km
    tex_p = ctx.texture((w, h), 4, pts.tobytes(), dtype="f4")
    tex_d = ctx.texture((w, h), 4, dv.tobytes(), dtype="f4")
    out = [ctx.texture((w, h), 4, dtype="f4") for _ in range(2)]
    fbo = ctx.framebuffer(color_attachments=out)
    try:
        defines = {**pa.defines(), "PROBE_MODE": mode, "PROBE_GROUND": ground}
        prog = _program(
            ctx, "atmosphere/precompute_probe.glsl", defines, inputs=(LookupInputs, ProbeInputs)
        )
        fbo.viewport = (0, 0, w, h)
        s = np.asarray(sun_direction, dtype=np.float64)
        probe = ProbeInputs(
            tuple(float(v) for v in s / np.linalg.norm(s)), float(shadow_length_km), tex_p, tex_d
        )
        prog.draw(fbo, pa.inputs(), probe)
        res = [
            np.frombuffer(t.read(), dtype="f4").reshape(h * w, 4)[:n].astype(np.float64)
            for t in out
        ]
    finally:
        release_all(fbo, tex_p, tex_d, *out)
    return res[0], res[1]


def camera_points(pa: PrecomputedAtmosphere, altitude_m: float, n: int) -> np.ndarray:
    """(n, 3) planet-centred positions (km) of a camera at ``altitude_m`` above the ground."""
    r = (pa.params.bottom_radius_m + float(altitude_m)) / M_PER_KM
    return np.tile([0.0, 0.0, r], (n, 1))


def sky_radiance(
    pa: PrecomputedAtmosphere,
    directions,
    sun_direction,
    *,
    altitude_m: float = 0.0,
    points_km=None,
    shadow_length_km: float = 0.0,
    ground: str = "none",
) -> tuple[np.ndarray, np.ndarray]:
    """Sky radiance (N, 4) (luminance cd/m^2, or spectral) and column densities (N, 3) (km).

    ``ground``: ``"none"`` (in-scattered light only), ``"sun"`` (add the ground lit by the Sun,
    like the single-scattering renderer) or ``"sun_and_sky"``.
    """
    dirs = _as_rows(directions, "directions")
    pts = (
        camera_points(pa, altitude_m, len(dirs))
        if points_km is None
        else _as_rows(points_km, "points_km")
    )
    mode = {"none": 0, "sun": 1, "sun_and_sky": 2}
    if ground not in mode:
        raise ParameterError(f"ground = {ground!r} must be one of {sorted(mode)}")
    main, extra = _run(pa, 0, pts, dirs, 0.0, sun_direction, shadow_length_km, mode[ground])
    return main, extra[:, :3]


def sky_radiance_to_point(
    pa: PrecomputedAtmosphere,
    directions,
    distances_km,
    sun_direction,
    *,
    altitude_m: float = 0.0,
    shadow_length_km: float = 0.0,
) -> np.ndarray:
    """In-scattered radiance (N, 4) between the camera and the points at ``distances_km``."""
    dirs = _as_rows(directions, "directions")
    dist = np.broadcast_to(np.asarray(distances_km, dtype=np.float64), (len(dirs),))
    pts = camera_points(pa, altitude_m, len(dirs))
    main, _ = _run(pa, 1, pts, dirs, dist, sun_direction, shadow_length_km, 0)
    return main


def sun_and_sky_irradiance(
    pa: PrecomputedAtmosphere, normals, sun_direction, *, altitude_m: float = 0.0, points_km=None
) -> tuple[np.ndarray, np.ndarray]:
    """Direct Sun and sky irradiance (N, 4) each (luminance lx, or spectral) on surfaces."""
    nrm = _as_rows(normals, "normals")
    pts = (
        camera_points(pa, altitude_m, len(nrm))
        if points_km is None
        else _as_rows(points_km, "points_km")
    )
    return _run(pa, 2, pts, nrm, 0.0, sun_direction, 0.0, 0)
