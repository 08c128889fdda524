// Curl noise (Bridson et al. 2007, "Curl-noise for procedural fluid flow"): the 2D curl
// v = (d psi / dy, -d psi / dx) of a tileable potential psi (Perlin fBm on the slice z = 0
// of the 3D noise), by central differences one texel apart. The discrete divergence of v
// with the same differences vanishes identically (the difference operators commute).
// Output: RG = v in tile units (psi per tile); the caller divides the texture by its largest
// |component| (one constant: still divergence-free). Texel (i, j) samples u = ((i, j) + 0.5) / N.
#include "clouds/noise_common.glsl"

out vec2 frag;

uniform int u_size;
uniform int u_seed;
uniform int u_period;     // cells per tile of the first octave
uniform int u_octaves;

const int STREAM_CURL = 112;

float potential(vec2 ij) {
    vec2 u = ij / float(u_size);
    // Keep the coordinate >= 0 across the wrap (the noise repeats every tile).
    u = mod(u, 1.0);
    return perlin_fbm(vec3(u, 0.0), u_period, u_octaves, u_seed, STREAM_CURL);
}

void main() {
    vec2 ij = gl_FragCoord.xy;
    float h = 1.0 / float(u_size);  // one texel, in tile units
    float dpsi_dx = (potential(ij + vec2(1, 0)) - potential(ij - vec2(1, 0))) / (2.0 * h);
    float dpsi_dy = (potential(ij + vec2(0, 1)) - potential(ij - vec2(0, 1))) / (2.0 * h);
    frag = vec2(dpsi_dy, -dpsi_dx);
}
