// Atmosphere description on the GPU and the geometry of rays in a spherical atmosphere.
// Lengths are in km here (float32 precision); Python passes km and per-km values.
#include "constants.glsl"

uniform float u_bottom_radius;   // planet radius, km
uniform float u_top_radius;      // top of the atmosphere, km
// Density profiles of Rayleigh (0), Mie (1) and absorbing (2) constituents: two layers
// each of (width, exp_term, exp_scale, linear_term, constant_term), units km and 1/km,
// at u_profile[10 * constituent + 5 * layer + k]. Bruneton 2017, DensityProfileLayer.
// With PROFILE_VALUES defined (30 comma-separated literals) the profiles are compile-time
// constants, which lets the compiler drop unused terms (a measurable gain on CPU renderers).
#ifdef PROFILE_VALUES
const float PROFILE[30] = float[30](PROFILE_VALUES);
#else
uniform float u_profile[30];
#define PROFILE u_profile
#endif

float clamp_cosine(float mu) { return clamp(mu, -1.0, 1.0); }
float safe_sqrt(float a) { return sqrt(max(a, 0.0)); }

float layer_density(int base, float altitude) {
    float d = PROFILE[base + 3] * altitude + PROFILE[base + 4];
    // Skip the exponential of purely linear layers (the ozone tent).
    if (PROFILE[base + 1] != 0.0) d += PROFILE[base + 1] * exp(PROFILE[base + 2] * altitude);
    return clamp(d, 0.0, 1.0);
}

float profile_density(int constituent, float altitude) {
    int base = 10 * constituent;
    return altitude < PROFILE[base] ? layer_density(base, altitude) : layer_density(base + 5, altitude);
}

// Relative densities (Rayleigh, Mie, absorption) at an altitude in km.
vec3 densities(float altitude) {
    return vec3(profile_density(0, altitude), profile_density(1, altitude), profile_density(2, altitude));
}

// Distance from radius r along direction cosine mu to the top boundary (Bruneton eq. 2.x).
float distance_to_top(float r, float mu) {
    float disc = r * r * (mu * mu - 1.0) + u_top_radius * u_top_radius;
    return max(-r * mu + safe_sqrt(disc), 0.0);
}

float distance_to_bottom(float r, float mu) {
    float disc = r * r * (mu * mu - 1.0) + u_bottom_radius * u_bottom_radius;
    return max(-r * mu - safe_sqrt(disc), 0.0);
}

bool ray_hits_ground(float r, float mu) {
    return mu < 0.0 && r * r * (mu * mu - 1.0) + u_bottom_radius * u_bottom_radius >= 0.0;
}

// Nearest non-negative intersection distance of ray o + t d with a centred sphere, or -1.
vec2 ray_sphere(vec3 o, vec3 d, float radius) {
    float b = dot(o, d);
    float c = dot(o, o) - radius * radius;
    float disc = b * b - c;
    if (disc < 0.0) return vec2(-1.0);
    float s = sqrt(disc);
    return vec2(-b - s, -b + s);
}
