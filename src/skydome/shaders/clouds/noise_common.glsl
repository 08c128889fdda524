// Tileable, seeded noise for clouds: an integer hash, gradient (Perlin) noise, cellular
// (Worley) noise and their fBm sums. Float64 twin: skydome.clouds.lattice_noise.
//
// Points are in lattice units: a noise of integer period P repeats every P units along each
// axis, so a texture that spans [0, P) per axis tiles seamlessly (wrap = repeat). Lattice
// cells are wrapped modulo P before hashing; distances and offsets use the unwrapped cells.
// Callers keep coordinates >= 0 (texture coordinates times the period).

// PCG4D integer hash of Jarzynski & Olano, "Hash Functions for GPU Rendering", JCGT 9(3),
// 2020: a 4-vector of uints to 4 well-mixed uints (uint arithmetic wraps modulo 2^32).
uvec4 pcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    return v;
}

// One random stream per (seed, stream id): octaves and channels never share lattice values.
uint noise_salt(int seed, int stream) {
    return pcg4d(uvec4(uint(seed), uint(stream), 0x68E31DA4u, 0xB5297A4Du)).x;
}

// The top 24 bits of a hash as a float in [0, 1): exact in float32 (and in the twin).
vec3 hash_unit3(uvec4 h) {
    return vec3(h.xyz >> 8u) * (1.0 / 16777216.0);
}

ivec3 wrap_cell(ivec3 cell, ivec3 period) {
    return (cell + period) % period;  // cell >= -period: no negative operand for %
}

// Perlin's quintic fade, 6t^5 - 15t^4 + 10t^3 (Perlin 2002, "Improving noise").
vec3 noise_fade(vec3 t) {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// The 12 edge-midpoint gradients of Perlin 2002 (|g| = sqrt 2), picked by the hash.
float perlin_corner(ivec3 cell, ivec3 period, uint salt, vec3 d) {
    uvec3 c = uvec3(wrap_cell(cell, period));
    uint i = (pcg4d(uvec4(c, salt)).x >> 16u) % 12u;
    vec2 pair = i < 4u ? d.xy : (i < 8u ? d.xz : d.yz);  // (+-1, +-1) on two axes
    float a = (i & 1u) != 0u ? -pair.x : pair.x;
    float b = (i & 2u) != 0u ? -pair.y : pair.y;
    return a + b;
}

// Gradient noise of period `period` (lattice cells per tile, per axis): 0 at every lattice
// point, values within about [-1, 1].
float perlin_noise(vec3 p, ivec3 period, uint salt) {
    ivec3 c = ivec3(floor(p));
    vec3 f = p - vec3(c);
    vec3 w = noise_fade(f);
    float n000 = perlin_corner(c, period, salt, f);
    float n100 = perlin_corner(c + ivec3(1, 0, 0), period, salt, f - vec3(1, 0, 0));
    float n010 = perlin_corner(c + ivec3(0, 1, 0), period, salt, f - vec3(0, 1, 0));
    float n110 = perlin_corner(c + ivec3(1, 1, 0), period, salt, f - vec3(1, 1, 0));
    float n001 = perlin_corner(c + ivec3(0, 0, 1), period, salt, f - vec3(0, 0, 1));
    float n101 = perlin_corner(c + ivec3(1, 0, 1), period, salt, f - vec3(1, 0, 1));
    float n011 = perlin_corner(c + ivec3(0, 1, 1), period, salt, f - vec3(0, 1, 1));
    float n111 = perlin_corner(c + ivec3(1, 1, 1), period, salt, f - vec3(1, 1, 1));
    float x00 = mix(n000, n100, w.x), x10 = mix(n010, n110, w.x);
    float x01 = mix(n001, n101, w.x), x11 = mix(n011, n111, w.x);
    return mix(mix(x00, x10, w.y), mix(x01, x11, w.y), w.z);
}

// Worley's F1 (Worley 1996): the distance, in cells, to the nearest feature point of a
// jittered grid (one point uniformly placed in each cell), searched over the 27 cells
// around p. The own cell first, then the others, skipping (unhashed) any cell whose box lies
// farther than the best distance so far: the same minimum as the full search, less work.
float worley_cell(ivec3 c, ivec3 o, vec3 f, ivec3 period, uint salt) {
    uvec3 cw = uvec3(wrap_cell(c + o, period));
    vec3 d = vec3(o) + hash_unit3(pcg4d(uvec4(cw, salt))) - f;
    return dot(d, d);
}

float worley_f1(vec3 p, ivec3 period, uint salt) {
    ivec3 c = ivec3(floor(p));
    vec3 f = p - vec3(c);
    // Squared distance from p to the slab of offset -1, 0, +1 along each axis.
    vec3 lo = f * f, hi = (1.0 - f) * (1.0 - f);
    float best = worley_cell(c, ivec3(0), f, period, salt);
    for (int k = -1; k <= 1; ++k)
        for (int j = -1; j <= 1; ++j)
            for (int i = -1; i <= 1; ++i) {
                ivec3 o = ivec3(i, j, k);
                vec3 gap = mix(vec3(0.0), mix(lo, hi, greaterThan(o, ivec3(0))),
                               notEqual(o, ivec3(0)));
                if ((i != 0 || j != 0 || k != 0) && gap.x + gap.y + gap.z < best)
                    best = min(best, worley_cell(c, o, f, period, salt));
            }
    return sqrt(best);
}

// fBm of gradient noise: octaves at periods P, 2P, 4P, ... with amplitudes 1, 1/2, 1/4, ...,
// divided by the sum of the amplitudes. Octave o uses stream `stream + o`.
// twin: skydome.clouds.lattice_noise.perlin_fbm(u, period, octaves, seed, stream) u=0..1 period=4 octaves=3 seed=7 stream=2
float perlin_fbm(vec3 u, int period, int octaves, int seed, int stream) {
    float sum = 0.0, amp = 1.0, norm = 0.0;
    int p = period;
    for (int o = 0; o < octaves; ++o) {
        sum += amp * perlin_noise(u * float(p), ivec3(p), noise_salt(seed, stream + o));
        norm += amp;
        amp *= 0.5;
        p *= 2;
    }
    return sum / norm;
}

// Inverted Worley noise, 1 - F1 clamped to [0, 1]: bright cell centres, billowy shapes.
float worley_inverted(vec3 u, int period, int seed, int stream) {
    return 1.0 - clamp(worley_f1(u * float(period), ivec3(period), noise_salt(seed, stream)),
                       0.0, 1.0);
}

// Worley fBm of Schneider (GPU Pro 7, 2016): 0.625 W(P) + 0.25 W(2P) + 0.125 W(4P), W the
// inverted Worley noise; streams `stream`, `stream + 1`, `stream + 2`.
// twin: skydome.clouds.lattice_noise.worley_fbm(u, period, seed, stream) u=0..1 period=3 seed=7 stream=5
float worley_fbm(vec3 u, int period, int seed, int stream) {
    return 0.625 * worley_inverted(u, period, seed, stream)
         + 0.25 * worley_inverted(u, 2 * period, seed, stream + 1)
         + 0.125 * worley_inverted(u, 4 * period, seed, stream + 2);
}
