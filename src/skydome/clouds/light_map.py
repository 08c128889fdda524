"""The clouds' light map (``shaders/clouds/cloud_light_map.glsl``): the key light's
transmittance through the clouds' shells along the rays that leave the sphere of their
lowest base towards it, one value per point of that sphere.

A ray towards the light from any point below the clouds' lowest base crosses the same shells
as from where it leaves that sphere, so the full-quality march reads the map for the light of
the air in front of the clouds (12 points a pixel), of the fog and rain under them and of the
ground in their shadows, where it marched each of those light paths through the shells (4
samples a crossing: the map holds the same sums). A texel stands for a point of the sphere
by the point's horizontal offsets (km) from the map's centre, where the light's ray from the
ground under the camera leaves the sphere (:func:`light_map_centre`: the points near the
camera look up the texels near it), warped into the unit disk so that texels are small
there and the disk reaches every distance (``shaders/clouds/light_map_warp.glsl``; these
are its float64 twins).

The map is bilinear between its texels: a cloud's shadow edge, which the point samples put at
one place, is spread over a texel (12 m near the camera, 0.2 km 10 km away, 0.7 km at 20 km).
A shadow's true penumbra, from the Sun's half-degree disk, is about a hundredth of the
distance from the cloud's edge (10-20 m under a cumulus's base).
"""

from __future__ import annotations

import numpy as np

from skydome.physics.geometry import ray_sphere

#: Texels a side of the map, and the warp's length (km): a texel spans 2 a / N km at the
#: centre and (r + a)^2 / a * 2 / N at r km from it. 512 and 3 km: against the "best" quality
#: (the light paths marched at every pixel) a full-quality 1280x720 frame of fair-weather
#: cumulus moved from a mean relative error of 2.79 % to 2.95 % (1024 texels and 10 km, the
#: map centred over the camera: 2.94 %, at four times the map's cost); the march's light
#: paths cost 25-30 % of that frame, the map 31-33 ms (llvmpipe, 2 cores).
LIGHT_MAP_TEXELS = 512
LIGHT_MAP_WARP_KM = 3.0
#: The key light's least elevation (deg) for the map. Below it the light's rays from the air
#: run tens of kilometres to the clouds and through them: a low Sun's 4 samples of a grazing
#: crossing hit or miss a cloud's edge, and a bilinear map of such sums drew frames off the
#: "best" quality by more than the marched paths (fair cumulus, Sun 3 deg up: 11.3 % against
#: 4.6 %, the mean 9 % too bright; a 75 % deck at 1.3-8 deg: 6-12 % against 5-10 %); from 10
#: deg up the two are as close to it (5.0 / 5.1 % and 7.6 / 7.4 % at 10 deg).
LIGHT_MAP_MIN_ELEVATION_DEG = 10.0
#: The least march (texels) for which a map is drawn afresh: the map costs what the light
#: paths of about 50,000 march texels do (a 25-frame time-lapse of fair cumulus at 640x360,
#: a 320x180 march and a map a frame: 440-445 ms a frame against 434-445 marched; at
#: 960x540, 480x270: 711-723 against 736-741 ms). A smaller march goes without a map even
#: where one is drawn for the sky: a full-quality frame is the same whatever came before.
LIGHT_MAP_MIN_MARCH_TEXELS = 100_000
#: Samples of each shell crossing on the march's light paths through the air (the map's too).
LIGHT_PATH_STEPS = 4


def light_map_centre(light, base_radius_km: float, ground_radius_km: float) -> tuple:
    """The map's centre (x, y) (km, planet-centred, the camera on the z axis): where the ray
    towards the unit ``light`` from the ground under the camera (radius ``ground_radius_km``)
    leaves the sphere of the clouds' lowest base (``base_radius_km``)."""
    t = float(ray_sphere((0.0, 0.0, ground_radius_km), light, base_radius_km)[1])
    return (t * float(light[0]), t * float(light[1]))


def light_map_uv(xy_km, a_km: float) -> np.ndarray:
    """Texture coordinates (..., 2) in the light map of a point of the clouds' lowest base
    at horizontal offsets ``xy_km`` (..., 2) (km) from the map's centre, for the warp's
    length ``a_km``."""
    xy = np.asarray(xy_km, dtype=np.float64)
    return 0.5 + 0.5 * xy / (np.linalg.norm(xy, axis=-1, keepdims=True) + a_km)


def light_map_xy(uv, a_km: float) -> np.ndarray:
    """The inverse of :func:`light_map_uv` inside the disk: offsets (..., 2) km."""
    m = 2.0 * np.asarray(uv, dtype=np.float64) - 1.0
    return a_km * m / np.maximum(1.0 - np.linalg.norm(m, axis=-1, keepdims=True), 1e-6)


def texel_points(texels, base_radius_km: float, centre_km=(0.0, 0.0),
                 a_km: float = LIGHT_MAP_WARP_KM, size: int = LIGHT_MAP_TEXELS) -> np.ndarray:  # fmt: skip
    """The points (..., 3) (km, planet-centred) of the sphere of radius ``base_radius_km`` that
    the texels ``texels`` (..., 2) (column, row) of a map of ``size`` texels centred at
    ``centre_km`` stand for (NaN outside the disk or past the sphere's horizon)."""
    uv = (np.asarray(texels, dtype=np.float64) + 0.5) / size
    inside = np.linalg.norm(2.0 * uv - 1.0, axis=-1) < 1.0
    xy = np.asarray(centre_km, dtype=np.float64) + light_map_xy(uv, a_km)
    z2 = base_radius_km**2 - np.sum(xy * xy, axis=-1)
    ok = inside & (z2 > 0.0)
    z = np.sqrt(np.where(ok, z2, np.nan))
    return np.concatenate([np.where(ok[..., None], xy, np.nan), z[..., None]], axis=-1)
