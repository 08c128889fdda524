// Scattered light along a view ray, shared by the precomputation passes that march rays:
// the ray from radius r (km) with view cosine mu to the ground (hits_ground) or the top, length
// L = ray_length(r, mu, hits_ground), with the Sun at cosines (mu_s, nu). Both integrals use the
// Gauss-Legendre rules of atmosphere/precompute_common.glsl (RAY_SAMPLES nodes) and fill the wavelength
// groups g0 <= g < g1 of their outputs (the others are zero): passes that compute one group per
// fragment ask for that one only. The group loops run over all NUM_GROUPS and skip the others:
// constant bounds let the compiler unroll them (a loop from g0 to g1 made the field pass 40%
// slower on llvmpipe).
#include "atmosphere/precompute_common.glsl"

// Single scattering without its phase functions, per unit solar irradiance (dimensionless):
//   S_i(x, v, s) = integral_0^L beta_i rho_i(y) T(x, y) T(y, sun) dt,  i in {R, M},
// beta_i in km^-1, t in km (seed 004 5.2.2.1, Bruneton 2017 ComputeSingleScattering), with
// T(y, sun) = 0 in the planet's shadow (a point Sun), over the sunlit part of the ray
// (lit_rule_node). nu is the same all along the ray, so the radiance (sr^-1) is
// P_R(nu) S_R + P_M(nu) S_M.
void single_scattering_integrals(float r, float mu, float mu_s, float nu, bool hits_ground, int g0,
                                 int g1, out vec4 rayleigh[NUM_GROUPS], out vec4 mie[NUM_GROUPS]) {
    for (int g = 0; g < NUM_GROUPS; ++g) {
        rayleigh[g] = vec4(0.0);
        mie[g] = vec4(0.0);
    }
    float L = ray_length(r, mu, hits_ground);
    vec3 c0 = column_to_top(r, hits_ground ? -mu : mu);
    LitRule rule = lit_rule(r, mu, lit_segments(r, mu, mu_s, nu, L));
    for (int i = 0; i < RAY_SAMPLES; ++i) {
        float t, dt;
        lit_rule_node(rule, i, r, mu, t, dt);
        float r_t, mu_t, mu_s_t;
        ray_point(r, mu, mu_s, nu, t, r_t, mu_t, mu_s_t);
        vec3 c_sun = column_to_sun(r_t, mu_s_t);
        if (c_sun.x < 0.0 || dt <= 0.0) continue;  // in the planet's shadow
        vec3 c = view_column(c0, r_t, mu_t, hits_ground) + c_sun;
        vec3 d = densities(r_t - u_bottom_radius) * dt;
        for (int g = 0; g < NUM_GROUPS; ++g) {
            if (g < g0 || g >= g1) continue;
            vec4 T = exp(-optical_depth(g, c));
            rayleigh[g] += u_rayleigh_scattering[g] * (d.x * T);
            mie[g] += u_mie_scattering[g] * (d.y * T);
        }
    }
}

// Radiance of the orders >= 2 arriving at the ray's start, per unit solar irradiance (sr^-1):
//   L(x, v, s) = integral_0^L T(x, y) J(y, v, s) dt
// (Bruneton 2017 ComputeMultipleScattering), t in km, J (sr^-1 km^-1) from `density`, a log
// table of the smooth mappings with NUM_GROUPS tables stacked in depth (grid `density_size`).
void scattered_radiance(sampler3D density, vec4 density_size, float r, float mu, float mu_s,
                        float nu, bool hits_ground, int g0, int g1, out vec4 radiance[NUM_GROUPS]) {
    for (int g = 0; g < NUM_GROUPS; ++g) radiance[g] = vec4(0.0);
    float L = ray_length(r, mu, hits_ground);
    vec3 c0 = column_to_top(r, hits_ground ? -mu : mu);
    RaySplit rule = whole_ray_split(r, mu, L);
    for (int i = 0; i < RAY_SAMPLES; ++i) {
        float t, dt;
        split_ray_node(rule, i, r, mu, t, dt);
        float r_t, mu_t, mu_s_t;
        ray_point(r, mu, mu_s, nu, t, r_t, mu_t, mu_s_t);
        vec3 c = view_column(c0, r_t, mu_t, hits_ground);
        vec4 uvwz = scattering_uvwz(r_t, mu_t, mu_s_t, nu, hits_ground, density_size, true);
        float fade = sun_cutoff_fade(mu_s_t);
        for (int g = 0; g < NUM_GROUPS; ++g) {
            if (g < g0 || g >= g1) continue;
            vec4 J = exp(sample_scattering(density, uvwz, density_size, g, NUM_GROUPS)) * fade;
            radiance[g] += J * exp(-optical_depth(g, c)) * dt;
        }
    }
}

#ifdef NU_PER_FRAGMENT
// scattered_radiance for NU_PER_FRAGMENT views that share (r, mu, mu_s) and differ in nu (all
// groups): the ray's nodes, its view columns and transmittances do not depend on nu, so they
// are computed once; only the Sun's cosine along the ray and the lookups of J are per view.
// radiance[g * NU_PER_FRAGMENT + t] = group g of view t, for g0 <= g < g1 (the others are
// zero); the same sums as scattered_radiance.
void scattered_radiance_views(sampler3D density, vec4 density_size, float r, float mu,
                              float mu_s, float nu[NU_PER_FRAGMENT], bool hits_ground, int g0,
                              int g1, out vec4 radiance[NUM_GROUPS * NU_PER_FRAGMENT]) {
    for (int k = 0; k < NUM_GROUPS * NU_PER_FRAGMENT; ++k) radiance[k] = vec4(0.0);
    float L = ray_length(r, mu, hits_ground);
    vec3 c0 = column_to_top(r, hits_ground ? -mu : mu);
    RaySplit rule = whole_ray_split(r, mu, L);
    for (int i = 0; i < RAY_SAMPLES; ++i) {
        float t, dt;
        split_ray_node(rule, i, r, mu, t, dt);
        float r_t, mu_t, mu_s_t;
        ray_point(r, mu, mu_s, nu[0], t, r_t, mu_t, mu_s_t);
        vec3 c = view_column(c0, r_t, mu_t, hits_ground);
        vec4 T[NUM_GROUPS];
        for (int g = 0; g < NUM_GROUPS; ++g) {
            if (g < g0 || g >= g1) continue;
            T[g] = exp(-optical_depth(g, c));
        }
        for (int v = 0; v < NU_PER_FRAGMENT; ++v) {
            ray_point(r, mu, mu_s, nu[v], t, r_t, mu_t, mu_s_t);
            vec4 uvwz = scattering_uvwz(r_t, mu_t, mu_s_t, nu[v], hits_ground, density_size, true);
            float fade = sun_cutoff_fade(mu_s_t);
            for (int g = 0; g < NUM_GROUPS; ++g) {
                if (g < g0 || g >= g1) continue;
                vec4 J = exp(sample_scattering(density, uvwz, density_size, g, NUM_GROUPS)) * fade;
                radiance[g * NU_PER_FRAGMENT + v] += J * T[g] * dt;
            }
        }
    }
}
#endif
