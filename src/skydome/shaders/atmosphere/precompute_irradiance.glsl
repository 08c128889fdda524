// Sky irradiance table E(r, mu_s) on a horizontal surface, per unit solar irradiance
// (dimensionless), every wavelength group at once (location g = group g):
//   E(x, s) = integral over the upper hemisphere of L(x, w) cos(w) dw
// (seed 004 5.2.2.1 E[L]; Bruneton 2017 ComputeIndirectIrradiance), with L marched directly:
//   IRRADIANCE_SINGLE 1: single scattering (phase functions applied, point Sun, shadow);
//   IRRADIANCE_SINGLE 0: orders >= 2, integral T J_total along each direction.
// Directions: IRR_N_MU Gauss-Legendre cosines on [0, 1] times IRR_N_PHI azimuths over [0, pi]
// (the sky is symmetric about the Sun's vertical plane, so the other half is the same).
// Rays going up never reach the ground, so no ground term is needed.
// The table is drawn IRR_PARTS times side by side, each copy u_part_stride texels apart (a
// multiple of the rasterizer's 64-pixel tiles) summing every IRR_PARTS-th cosine from its own
// part: a CPU rasterizer gives each tile to one thread, and the whole table is one tile. The
// parts are summed after the read-back.
#include "atmosphere/precompute_ray.glsl"

uniform vec2 u_irradiance_size;    // (MU_S, R) texels
uniform int u_part_stride;         // texels between the parts' copies of the table
uniform vec2 u_irr_mu_rule[IRR_N_MU];  // Gauss-Legendre on [-1, 1]
uniform vec4 u_density_size;       // the grid of J (orders >= 2)
uniform sampler3D u_density;       // log J_total, NUM_GROUPS tables stacked in depth

layout(location = 0) out vec4 out_irradiance[NUM_GROUPS];

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    int part = texel.x / u_part_stride;
    texel.x -= part * u_part_stride;
    if (float(texel.x) >= u_irradiance_size.x) discard;  // between the copies
    float r, mu_s;
    irradiance_texel_params(texel, u_irradiance_size, r, mu_s);
    vec3 s = sun_in_frame(mu_s);
    vec4 E[NUM_GROUPS];
    for (int g = 0; g < NUM_GROUPS; ++g) E[g] = vec4(0.0);
    float dphi = PI / float(IRR_N_PHI);
    for (int a = part; a < IRR_N_MU; a += IRR_PARTS) {
        float mu = 0.5 * (u_irr_mu_rule[a].x + 1.0);
        float w_mu = 0.5 * u_irr_mu_rule[a].y;
        float sin_a = safe_sqrt(1.0 - mu * mu);
        for (int j = 0; j < IRR_N_PHI; ++j) {
            float phi = (float(j) + 0.5) * dphi;
            vec3 w = vec3(sin_a * cos(phi), sin_a * sin(phi), mu);
            float nu = dot(w, s);
            // cos(w) dw, both halves of the azimuth circle
            float weight = mu * w_mu * 2.0 * dphi;
            vec4 radiance[NUM_GROUPS];
#if IRRADIANCE_SINGLE
            vec4 ray_r[NUM_GROUPS];
            vec4 ray_m[NUM_GROUPS];
            single_scattering_integrals(r, mu, mu_s, nu, false, 0, NUM_GROUPS, ray_r, ray_m);
            float phase_r = rayleigh_phase(nu);
            for (int g = 0; g < NUM_GROUPS; ++g)
                radiance[g] = phase_r * ray_r[g] + mie_phase_group(nu, g) * ray_m[g];
#else
            scattered_radiance(u_density, u_density_size, r, mu, mu_s, nu, false, 0, NUM_GROUPS,
                               radiance);
#endif
            for (int g = 0; g < NUM_GROUPS; ++g) E[g] += radiance[g] * weight;
        }
    }
    for (int g = 0; g < NUM_GROUPS; ++g) out_irradiance[g] = E[g];
}
