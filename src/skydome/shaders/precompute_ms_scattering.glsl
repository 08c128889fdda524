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
#include "precompute_common.glsl"

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
    float L = ray_length(r, mu, hits_ground);
    vec3 c0 = column_to_top(r, hits_ground ? -mu : mu);
    vec4 radiance[NUM_GROUPS];
    for (int g = 0; g < NUM_GROUPS; ++g) radiance[g] = vec4(0.0);
    for (int i = 0; i < RAY_SAMPLES; ++i) {
        float t, dt;
        ray_node(i, r, mu, L, t, dt);
        float r_t, mu_t, mu_s_t;
        ray_point(r, mu, mu_s, nu, t, r_t, mu_t, mu_s_t);
        vec3 c = view_column(c0, r_t, mu_t, hits_ground);
        vec4 uvwz = scattering_uvwz(r_t, mu_t, mu_s_t, nu, hits_ground, u_density_size, true);
        float fade = sun_cutoff_fade(mu_s_t);
        for (int g = 0; g < NUM_GROUPS; ++g) {
            vec4 J = exp(sample_scattering(u_density, uvwz, u_density_size, g, NUM_GROUPS)) * fade;
            radiance[g] += J * exp(-optical_depth(g, c)) * dt;
        }
    }
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
