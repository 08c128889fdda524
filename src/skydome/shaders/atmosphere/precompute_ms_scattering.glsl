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
out vec4 frag;

void main() {
    float r, mu, mu_s, nu;
    bool hits_ground;
    scattering_texel_params(ivec2(gl_FragCoord.xy), v_layer, u_ms_size, true, r, mu, mu_s, nu,
                            hits_ground);
    vec4 radiance[NUM_GROUPS];
    scattered_radiance(u_density, u_density_size, r, mu, mu_s, nu, hits_ground, 0, NUM_GROUPS,
                       radiance);
    vec4 v = vec4(0.0);
#if MS_LOG_INTERP
    vec4 L4 = radiance[0];
    float hi = max(max(L4.x, L4.y), max(L4.z, L4.w));
    float lo = min(min(L4.x, L4.y), min(L4.z, L4.w));
    if (lo > 1e-6 * hi && hi > 0.0) {
        vec4 ln4 = log(L4);
        for (int k = 0; k < NUM_RENDER_GROUPS; ++k) v += u_render_to_table[k] * exp(u_ms_log_interp[k] * ln4);
    } else {
        v = u_spectral_to_table[0] * L4;  // (near) zero somewhere: linear interpolation
    }
#else
    for (int g = 0; g < NUM_GROUPS; ++g) v += u_spectral_to_table[g] * radiance[g];
#endif
    frag = to_log(v);
}
