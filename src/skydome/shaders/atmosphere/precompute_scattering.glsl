// Single-scattering tables, one texel per (r, mu, mu_s, nu) (layered: one layer per r), as
// (R, G, B, scotopic) luminance per unit solar irradiance (u_spectral_to_table), each divided
// by its normalization F (lit_density, atmosphere/precomputed_params.glsl) and by u_table_scale:
//   location 0: single Rayleigh scattering without its phase function, / F_R;
//   location 1: single Mie scattering without its phase function, / F_M.
// Bruneton 2017 / seed 004 5.2.2.3 store C_R = S_R[L0] / P_R and C_M = S_M[L0] / P_M and apply
// the phase functions at lookup. Mie is kept in its own table because its phase function is
// sharply peaked (g ~ 0.8): multiplying a table interpolated in nu by P_M is far more accurate
// than interpolating P_M-weighted values, and the Rayleigh/Mie ratio changes with the view
// (seed 004 fig. 8.10; Bruneton's single-texture variant extrapolates Mie's colour and is off
// by percents). The orders >= 2 have their own table (atmosphere/precompute_ms_scattering.glsl).
//
// Single scattering (seed 004 5.2.2.1, Bruneton 2017 ComputeSingleScattering):
//   S_i(x, v, s) = integral_0^L beta_i rho_i(y) T(x, y) T(y, sun) dt,  i in {R, M},
// with T(y, sun) = 0 in the planet's shadow (a point Sun, like the single-scattering renderer),
// integrated over the sunlit part of the ray (single_scattering_integrals, atmosphere/precompute_ray.glsl)
// at every render wavelength, then converted with u_spectral_to_table.
#include "atmosphere/precompute_ray.glsl"

uniform vec4 u_scattering_size;   // (NU, MU_S, MU, R) of the table being written
uniform float u_table_scale;      // stored = value / F * u_table_scale (float16 range)

flat in int v_layer;
layout(location = 0) out vec4 out_rayleigh;
layout(location = 1) out vec4 out_mie;

void main() {
    float r, mu, mu_s, nu;
    bool hits_ground;
    scattering_texel_params(ivec2(gl_FragCoord.xy), v_layer, u_scattering_size, false, r, mu, mu_s, nu,
                            hits_ground);
    vec4 ray_r[NUM_GROUPS];
    vec4 ray_m[NUM_GROUPS];
    single_scattering_integrals(r, mu, mu_s, nu, hits_ground, 0, NUM_GROUPS, ray_r, ray_m);
    vec4 rayleigh = vec4(0.0);
    vec4 mie = vec4(0.0);
    for (int g = 0; g < NUM_GROUPS; ++g) {
        rayleigh += u_spectral_to_table[g] * ray_r[g];
        mie += u_spectral_to_table[g] * ray_m[g];
    }
    vec2 F = lit_density(r, mu, mu_s, nu, ray_length(r, mu, hits_ground));
    out_rayleigh = F.x > 0.0 ? rayleigh * (u_table_scale / F.x) : vec4(0.0);
    out_mie = F.y > 0.0 ? mie * (u_table_scale / F.y) : vec4(0.0);
}
