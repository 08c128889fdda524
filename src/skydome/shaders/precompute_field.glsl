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
// Both J_{n+1} = beta P (x) L_n (precompute_density.glsl) and the ground irradiance
// E_n = integral L_n cos (precompute_ground_irradiance.glsl) are sums over this field: the
// radiance of a point does not depend on the view direction, so it is computed once per
// (r, mu_s, direction) instead of once per texel of the 4D table and direction.
#include "precompute_common.glsl"

uniform vec4 u_density_size;             // the grid of J (NU, MU_S, MU, R)
uniform sampler3D u_density;             // log J_n, NUM_GROUPS tables stacked in depth (n >= 2)
uniform sampler2D u_ground_irradiance;   // log E_{n-1} on the ground: x = mu_s (table mapping), y = group

out vec4 frag;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    int g = p.x / N_DIR;
    int i = p.x - g * N_DIR;
    int a = i / N_PHI;
    int j = i - a * N_PHI;
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
    float L = ray_length(r, mu, hits_ground);
    vec3 c0 = column_to_top(r, hits_ground ? -mu : mu);
    float Rb = u_bottom_radius;

    vec4 radiance = vec4(0.0);
#if FIELD_SINGLE
    float phase_r = rayleigh_phase(nu);
    float phase_m = cornette_shanks_phase(nu, u_mie_g);
    vec4 beta = u_rayleigh_scattering[g] * phase_r;
    vec4 beta_m = u_mie_scattering[g] * phase_m;
    vec4 lit = lit_segments(r, mu, mu_s, nu, L);
#endif
    for (int q = 0; q < RAY_SAMPLES; ++q) {
        float t, dt;
#if FIELD_SINGLE
        lit_ray_node(q, r, mu, lit, t, dt);
#else
        ray_node(q, r, mu, L, t, dt);
#endif
        float r_t, mu_t, mu_s_t;
        ray_point(r, mu, mu_s, nu, t, r_t, mu_t, mu_s_t);
        vec3 c = view_column(c0, r_t, mu_t, hits_ground);
#if FIELD_SINGLE
        vec3 c_sun = column_to_sun(r_t, mu_s_t);
        if (c_sun.x < 0.0) continue;
        vec3 d = densities(r_t - Rb) * dt;
        radiance += (beta * d.x + beta_m * d.y) * exp(-optical_depth(g, c + c_sun));
#else
        vec4 J = lookup_log_table(u_density, r_t, mu_t, mu_s_t, nu, hits_ground, u_density_size,
                                  g, NUM_GROUPS);
        radiance += J * exp(-optical_depth(g, c)) * dt;
#endif
    }
    if (hits_ground) {
        float mu_g = clamp_cosine((r * mu + L) / Rb);
        float mu_s_g = clamp_cosine((r * mu_s + L * nu) / Rb);
        vec4 T = exp(-optical_depth(g, view_column(c0, Rb, mu_g, true)));
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
