// Night vision, step 3: temporal noise of scotopic vision (Thompson, Shirley & Ferwerda 2002,
// sec. 4: noise that grows as the light falls). Twin: skydome/reference/night_vision.py.
//
// Multiplicative and mean-preserving: out = c (1 + a n), n of mean 0 and variance 1 (the sum of
// two uniform hashes, triangular on [-sqrt 6, sqrt 6]), a = (1 - m) min(NV_NOISE_CAP,
// 1 / sqrt(NV_NOISE_QUANTA * L_s)): the photon-count (de Vries-Rose) law, relative noise
// 1 / sqrt(N) with N proportional to the pixel's scotopic luminance L_s, capped so that
// 1 + a n >= 0. n is a hash (PCG, O'Neill 2014) of the pixel, the seed and the bits of the
// frame time: the same seed and time give the same image. m = 1: texel copied unchanged.
#include "post/night_adaptation.glsl"

uniform sampler2D u_hdr;            // RGBA32F, GL rows
uniform uint u_seed;
uniform float u_time;               // s
out vec4 frag;

uint pcg_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 c = texelFetch(u_hdr, p, 0);
    Adaptation a = adaptation_state();
    if (a.m >= 1.0) { frag = c; return; }
    float ls = max(c.a, 0.0);
    float amp = (1.0 - a.m) * (ls > 0.0 ? min(NV_NOISE_CAP, inversesqrt(NV_NOISE_QUANTA * ls))
                                        : NV_NOISE_CAP);
    uint h = pcg_hash(pcg_hash(pcg_hash(u_seed) ^ floatBitsToUint(u_time)) + uint(p.y));
    uint h1 = pcg_hash(h + uint(p.x));
    uint h2 = pcg_hash(h1 ^ 0x9e3779b9u);
    int k = int((h1 >> 8u) + (h2 >> 8u)) - 16777216;   // exact: |k| < 2^24
    float n = float(k) * (2.449489742783178 / 16777216.0);
    frag = vec4(c.rgb * (1.0 + amp * n), c.a);
}
