// Detail noise of the clouds (after Schneider 2015): one layer of a tileable 3D RGBA texture
// per instance. R, G, B = Worley fBm of base periods u_worley_period_1, _2, _3 cells per
// tile; A = 0.625 R + 0.25 G + 0.125 B (their combined fBm, ready for the edge erosion).
// Texel (i, j, layer k) of an N^3 texture samples u = ((i, j, k) + 0.5) / N.
#include "clouds/noise_common.glsl"

flat in int v_layer;
out vec4 frag;

uniform int u_size;
uniform int u_seed;
// Base periods of the three Worley fBm channels (scalar ints: skydome's uniform setter
// writes vectors as floats).
uniform int u_worley_period_1, u_worley_period_2, u_worley_period_3;

const int STREAM_R = 64, STREAM_G = 80, STREAM_B = 96;

void main() {
    vec3 u = vec3(gl_FragCoord.xy, float(v_layer) + 0.5) / float(u_size);
    float r = worley_fbm(u, u_worley_period_1, u_seed, STREAM_R);
    float g = worley_fbm(u, u_worley_period_2, u_seed, STREAM_G);
    float b = worley_fbm(u, u_worley_period_3, u_seed, STREAM_B);
    frag = vec4(r, g, b, 0.625 * r + 0.25 * g + 0.125 * b);
}
