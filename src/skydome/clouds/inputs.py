"""The cloud layer's shader inputs (``shaders/clouds/``), typed."""

from __future__ import annotations

from dataclasses import dataclass

from skydome.gpu.inputs import ShaderInputs


@dataclass(frozen=True)
class CloudInputs(ShaderInputs):
    """The march's own uniforms (``clouds/cloud_*.glsl``): the key light (direction, scale
    per channel), the shells' radii (km), the fog's and the precipitation's under the
    clouds (radii km, extinctions 1/km), the noises' tiles (km) and the wind's offset,
    the extinctions per cloud type and of the cirrus (1/km, delta-M scaled), the detail's
    erosion, the water's normalisation per type and coverage, the droplets' phase-function moments, the march's steps, the
    ground's albedo below, the frame's jitter, the multiple-scattering table's norms; for
    tests a fixed irradiance and a uniform extinction; for the light shafts their length
    (km)."""

    u_light_direction: tuple[float, float, float]
    u_light_scale: tuple[float, float, float, float]
    u_cloud_shell: tuple[float, float, float, float]
    u_ground_layer: tuple[float, float, float, float]
    u_ground_extinction: tuple[float, float, float]
    u_noise_tiles_km: tuple[float, float, float]
    u_cloud_offset_km: tuple[float, float, float]
    u_type_extinction: tuple[float, float, float, float]
    u_cirrus_extinction: float
    u_detail_erosion: float
    u_water_norm: list[float]
    u_cloud_moments: tuple[float, float, float]
    u_march: tuple[float, float, float]
    u_light_march_km: tuple[float, float]
    u_cloud_albedo_below: float
    u_frame_jitter: float
    u_peak_scale: float
    u_ms_norm_g: list[float]
    u_sky_light_ratio: tuple[float, float, float, float] = (1.0, 1.0, 1.0, 1.0)
    u_ambient_radiance: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    u_under_sky_ratio: tuple[float, float, float, float] = (1.0, 1.0, 1.0, 1.0)
    u_rain_share: float = 1.0
    u_test_irradiance: tuple[float, float, float, float] | None = None
    u_uniform_extinction: float | None = None
    u_shaft_km: float | None = None


@dataclass(frozen=True)
class CloudTextures(ShaderInputs):
    """The clouds' textures: the multiple-scattering table, the droplets' phase function,
    the rain's and the droplets' by output channel, the weather map and the noises (None
    where a pass marches a uniform cloud), the cirrus crystals' halo table (None without
    one), the fog droplets' phase function by output channel (None: the clouds')."""

    u_cloud_ms_table: object
    u_cloud_phase_table: object
    u_rain_phase_table: object
    u_droplet_phase_table: object
    u_weather: object = None
    u_shape_noise: object = None
    u_detail_noise: object = None
    u_curl_noise: object = None
    u_halo_table: object = None
    u_fog_phase_table: object = None


@dataclass(frozen=True)
class CompositeInputs(ShaderInputs):
    """``clouds/clouds_composite.glsl``: the march's radiance and data at their resolution,
    where a pixel falls in them, and the camera (km, planet-centred) with the ground's
    radius (km), to tell a pixel of the ground from one of the sky; with DIRECTION_TABLE,
    the direction table's frame and size (clouds/direction_table.glsl)."""

    u_cloud_radiance: object
    u_cloud_data: object
    u_cloud_map: tuple[float, float, float, float]
    u_ground_sphere: tuple[float, float, float, float]
    u_table_frame: tuple[float, float, float] | None = None
    u_table_size: tuple[float, float] | None = None


@dataclass(frozen=True)
class TemporalInputs(ShaderInputs):
    """``clouds/clouds_temporal.glsl``: the history's weight, the previous camera (basis and
    field, for the reprojection; None for other models), this frame's march and the
    history."""

    u_blend: float
    u_prev_basis: tuple[float, ...] | None
    u_prev_tan_half_fov: float | None
    u_current_radiance: object
    u_current_data: object
    u_history_radiance: object
    u_history_data: object


@dataclass(frozen=True)
class DepthInputs(ShaderInputs):
    """A user's scene: its distance (km, <= 0 where there is none) along each ray of the tile
    (the march compiled with HAS_DEPTH_MAP)."""

    u_depth_map: object


@dataclass(frozen=True)
class CloudDataInputs(ShaderInputs):
    """``clouds/cloud_transmittance.glsl``: the march's data at the frame's resolution."""

    u_cloud_data: object


@dataclass(frozen=True)
class UpsampleInputs(ShaderInputs):
    """``clouds/upsample.glsl``: the source's size over the target's, the source."""

    u_scale: tuple[float, float]
    u_source: object


@dataclass(frozen=True)
class ColumnInputs(ShaderInputs):
    """``clouds/cloud_columns.glsl``: the census grid's spacing (km, east and north)."""

    u_grid_km: tuple[float, float]


@dataclass(frozen=True)
class QueryInputs(ShaderInputs):
    """``clouds/cloud_shadow_query.glsl``: the query points (km, a texture)."""

    u_points: object


@dataclass(frozen=True)
class LightMapInputs(ShaderInputs):
    """The clouds' light map (``clouds/light_map_warp.glsl``): its warp's length, the
    clouds' lowest base's radius and the map's centre's offsets (km); the map itself for the
    march (None for the pass that draws it)."""

    u_light_map_warp: tuple[float, float, float, float]
    u_light_map: object = None
