// Night vision: temporal noise of scotopic vision (Thompson, Shirley & Ferwerda 2002, sec. 4:
// noise that grows as the light falls), included by post/night_vision.glsl.
// Twin: skydome/reference/night_vision.py (add_noise, noise_field).
//
// Multiplicative and mean-preserving: out = c (1 + a n), n of mean 0 and variance 1 (the sum of
// two uniform hashes, triangular on [-sqrt 6, sqrt 6]), a = (1 - m) min(NV_NOISE_CAP,
// 1 / sqrt(NV_NOISE_QUANTA * L_s)): the photon-count (de Vries-Rose) law, relative noise
// 1 / sqrt(N) with N proportional to the pixel's scotopic luminance L_s, capped so that
// 1 + a n >= 0. n is a hash (PCG, O'Neill 2014) of the pixel, the seed and the bits of the
// frame time: the same seed and time give the same image. The part of the hash that depends
// on the seed and the time only, pcg(pcg(seed) ^ bits(time)), is the same for every pixel and
// comes from the CPU (skydome.display.night_vision.noise_base), with the same hash.
uniform uint u_noise_base;
uniform float u_noise_scale;        // 1 - m

uint pcg_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// a n for pixel p of scotopic luminance ls (scotopic cd/m^2).
float night_noise(ivec2 p, float ls) {
    ls = max(ls, 0.0);
    float amp = u_noise_scale * (ls > 0.0 ? min(NV_NOISE_CAP, inversesqrt(NV_NOISE_QUANTA * ls))
                                          : NV_NOISE_CAP);
    uint h = pcg_hash(u_noise_base + uint(p.y));
    uint h1 = pcg_hash(h + uint(p.x));
    uint h2 = pcg_hash(h1 ^ 0x9e3779b9u);
    int k = int((h1 >> 8u) + (h2 >> 8u)) - 16777216;   // exact: |k| < 2^24
    return amp * float(k) * (2.449489742783178 / 16777216.0);
}
