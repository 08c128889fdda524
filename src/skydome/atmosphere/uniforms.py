"""Atmosphere parameters as shader uniforms (km and per-km values, vec4 wavelength groups)."""

from __future__ import annotations

import math

import numpy as np

from skydome.atmosphere.params import AtmosphereParams, DensityProfile
from skydome.physics.constants import M_PER_KM

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


def geometry_uniforms(params: AtmosphereParams) -> dict[str, object]:
    """Radii (km) and density profiles: what the transmittance table depends on."""
    bottom, top = params.bottom_radius_m / M_PER_KM, params.top_radius_m / M_PER_KM
    return {
        "u_bottom_radius": bottom,
        "u_top_radius": top,
        "u_horizon_length": (top * top - bottom * bottom) ** 0.5,
        "u_kink_radius": mie_kink_radius_km(params),
        **profile_uniforms(
            (params.rayleigh_density, params.mie_density, params.absorption_density),
            params.atmosphere_height_m,
        ),
    }


def spectral_uniforms(params: AtmosphereParams, wavelengths_nm) -> dict[str, object]:
    """Per-wavelength coefficients per km, grouped in vec4s (``len(wavelengths) % 4 == 0``)."""
    c = params.coefficients(wavelengths_nm)

    def vec4s(values: np.ndarray, scale: float = 1.0) -> list[float]:
        return [float(v) for v in np.asarray(values, float) * scale]

    return {
        "u_rayleigh_scattering": vec4s(c["rayleigh_scattering"], M_PER_KM),
        "u_mie_scattering": vec4s(c["mie_scattering"], M_PER_KM),
        "u_mie_extinction": vec4s(c["mie_extinction"], M_PER_KM),
        "u_absorption_extinction": vec4s(c["absorption_extinction"], M_PER_KM),
        "u_ground_albedo": vec4s(c["ground_albedo"]),
        "u_mie_g": float(params.mie_g),
        "u_sun_angular_radius": float(params.sun_angular_radius_rad),
        **mie_lobe_uniforms(params, wavelengths_nm),
    }


def mie_phase_defines(params: AtmosphereParams) -> dict[str, object]:
    """``MIE_LOBES`` (the lobe count) for an atmosphere with a spectral phase function
    (``params.mie_phase``; common/mie_phase.glsl), else nothing: Cornette-Shanks of u_mie_g."""
    return {} if params.mie_phase is None else {"MIE_LOBES": len(params.mie_phase.lobe_g)}


def mie_lobe_uniforms(params: AtmosphereParams, wavelengths_nm) -> dict[str, object]:
    """``u_mie_lobe_g`` and ``u_mie_lobe_weight`` (group-major vec4s: for each group of 4
    wavelengths, each lobe's weights at them) of a spectral phase function, else nothing."""
    phase = params.mie_phase
    if phase is None:
        return {}
    w = phase.weights_at(wavelengths_nm)  # (wavelengths, lobes)
    groups = w.reshape(-1, 4, w.shape[1])  # (group, 4, lobe)
    return {
        "u_mie_lobe_g": [float(g) for g in phase.lobe_g],
        "u_mie_lobe_weight": [float(v) for v in np.transpose(groups, (0, 2, 1)).ravel()],
    }
