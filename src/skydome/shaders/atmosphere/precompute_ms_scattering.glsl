// The multiple-scattering table, one texel per (r, mu, mu_s, nu) of its grid (layered):
//   S_ms(x, v, s) = integral_0^L T(x, y) J_total(y, v, s) dt,  J_total = sum_{n=2}^{N} J_n,
// since the integral is linear in J, all the orders are integrated at once instead of one
// Delta S per order (Bruneton 2017 ComputeMultipleScattering, summed). Converted to the table's
// channels with u_spectral_to_table (from the multiple-scattering wavelengths) and stored as a
// logarithm: in twilight the orders >= 2 fall exponentially with the Sun's depression, more
// slowly than single scattering but not like its normalization F, hence a table of their own.
// Unlike Bruneton (seed 004 5.2.2.3), who divides them by the Rayleigh phase function to add
// them to single Rayleigh scattering, they are stored as they are: P_R(nu) would double their
// variation with nu, which the texels at the edges of the (mu, mu_s, nu) domain (zenith Sun or
// view, where all nu collapse to one) cannot represent.
#ifndef NU_PER_FRAGMENT
#define NU_PER_FRAGMENT 1  // views (nu) per fragment: see main()
#endif
#include "atmosphere/precompute_ray.glsl"

uniform vec4 u_ms_size;       // this table (NU, MU_S, MU, R)
uniform vec4 u_density_size;  // the grid of J
uniform sampler3D u_density;  // ln J_total, NUM_GROUPS tables stacked in depth
#if MS_LOG_INTERP
// Orders >= 2 computed at 4 wavelengths (one group) and extended to the NUM_RENDER_GROUPS
// groups of render wavelengths by interpolating ln L in a physical basis (precompute.py,
// ms_log_interpolation): ln L(render group k) = u_ms_log_interp[k] * ln L(4 samples).
uniform mat4 u_ms_log_interp[NUM_RENDER_GROUPS];
uniform mat4 u_render_to_table[NUM_RENDER_GROUPS];
#endif

flat in int v_layer;
// NU_PER_FRAGMENT views (nu) per fragment, sharing the ray's nodes and transmittances: the pass
// draws (MU_S * NU / NU_PER_FRAGMENT, MU) texels per layer; output t holds the nu index
// block * NU_PER_FRAGMENT + t of the fragment's block (precompute.py reorders).
layout(location = 0) out vec4 frag[NU_PER_FRAGMENT];

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    int n_mu_s = int(u_ms_size.y);
    int block = texel.x / n_mu_s;
    int i_mu_s = texel.x - block * n_mu_s;
    float r, mu, mu_s;
    bool hits_ground;
    float nus[NU_PER_FRAGMENT];
    for (int t = 0; t < NU_PER_FRAGMENT; ++t) {
        ivec2 full = ivec2((block * NU_PER_FRAGMENT + t) * n_mu_s + i_mu_s, texel.y);
        scattering_texel_params(full, v_layer, u_ms_size, true, r, mu, mu_s, nus[t], hits_ground);
    }
    vec4 radiance[NUM_GROUPS * NU_PER_FRAGMENT];
    scattered_radiance_views(u_density, u_density_size, r, mu, mu_s, nus, hits_ground, 0,
                             NUM_GROUPS, radiance);
    for (int t = 0; t < NU_PER_FRAGMENT; ++t) {
        vec4 v = vec4(0.0);
#if MS_LOG_INTERP
        vec4 L4 = radiance[t];
        float hi = max(max(L4.x, L4.y), max(L4.z, L4.w));
        float lo = min(min(L4.x, L4.y), min(L4.z, L4.w));
        if (lo > 1e-6 * hi && hi > 0.0) {
            vec4 ln4 = log(L4);
            for (int k = 0; k < NUM_RENDER_GROUPS; ++k)
                v += u_render_to_table[k] * exp(u_ms_log_interp[k] * ln4);
        } else {
            v = u_spectral_to_table[0] * L4;  // (near) zero somewhere: linear interpolation
        }
#else
        for (int g = 0; g < NUM_GROUPS; ++g)
            v += u_spectral_to_table[g] * radiance[g * NU_PER_FRAGMENT + t];
#endif
        frag[t] = to_log(v);
    }
}
