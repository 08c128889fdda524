// Base-shape noise of the clouds (after Schneider 2015, "The real-time volumetric cloudscapes
// of Horizon Zero Dawn"): one layer of a tileable 3D RGBA texture per instance.
//   R = Perlin-Worley: the Perlin fBm remapped with the Worley fBm of G as its new lower
//       bound (the remap the MEng report of seed 004, 8.2.2.6, found to work):
//       R = G + P01 (1 - G), P01 = clamp(0.5 + u_perlin_gain * perlin_fbm, 0, 1);
//   G, B, A = Worley fBm of base periods u_worley_period_1, _2, _3 cells per tile.
// Texel (i, j, layer k) of an N^3 texture samples u = ((i, j, k) + 0.5) / N.
#include "clouds/noise_common.glsl"

flat in int v_layer;
out vec4 frag;

uniform int u_size;            // texels per axis
uniform int u_seed;
uniform int u_perlin_period;   // cells per tile of the first Perlin octave
uniform int u_perlin_octaves;
uniform float u_perlin_gain;
// Base periods of the three Worley fBm channels (scalar ints: skydome's uniform setter
// writes vectors as floats).
uniform int u_worley_period_1, u_worley_period_2, u_worley_period_3;

const int STREAM_PERLIN = 0, STREAM_G = 16, STREAM_B = 32, STREAM_A = 48;

void main() {
    vec3 u = vec3(gl_FragCoord.xy, float(v_layer) + 0.5) / float(u_size);
    float perlin = perlin_fbm(u, u_perlin_period, u_perlin_octaves, u_seed, STREAM_PERLIN);
    float g = worley_fbm(u, u_worley_period_1, u_seed, STREAM_G);
    float b = worley_fbm(u, u_worley_period_2, u_seed, STREAM_B);
    float a = worley_fbm(u, u_worley_period_3, u_seed, STREAM_A);
    float p01 = clamp(0.5 + u_perlin_gain * perlin, 0.0, 1.0);
    frag = vec4(g + p01 * (1.0 - g), g, b, a);
}
