// Sky irradiance table E(r, mu_s) on a horizontal surface, per unit solar irradiance
// (dimensionless), every wavelength group at once (location g = group g):
//   E(x, s) = integral over the upper hemisphere of L(x, w) cos(w) dw
// (seed 004 5.2.2.1 E[L]; Bruneton 2017 ComputeIndirectIrradiance), with L marched directly:
//   IRRADIANCE_SINGLE 1: single scattering (phase functions applied, point Sun, shadow);
//   IRRADIANCE_SINGLE 0: orders >= 2, integral T J_total along each direction.
// Directions: IRR_N_MU Gauss-Legendre cosines on [0, 1] times IRR_N_PHI azimuths over [0, pi]
// (the sky is symmetric about the Sun's vertical plane, so the other half is the same).
// Rays going up never reach the ground, so no ground term is needed.
#include "precompute_common.glsl"

uniform vec2 u_irradiance_size;    // (MU_S, R) texels
uniform vec2 u_irr_mu_rule[IRR_N_MU];  // Gauss-Legendre on [-1, 1]
uniform vec4 u_density_size;       // the grid of J (orders >= 2)
uniform sampler3D u_density;       // log J_total, NUM_GROUPS tables stacked in depth

layout(location = 0) out vec4 out_irradiance[NUM_GROUPS];

void main() {
    float r, mu_s;
    irradiance_texel_params(ivec2(gl_FragCoord.xy), u_irradiance_size, r, mu_s);
    vec3 s = sun_in_frame(mu_s);
    vec4 E[NUM_GROUPS];
    for (int g = 0; g < NUM_GROUPS; ++g) E[g] = vec4(0.0);
    float dphi = PI / float(IRR_N_PHI);
    for (int a = 0; a < IRR_N_MU; ++a) {
        float mu = 0.5 * (u_irr_mu_rule[a].x + 1.0);
        float w_mu = 0.5 * u_irr_mu_rule[a].y;
        float sin_a = safe_sqrt(1.0 - mu * mu);
        float L = distance_to_top(r, mu);
        vec3 c0 = column_to_top(r, mu);
        for (int j = 0; j < IRR_N_PHI; ++j) {
            float phi = (float(j) + 0.5) * dphi;
            vec3 w = vec3(sin_a * cos(phi), sin_a * sin(phi), mu);
            float nu = dot(w, s);
            // cos(w) dw, both halves of the azimuth circle
            float weight = mu * w_mu * 2.0 * dphi;
            vec4 radiance[NUM_GROUPS];
            for (int g = 0; g < NUM_GROUPS; ++g) radiance[g] = vec4(0.0);
#if IRRADIANCE_SINGLE
            float phase_r = rayleigh_phase(nu);
            float phase_m = cornette_shanks_phase(nu, u_mie_g);
            vec4 lit = lit_segments(r, mu, mu_s, nu, L);
#endif
            for (int q = 0; q < RAY_SAMPLES; ++q) {
                float t, dt;
#if IRRADIANCE_SINGLE
                lit_ray_node(q, r, mu, lit, t, dt);
#else
                ray_node(q, r, mu, L, t, dt);
#endif
                float r_t, mu_t, mu_s_t;
                ray_point(r, mu, mu_s, nu, t, r_t, mu_t, mu_s_t);
                vec3 c = view_column(c0, r_t, mu_t, false);
#if IRRADIANCE_SINGLE
                vec3 c_sun = column_to_sun(r_t, mu_s_t);
                if (c_sun.x < 0.0) continue;
                vec3 d = densities(r_t - u_bottom_radius) * dt;
                for (int g = 0; g < NUM_GROUPS; ++g) {
                    vec4 beta = u_rayleigh_scattering[g] * (phase_r * d.x)
                              + u_mie_scattering[g] * (phase_m * d.y);
                    radiance[g] += beta * exp(-optical_depth(g, c + c_sun));
                }
#else
                vec4 uvwz = scattering_uvwz(r_t, mu_t, mu_s_t, nu, false, u_density_size, true);
                float fade = sun_cutoff_fade(mu_s_t);
                for (int g = 0; g < NUM_GROUPS; ++g) {
                    vec4 J = exp(sample_scattering(u_density, uvwz, u_density_size, g, NUM_GROUPS)) * fade;
                    radiance[g] += J * exp(-optical_depth(g, c)) * dt;
                }
#endif
            }
            for (int g = 0; g < NUM_GROUPS; ++g) E[g] += radiance[g] * weight;
        }
    }
    for (int g = 0; g < NUM_GROUPS; ++g) out_irradiance[g] = E[g];
}
