// The radiance field of one scattering order on the coarse grid: for each radius r_k and Sun
// cosine mu_s_j of the grid of J and each direction of the sphere quadrature, the radiance
// L_n arriving at (r_k) from that direction, times the direction's solid angle.
// Texel (x, y): x = group * N_DIR + direction, y = k * MU_S + j.
//
// Order 1 (FIELD_SINGLE): single scattering, with its phase functions, marched directly (no
// table interpolation), plus the Sun's light reflected once by the ground.
// Order n >= 2: L_n = integral T(y, q) J_n(q) dq along the ray (Bruneton 2017,
// ComputeMultipleScattering) plus, for rays that hit the ground, T alpha/pi E_{n-1}(ground)
// (the light of order n whose last bounce is on the ground; Bruneton puts it in J, seed 004
// 5.2.2.3: J[T alpha/pi dE + dS]).
// Both J_{n+1} = beta P (x) L_n (atmosphere/precompute_density.glsl) and the ground irradiance
// E_n = integral L_n cos (atmosphere/precompute_ground_irradiance.glsl) are sums over this field: the
// radiance of a point does not depend on the view direction, so it is computed once per
// (r, mu_s, direction) instead of once per texel of the 4D table and direction.
// Orders >= 2 (FIELD_SINGLE 0) with NU_PER_FRAGMENT > 1: a fragment computes that many azimuths
// j = block * NU_PER_FRAGMENT + t of one cosine a, output t each (texel x = group * N_MU *
// PHI_DRAWN / NU_PER_FRAGMENT + a * PHI_DRAWN / NU_PER_FRAGMENT + block; precompute.py
// reorders): they share
// the ray's nodes, columns and transmittances (which depend on the cosine only).
// Only the azimuths j < PHI_DRAWN are drawn (texel x = group * N_MU * PHI_DRAWN +
// a * PHI_DRAWN + j): the field is mirror-symmetric about the Sun's vertical plane (the air is
// spherically symmetric, and the azimuths (j + 1/2) 2 pi / N_PHI pair up as j, N_PHI - 1 - j,
// whose rays have the same nu), and precompute.py fills in the others (they came out
// bit-identical when drawn).
#ifndef NU_PER_FRAGMENT
#define NU_PER_FRAGMENT 1
#endif
#ifndef PHI_DRAWN
#define PHI_DRAWN N_PHI
#endif
#include "atmosphere/precompute_ray.glsl"

uniform vec4 u_density_size;             // the grid of J (NU, MU_S, MU, R)
uniform sampler3D u_density;             // log J_n, NUM_GROUPS tables stacked in depth (n >= 2)
uniform sampler2D u_ground_irradiance;   // log E_{n-1} on the ground: x = mu_s (table mapping), y = group

#if FIELD_SINGLE || NU_PER_FRAGMENT == 1
out vec4 frag;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    int g = p.x / (N_MU * PHI_DRAWN);
    int i = p.x - g * (N_MU * PHI_DRAWN);
    int a = i / PHI_DRAWN;
    int j = i - a * PHI_DRAWN;
    int n_mu_s = int(u_density_size.y);
    int k = p.y / n_mu_s;
    int jm = p.y - k * n_mu_s;

    float r, mu_unused, mu_s, nu_unused;
    bool hg_unused;
    scattering_texel_params(ivec2(jm, 0), k, u_density_size, true, r, mu_unused, mu_s, nu_unused,
                            hg_unused);
    float weight;
    vec3 omega = quadrature_direction(a, j, r, weight);
    float mu = omega.z;
    float nu = dot(omega, sun_in_frame(mu_s));
    bool hits_ground = a >= N_MU_SKY;  // the quadrature is split at the horizon
    float Rb = u_bottom_radius;

    // Along the ray, for this texel's group g only.
#if FIELD_SINGLE
    vec4 ray_r[NUM_GROUPS];
    vec4 ray_m[NUM_GROUPS];
    single_scattering_integrals(r, mu, mu_s, nu, hits_ground, g, g + 1, ray_r, ray_m);
    vec4 radiance = rayleigh_phase(nu) * ray_r[g] + mie_phase_group(nu, g) * ray_m[g];
#else
    vec4 ray[NUM_GROUPS];
    scattered_radiance(u_density, u_density_size, r, mu, mu_s, nu, hits_ground, g, g + 1, ray);
    vec4 radiance = ray[g];
#endif
    if (hits_ground) {
        float L = ray_length(r, mu, true);
        float mu_g = clamp_cosine((r * mu + L) / Rb);
        float mu_s_g = clamp_cosine((r * mu_s + L * nu) / Rb);
        vec4 T = exp(-optical_depth(g, view_column(column_to_top(r, -mu), Rb, mu_g, true)));
#if FIELD_SINGLE
        // Direct sunlight on the ground (point Sun): mu_s T_sun.
        vec3 c_sun = column_to_sun(Rb, mu_s_g);
        vec4 E = (c_sun.x < 0.0 || mu_s_g <= 0.0) ? vec4(0.0)
                                                  : mu_s_g * exp(-optical_depth(g, c_sun));
#else
        vec2 uv = vec2(texcoord_from_unit(mu_s_unit_smooth(u_bottom_radius, mu_s_g), u_density_size.y),
                       (float(g) + 0.5) / float(NUM_GROUPS));
        vec4 E = exp(texture(u_ground_irradiance, uv)) * sun_cutoff_fade(mu_s_g);
#endif
        radiance += u_ground_albedo[g] * INV_PI * T * E;
    }
    frag = radiance * weight;
}
#else
#define NV NU_PER_FRAGMENT
layout(location = 0) out vec4 frags[NV];

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    const int per_group = N_MU * PHI_DRAWN / NV;
    const int blocks = PHI_DRAWN / NV;
    int g = p.x / per_group;
    int i = p.x - g * per_group;
    int a = i / blocks;
    int block = i - a * blocks;
    int n_mu_s = int(u_density_size.y);
    int k = p.y / n_mu_s;
    int jm = p.y - k * n_mu_s;

    float r, mu_unused, mu_s, nu_unused;
    bool hg_unused;
    scattering_texel_params(ivec2(jm, 0), k, u_density_size, true, r, mu_unused, mu_s, nu_unused,
                            hg_unused);
    float weight;
    float nus[NV];
    float mu;
    for (int t = 0; t < NV; ++t) {
        vec3 omega = quadrature_direction(a, block * NV + t, r, weight);
        mu = omega.z;
        nus[t] = dot(omega, sun_in_frame(mu_s));
    }
    bool hits_ground = a >= N_MU_SKY;  // the quadrature is split at the horizon
    float Rb = u_bottom_radius;
    vec4 ray[NUM_GROUPS * NV];
    scattered_radiance_views(u_density, u_density_size, r, mu, mu_s, nus, hits_ground, g, g + 1,
                             ray);
    float L = ray_length(r, mu, true);
    float mu_g = clamp_cosine((r * mu + L) / Rb);
    vec4 T = hits_ground
                 ? exp(-optical_depth(g, view_column(column_to_top(r, -mu), Rb, mu_g, true)))
                 : vec4(0.0);
    for (int t = 0; t < NV; ++t) {
        vec4 radiance = ray[g * NV + t];
        if (hits_ground) {
            float mu_s_g = clamp_cosine((r * mu_s + L * nus[t]) / Rb);
            vec2 uv = vec2(texcoord_from_unit(mu_s_unit_smooth(u_bottom_radius, mu_s_g), u_density_size.y),
                           (float(g) + 0.5) / float(NUM_GROUPS));
            vec4 E = exp(texture(u_ground_irradiance, uv)) * sun_cutoff_fade(mu_s_g);
            radiance += u_ground_albedo[g] * INV_PI * T * E;
        }
        frags[t] = radiance * weight;
    }
}
#endif
