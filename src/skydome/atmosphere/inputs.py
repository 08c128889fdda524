"""The atmosphere's shader inputs: its parameters as typed uniform blocks (km and per-km
values, vec4 wavelength groups), and the blocks of its tables' lookups.

- :class:`AirGeometry`: radii and density profiles (``common/atmosphere_common.glsl``);
- :class:`AirSpectra`: scattering and extinction per wavelength, the phase functions'
  parameters, the conversion to output channels;
- :class:`TransmittanceInputs`: the transmittance table;
- :class:`LookupInputs`: all of those and the precomputed tables, as
  ``atmosphere/precomputed_lookup.glsl`` reads them (what the clouds get from the air);
- :class:`SkyViewInputs`, :class:`ViewTransmittanceInputs`, :class:`FrameMapsInputs`: the
  frame passes' tables of the camera's height and a user's per-pixel maps.

The aerial-perspective tables' and the lights' blocks are the air's service contract
(``skydome.core.services``: ``AerialInputs``, ``LightInputs``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skydome.atmosphere.params import AtmosphereParams, DensityProfile
from skydome.gpu.inputs import ShaderInputs
from skydome.physics.constants import M_PER_KM
from skydome.physics.packing import mat4_groups
from skydome.spectra import conversion_matrix

#: Samples per constituent of ``u_profile_table`` (PROFILE_TABLE_SIZE in common/atmosphere_common.glsl).
PROFILE_TABLE_SIZE = 256
#: What the table stores for ln(0) (PROFILE_LOG_ZERO in common/atmosphere_common.glsl): exp of it is 0
#: in float32, and any sample at or below it makes its neighbours' interpolation linear.
PROFILE_LOG_ZERO = -1.0e4


def profile_uniform(profiles: tuple[DensityProfile, ...]) -> list[float]:
    """Flatten density profiles into ``u_profile``: per layer (width, exp, scale, linear, const), km.

    A tabulated profile has no layers: its ten entries are 0 (the shader reads its table).
    """
    out: list[float] = []
    for profile in profiles:
        if profile.is_tabulated:
            out += [0.0] * 10
            continue
        for layer in profile.layers:
            out += [
                layer.width_m / M_PER_KM,
                layer.exp_term,
                layer.exp_scale_per_m * M_PER_KM,
                layer.linear_per_m * M_PER_KM,
                layer.constant,
            ]
    return out


def profile_table_grid(profile: DensityProfile, top_m: float) -> tuple[float, int]:
    """The uniform altitude grid a tabulated profile is sampled on for the GPU: (step m, count).

    The grid starts at the ground and reaches at least ``top_m`` with at most
    ``PROFILE_TABLE_SIZE`` samples. When the table's altitudes are whole metres and their
    greatest common divisor gives few enough samples, that is the step (500 m for the US
    Standard Atmosphere 1976 and the AFGL ozone tables): every table sample is a grid node,
    each grid cell lies within one table segment, and the shader's log-linear interpolation
    is :meth:`DensityProfile.density` exactly (a linear piece next to a 0 is exact only where
    it spans one cell). Otherwise the step is top / (PROFILE_TABLE_SIZE - 1) and the profile
    is resampled log-linearly onto it.
    """
    alt = np.asarray(profile.altitudes_m)
    whole = np.round(alt)
    if np.all(np.abs(alt - whole) <= 1e-6):
        step = float(np.gcd.reduce(np.abs(whole).astype(np.int64)))
        if step > 0.0:
            count = math.ceil(top_m / step - 1e-9) + 1
            if count <= PROFILE_TABLE_SIZE:
                return step, max(count, 2)
    return top_m / (PROFILE_TABLE_SIZE - 1), PROFILE_TABLE_SIZE


def profile_uniforms(profiles: tuple[DensityProfile, ...], top_m: float) -> dict[str, object]:
    """The density profiles' uniforms (``u_profile``, ``u_profile_inv_step`` 1/km,
    ``u_profile_last``, ``u_profile_table`` of ln densities) for an atmosphere ``top_m`` thick."""
    inv_step = [0.0, 0.0, 0.0]
    last = [1.0, 1.0, 1.0]
    table = np.full((len(profiles), PROFILE_TABLE_SIZE), PROFILE_LOG_ZERO)
    for c, profile in enumerate(profiles):
        if not profile.is_tabulated:
            continue
        step_m, count = profile_table_grid(profile, top_m)
        d = profile.density(step_m * np.arange(count))
        with np.errstate(divide="ignore"):
            table[c, :count] = np.where(
                d > 0.0, np.log(np.where(d > 0.0, d, 1.0)), PROFILE_LOG_ZERO
            )
        inv_step[c] = M_PER_KM / step_m
        last[c] = float(count - 1)
    return {
        "u_profile": profile_uniform(profiles),
        "u_profile_inv_step": tuple(inv_step),
        "u_profile_last": tuple(last),
        "u_profile_table": table.ravel().tolist(),
    }


def profile_defines(params: AtmosphereParams) -> dict[str, object]:
    """``PROFILE_FORMS`` for every shader that includes common/atmosphere_common.glsl: bit c set when
    constituent c (Rayleigh, Mie, absorption) is tabulated, bit c + 3 when its GPU table holds
    a zero (linear pieces). It makes the profile forms compile-time constants (see the
    shader); shaders compiled without it decide at run time, at a cost on CPU renderers."""
    profiles = (params.rayleigh_density, params.mie_density, params.absorption_density)
    top = params.atmosphere_height_m
    forms = 0
    for c, profile in enumerate(profiles):
        if profile.is_tabulated:
            forms |= 1 << c
            step_m, count = profile_table_grid(profile, top)
            if np.any(profile.density(step_m * np.arange(count)) <= 0.0):
                forms |= 1 << (c + 3)
    return {"PROFILE_FORMS": forms}


def mie_kink_radius_km(params: AtmosphereParams) -> float:
    """Radius (km) of the boundary between a layered aerosol profile's two layers, where its
    ln density has a kink (the mixing-layer top of the OPAC types), or 0: the precomputation's
    ray quadrature splits there (atmosphere/precompute_common.glsl, split_node)."""
    profile = params.mie_density
    if profile.is_tabulated:
        return 0.0
    lower, upper = profile.layers
    if lower == upper or not 0.0 < lower.width_m < params.atmosphere_height_m:
        return 0.0
    return (params.bottom_radius_m + lower.width_m) / M_PER_KM


@dataclass(frozen=True)
class AirGeometry(ShaderInputs):
    """Radii (km) and density profiles: what the transmittance table depends on."""

    u_bottom_radius: float
    u_top_radius: float
    u_horizon_length: float
    u_profile: list[float]
    u_profile_inv_step: tuple[float, float, float]
    u_profile_last: tuple[float, float, float]
    u_profile_table: list[float]


@dataclass(frozen=True)
class AirSpectra(ShaderInputs):
    """Per-wavelength coefficients per km in vec4 groups, the ground's albedo, the Mie phase
    function's parameters (one Cornette-Shanks g, or weights of HG lobes per group), the
    Sun's angular radius, and the conversion of spectral values to the output channels
    (one mat4 per group)."""

    u_rayleigh_scattering: list[float]
    u_mie_scattering: list[float]
    u_mie_extinction: list[float]
    u_absorption_extinction: list[float]
    u_ground_albedo: list[float]
    u_mie_g: float
    u_sun_angular_radius: float
    u_spectral_to_rgbs: list[float]
    u_mie_lobe_g: list[float] | None = None
    u_mie_lobe_weight: list[float] | None = None


@dataclass(frozen=True)
class TransmittanceInputs(ShaderInputs):
    """The transmittance table (column densities, km) and its size (texels)."""

    u_transmittance_lut: object
    u_transmittance_size: tuple[int, int]


@dataclass(frozen=True)
class LookupInputs(ShaderInputs):
    """The precomputed tables as ``atmosphere/precomputed_lookup.glsl`` reads them: the air,
    the transmittance, the tables' mappings and encodings, the per-channel weights of the
    light behind the air, and the four tables."""

    geometry: AirGeometry
    spectra: AirSpectra
    transmittance: TransmittanceInputs
    u_transmittance_to_output: list[float]
    u_table_to_output: list[float]
    u_mu_s_min: float
    u_mu_s_knee: float
    u_scattering_size: tuple[float, float, float, float]
    u_scattering_scale: float
    u_multiple_scattering_size: tuple[float, float, float, float]
    u_multiple_scattering_log_range: tuple[float, float]
    u_irradiance_size: tuple[float, float]
    u_behind_transmittance: list[float]
    u_scattering_texture: object
    u_single_mie_texture: object
    u_multiple_scattering_texture: object
    u_irradiance_spectral: object


@dataclass(frozen=True)
class SkyViewInputs(ShaderInputs):
    """The frame pass's sky-view tables of the camera's height: the Sun's and the second
    light's (None without one)."""

    u_sun_scattering: object
    u_sun_single_mie: object
    u_light2_scattering: object = None
    u_light2_single_mie: object = None


@dataclass(frozen=True)
class ViewTransmittanceInputs(ShaderInputs):
    """The view-transmittance table of the camera's height (``view_transmittance.glsl``)
    and the view cosine of its horizon."""

    u_view_transmittance: object
    u_view_horizon_mu: float


@dataclass(frozen=True)
class FrameMapsInputs(ShaderInputs):
    """A user's per-pixel inputs of a tile (textures, km; None: not given): the distance to
    a scene along each ray, the length of each ray in an occluder's shadow."""

    u_depth_map: object = None
    u_shadow_map: object = None


def geometry_inputs(params: AtmosphereParams) -> AirGeometry:
    """Radii (km) and density profiles of ``params``."""
    bottom, top = params.bottom_radius_m / M_PER_KM, params.top_radius_m / M_PER_KM
    profiles = profile_uniforms(
        (params.rayleigh_density, params.mie_density, params.absorption_density),
        params.atmosphere_height_m,
    )
    return AirGeometry(
        u_bottom_radius=bottom,
        u_top_radius=top,
        u_horizon_length=(top * top - bottom * bottom) ** 0.5,
        u_profile=profiles["u_profile"],
        u_profile_inv_step=profiles["u_profile_inv_step"],
        u_profile_last=profiles["u_profile_last"],
        u_profile_table=profiles["u_profile_table"],
    )


def spectra_inputs(params: AtmosphereParams, wavelengths_nm, output: str = "rgbs") -> AirSpectra:
    """Per-wavelength coefficients per km, grouped in vec4s (``len(wavelengths) % 4 == 0``),
    and the conversion to ``output`` channels."""
    c = params.coefficients(wavelengths_nm)

    def vec4s(values: np.ndarray, scale: float = 1.0) -> list[float]:
        return [float(v) for v in np.asarray(values, float) * scale]

    lobes = mie_lobe_uniforms(params, wavelengths_nm)
    return AirSpectra(
        u_rayleigh_scattering=vec4s(c["rayleigh_scattering"], M_PER_KM),
        u_mie_scattering=vec4s(c["mie_scattering"], M_PER_KM),
        u_mie_extinction=vec4s(c["mie_extinction"], M_PER_KM),
        u_absorption_extinction=vec4s(c["absorption_extinction"], M_PER_KM),
        u_ground_albedo=vec4s(c["ground_albedo"]),
        u_mie_g=float(params.mie_g),
        u_sun_angular_radius=float(params.sun_angular_radius_rad),
        u_spectral_to_rgbs=mat4_groups(conversion_matrix(wavelengths_nm, output)),
        u_mie_lobe_g=lobes.get("u_mie_lobe_g"),
        u_mie_lobe_weight=lobes.get("u_mie_lobe_weight"),
    )


def mie_phase_defines(params: AtmosphereParams) -> dict[str, object]:
    """``MIE_LOBES`` (the lobe count) for an atmosphere with a spectral phase function
    (``params.mie_phase``; common/mie_phase.glsl), else nothing: Cornette-Shanks of u_mie_g."""
    return {} if params.mie_phase is None else {"MIE_LOBES": len(params.mie_phase.lobe_g)}


def broadened_lobe_uniforms(
    params: AtmosphereParams, wavelengths_nm, g_max: float
) -> dict[str, object]:
    """:func:`mie_lobe_uniforms` with every lobe's g capped at ``g_max`` and the lobes that
    then share a g merged into one (their weights summed): the phase function the density
    pass of the orders >= 2 uses (precompute_density.glsl), with fewer lobes to evaluate
    (Mars's dust: the 5 lobes of g 0.83-0.98 become one of g 0.8, 10 lobes 6)."""
    phase = params.mie_phase
    if phase is None:
        return {}
    capped = np.minimum(np.asarray(phase.lobe_g, dtype=float), g_max)
    merged_g, lobe_of = np.unique(capped, return_inverse=True)
    w = phase.weights_at(wavelengths_nm)  # (wavelengths, lobes)
    merged = np.zeros((w.shape[0], merged_g.size))
    np.add.at(merged, (slice(None), lobe_of.ravel()), w)
    return _lobe_uniforms(merged_g, merged)


def mie_lobe_uniforms(params: AtmosphereParams, wavelengths_nm) -> dict[str, object]:
    """``u_mie_lobe_g`` and ``u_mie_lobe_weight`` (group-major vec4s: for each group of 4
    wavelengths, each lobe's weights at them) of a spectral phase function, else nothing."""
    phase = params.mie_phase
    if phase is None:
        return {}
    return _lobe_uniforms(phase.lobe_g, phase.weights_at(wavelengths_nm))


def _lobe_uniforms(lobe_g, weights) -> dict[str, object]:
    """The lobes' ``u_mie_lobe_g`` and their ``weights`` (wavelengths, lobes) as
    ``u_mie_lobe_weight``'s group-major vec4s (for each group of 4 wavelengths, each lobe's
    weights at them)."""
    groups = np.asarray(weights).reshape(-1, 4, len(lobe_g))  # (group, 4, lobe)
    return {
        "u_mie_lobe_g": [float(g) for g in lobe_g],
        "u_mie_lobe_weight": [float(v) for v in np.transpose(groups, (0, 2, 1)).ravel()],
    }
