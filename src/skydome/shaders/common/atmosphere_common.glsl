// Atmosphere description on the GPU and the geometry of rays in a spherical atmosphere.
// Lengths are in km here (float32 precision); Python passes km and per-km values.
#include "common/constants.glsl"

uniform float u_bottom_radius;   // planet radius, km
uniform float u_top_radius;      // top of the atmosphere, km
// Density profiles of Rayleigh (0), Mie (1) and absorbing (2) constituents, each layered or
// tabulated (uniforms.py, profile_uniforms).
// Layered: two layers each of (width, exp_term, exp_scale, linear_term, constant_term), units
// km and 1/km, at u_profile[10 * constituent + 5 * layer + k]. Bruneton 2017,
// DensityProfileLayer.
// Tabulated (PROFILE_INV_STEP[c] > 0): ln(density) at the altitudes i / PROFILE_INV_STEP[c] km,
// i = 0 .. PROFILE_LAST[c], sample i of constituent c at flat index c * PROFILE_TABLE_SIZE + i
// of u_profile_table (four to a vec4); a density of 0 is stored as PROFILE_LOG_ZERO.
// Log-linear between samples, linear next to a 0; constant outside the samples.
// PROFILE_FORMS (bit c set: constituent c is tabulated; bit c + 3: its table has zeros, so
// linear pieces; uniforms.py, profile_defines) makes the forms compile-time constants: CPU
// renderers (llvmpipe) run both sides of a branch on a uniform, so without it every density
// would also pay for the table lookup (twice the cost of the transmittance table), and every
// tabulated one for the linear pieces. Without the define both are decided at run time.
// With PROFILE_VALUES defined (30 comma-separated literals, and the 3 + 3 of
// PROFILE_INV_STEP_VALUES and PROFILE_LAST_VALUES) the layers and grids are compile-time
// constants too, which lets the compiler drop unused terms (a measurable gain on CPU renderers).
#define PROFILE_TABLE_SIZE 256
#define PROFILE_LOG_ZERO -1.0e4
#ifdef PROFILE_VALUES
const float PROFILE[30] = float[30](PROFILE_VALUES);
const vec3 PROFILE_INV_STEP = vec3(PROFILE_INV_STEP_VALUES);
const vec3 PROFILE_LAST = vec3(PROFILE_LAST_VALUES);
#else
uniform float u_profile[30];
uniform vec3 u_profile_inv_step;  // 1 / table step (1/km) per constituent; 0 = layered
uniform vec3 u_profile_last;      // index of the last table sample per constituent
#define PROFILE u_profile
#define PROFILE_INV_STEP u_profile_inv_step
#define PROFILE_LAST u_profile_last
#endif
uniform vec4 u_profile_table[3 * PROFILE_TABLE_SIZE / 4];

float clamp_cosine(float mu) { return clamp(mu, -1.0, 1.0); }
float safe_sqrt(float a) { return sqrt(max(a, 0.0)); }

float layer_density(int base, float altitude) {
    float d = PROFILE[base + 3] * altitude + PROFILE[base + 4];
    // Skip the exponential of purely linear layers (the ozone tent).
    if (PROFILE[base + 1] != 0.0) d += PROFILE[base + 1] * exp(PROFILE[base + 2] * altitude);
    return clamp(d, 0.0, 1.0);
}

float table_log_density(int k) { return u_profile_table[k >> 2][k & 3]; }

#ifdef PROFILE_FORMS
#define PROFILE_IS_TABULATED(c) (((PROFILE_FORMS >> (c)) & 1) != 0)
#define PROFILE_HAS_ZEROS(c) (((PROFILE_FORMS >> ((c) + 3)) & 1) != 0)
#else
#define PROFILE_IS_TABULATED(c) (PROFILE_INV_STEP[c] > 0.0)
#define PROFILE_HAS_ZEROS(c) true
#endif

float tabulated_density(int constituent, float altitude) {
    float last = PROFILE_LAST[constituent];
    float x = clamp(altitude * PROFILE_INV_STEP[constituent], 0.0, last);
    float i = min(floor(x), last - 1.0);
    float f = x - i;
    int k = constituent * PROFILE_TABLE_SIZE + int(i);
    float a = table_log_density(k);
    float b = table_log_density(k + 1);
    if (PROFILE_HAS_ZEROS(constituent) && min(a, b) <= PROFILE_LOG_ZERO) {
        return mix(exp(a), exp(b), f);  // exp(-1e4) = 0
    }
    return exp(mix(a, b, f));
}

float profile_density(int constituent, float altitude) {
    if (PROFILE_IS_TABULATED(constituent)) return tabulated_density(constituent, altitude);
    int base = 10 * constituent;
    return altitude < PROFILE[base] ? layer_density(base, altitude) : layer_density(base + 5, altitude);
}

// Relative densities (Rayleigh, Mie, absorption) at an altitude in km.
// twin: skydome.atmosphere.columns.densities(params, altitude * 1000) altitude=0..100
vec3 densities(float altitude) {
    return vec3(profile_density(0, altitude), profile_density(1, altitude), profile_density(2, altitude));
}

// Distance from radius r along direction cosine mu to the top boundary (Bruneton 2017,
// DistanceToTopAtmosphereBoundary; skydome.physics.geometry).
// twin: skydome.physics.geometry.distance_to_top(r, mu, u_top_radius) r=6360..6420 mu=-1..1 u_top_radius=6420
float distance_to_top(float r, float mu) {
    float disc = r * r * (mu * mu - 1.0) + u_top_radius * u_top_radius;
    return max(-r * mu + safe_sqrt(disc), 0.0);
}

// Distance from radius r along direction cosine mu to the ground (Bruneton 2017,
// DistanceToBottomAtmosphereBoundary), where the ray hits it.
// twin: skydome.physics.geometry.distance_to_bottom(r, mu, u_bottom_radius) r=6360..6420 mu=-1..0 u_bottom_radius=6360
float distance_to_bottom(float r, float mu) {
    float disc = r * r * (mu * mu - 1.0) + u_bottom_radius * u_bottom_radius;
    return max(-r * mu - safe_sqrt(disc), 0.0);
}

// Whether the ray (r, mu) meets the ground (Bruneton 2017, RayIntersectsGround).
// twin: skydome.physics.geometry.ray_hits_ground(r, mu, u_bottom_radius) r=6360..6420 mu=-1..1 u_bottom_radius=6360
bool ray_hits_ground(float r, float mu) {
    return mu < 0.0 && r * r * (mu * mu - 1.0) + u_bottom_radius * u_bottom_radius >= 0.0;
}

// Distances along the ray o + t d (d unit) to its two intersections with a sphere of `radius`
// around the origin, nearer first (negative behind o); both -1 where the line misses it.
// twin: skydome.physics.geometry.ray_sphere(o, d, radius) o=unit*6300..6600 d=unit radius=6420
vec2 ray_sphere(vec3 o, vec3 d, float radius) {
    float b = dot(o, d);
    float c = dot(o, o) - radius * radius;
    float disc = b * b - c;
    if (disc < 0.0) return vec2(-1.0);
    float s = sqrt(disc);
    return vec2(-b - s, -b + s);
}
