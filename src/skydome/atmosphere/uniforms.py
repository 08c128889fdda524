"""Atmosphere parameters as shader uniforms (km and per-km values, vec4 wavelength groups)."""

from __future__ import annotations

import numpy as np

from skydome.atmosphere.params import AtmosphereParams, DensityProfile

M_PER_KM = 1000.0


def profile_uniform(profiles: tuple[DensityProfile, ...]) -> list[float]:
    """Flatten density profiles into ``u_profile``: per layer (width, exp, scale, linear, const), km."""
    out: list[float] = []
    for profile in profiles:
        for layer in profile.layers:
            out += [
                layer.width_m / M_PER_KM,
                layer.exp_term,
                layer.exp_scale_per_m * M_PER_KM,
                layer.linear_per_m * M_PER_KM,
                layer.constant,
            ]
    return out


def geometry_uniforms(params: AtmosphereParams) -> dict[str, object]:
    """Radii (km) and density profiles: what the transmittance table depends on."""
    bottom, top = params.bottom_radius_m / M_PER_KM, params.top_radius_m / M_PER_KM
    return {
        "u_bottom_radius": bottom,
        "u_top_radius": top,
        "u_horizon_length": (top * top - bottom * bottom) ** 0.5,
        "u_profile": profile_uniform(
            (params.rayleigh_density, params.mie_density, params.absorption_density)
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
    }
