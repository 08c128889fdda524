// Irradiance of one scattering order on the ground, E_n(Rb, mu_s) = integral over the upper
// hemisphere of L_n(w) cos(w) dw (Bruneton 2017 ComputeIndirectIrradiance), for the mu_s of
// the coarse table: a sum over the sky directions of the field of radius index 0 (r = Rb, where
// the horizon is at mu = 0, so the sky nodes are exactly the upper hemisphere).
// Texel (j, g): Sun cosine index j, wavelength group g. Used by the next order's field for the
// light reflected by the ground. Stored as a logarithm.
#include "atmosphere/precompute_common.glsl"

uniform sampler2D u_field;  // L dw, x = group * N_DIR + direction, y = r_index * MU_S + mu_s_index

out vec4 frag;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    int row = p.x;  // r index 0
    int g = p.y;
    vec4 E = vec4(0.0);
    for (int a = 0; a < N_MU_SKY; ++a) {
        float mu = mu_node(a, u_bottom_radius).x;
        for (int j = 0; j < N_PHI; ++j) {
            E += mu * texelFetch(u_field, ivec2(g * N_DIR + a * N_PHI + j, row), 0);
        }
    }
    frag = to_log(E);
}
