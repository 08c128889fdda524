// The weather map at one time: moved by the wind, advected by a divergence-free flow field
// with a two-phase flow map (Vlachos 2010, "Water flow in Portal 2"), and evolving (clouds
// growing and decaying) by a slowly changing noise. Every term is a function of the time
// only, never of earlier frames. Skydome: skydome/clouds/weather.py.
//
// Coordinates are tile units: u in [0, 1)^2 over the tile, x east (texture s), y north (t).
#include "clouds/noise_common.glsl"

out vec4 frag;

uniform sampler2D u_weather;   // the map: R coverage, G type, B precipitation, A cirrus
uniform sampler2D u_flow;      // curl noise, RG in [-1, 1] (tile-periodic)
uniform vec2 u_size;           // output texels
uniform vec2 u_wind_offset;    // wind * t / tile, wrapped to [0, 1)
uniform float u_flow_reach;    // flow speed * flow period / tile: displacement per phase
uniform vec2 u_phase;          // the two flow-map phases in [0, 1), half a period apart
uniform float u_evolution_z;   // t / evolution time, wrapped to [0, EVOLUTION_Z_PERIOD)
uniform float u_evolution_on;  // 1 with evolution, 0 without
uniform int u_seed;

const int EVOLUTION_PERIOD = 8;       // noise cells per tile
const int EVOLUTION_Z_PERIOD = 256;   // evolution times before the evolution repeats
const int STREAM_EVOLVE = 128, STREAM_EVOLVE_CIRRUS = 129;

// n(x, z) - n(x, 0): zero at t = 0, of the order of the noise's +-0.5 once decorrelated.
float evolution(vec2 x, int stream) {
    vec3 p = vec3(x * float(EVOLUTION_PERIOD), 0.0);
    ivec3 period = ivec3(EVOLUTION_PERIOD, EVOLUTION_PERIOD, EVOLUTION_Z_PERIOD);
    uint salt = noise_salt(u_seed, stream);
    return perlin_noise(p + vec3(0.0, 0.0, u_evolution_z), period, salt)
         - perlin_noise(p, period, salt);
}

void main() {
    vec2 u = gl_FragCoord.xy / u_size;
    vec2 src = fract(u - u_wind_offset);  // the air that the wind has brought here
    // Flow map: phase k displaces by v * reach * (phase_k - 1/2) and weighs 1 - |2 phase_k - 1|;
    // the weights sum to 1 and each phase restarts (weight 0) where its displacement jumps.
    vec2 v = texture(u_flow, src).xy;
    vec4 m0 = texture(u_weather, src - v * (u_flow_reach * (u_phase.x - 0.5)));
    vec4 m1 = texture(u_weather, src - v * (u_flow_reach * (u_phase.y - 0.5)));
    float w0 = 1.0 - abs(2.0 * u_phase.x - 1.0);
    vec4 m = w0 * m0 + (1.0 - w0) * m1;
    if (u_evolution_on > 0.5) {
        // Clouds grow where the noise rose since t = 0 and decay where it fell; clear air
        // stays clear (the map decides where clouds may be). Rain follows its cloud.
        float grow = 1.0 + evolution(src, STREAM_EVOLVE);
        m.r = clamp(m.r * grow, 0.0, 1.0);
        m.b = clamp(m.b * grow, 0.0, 1.0);
        m.a = clamp(m.a * (1.0 + evolution(src, STREAM_EVOLVE_CIRRUS)), 0.0, 1.0);
    }
    frag = m;
}
