// Falling rain and snow near the camera (skydome.weather.particles), over what lies behind:
// particles seeded in a lattice that falls with the wind, drawn as what a camera records in
// one exposure: a drop or a flake moving a streak's length, covering each pixel on its path
// for the part of the exposure it spends there (Garg & Nayar 2004's streak model; the share
// normalised so that a pixel's mean covered share is the particles' projected area), with the
// radiance of the light around it (a drop refracts the whole sky towards the eye, a flake
// scatters it).
//
// The particles within FAR_M of the camera are drawn (farther, a camera does not resolve
// them: they are the haze of the rain volume under the clouds). That range is cut into SHEETS
// shells, each DEPTH_M / SHEETS deep; each shell is a lattice of cubes small enough to hold
// about one particle on average in the shell's depth behind each cube's face (a side of
// (n depth)^-1/2). The view ray's cube at the shell's middle, and those back along the
// particles' motion over the exposure (where a streak crossing the ray began), each hold a
// particle there with that probability: a seeded place across
// the cube and in depth across the shell, a diameter drawn from the size distribution
// (exponential above the smallest drawn size), the speed that diameter falls at.
#include "common/camera.glsl"
#include "weather/fall_speed.glsl"

uniform sampler2D u_behind;        // the light arriving from behind, cd/m^2
uniform vec4 u_particles;          // per m^3 of particles seen, 1/mm slope of the sizes,
                                   // smallest size mm, kind (0 rain, 1 snow)
uniform vec4 u_motion;             // wind east, north (m/s), exposure (s), time (s)
uniform vec4 u_particle_radiance;  // a particle's radiance, cd/m^2 per channel
uniform vec2 u_particle_scale;     // (size of a flake over its melted drop, the camera's height m)
uniform float u_pixel_rad;         // a pixel's angular size (rad)
uniform float u_seed;
uniform float u_far_m;             // the farthest particle drawn (m)
layout(location = 0) out vec4 frag;

const int SHEETS = 8;
const int MAX_CUBES = 4;
const float NEAR_M = 0.3;

// A hash of a lattice cell and a salt into [0, 1)^3 (Jarzynski & Olano 2020's pcg3d).
vec3 hash3(ivec3 cell, int salt) {
    uvec3 v = uvec3(cell) * 1664525u + 1013904223u + uint(salt) * 747796405u;
    v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
    v ^= v >> 16u;
    v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
    return vec3(v) * (1.0 / 4294967296.0);
}

// The velocity (m/s, ENU) of a particle of size d_mm.
vec3 velocity(float d_mm, bool snow) {
    float v = snow ? flake_fall_speed(d_mm) : rain_fall_speed(d_mm);
    return vec3(u_motion.xy, -v);
}

// How much of the pixel along unit `dir` the particle of this cube covers over the exposure
// (0-1): cubes of side `side` m across a shell from r0 to r0 + depth m, the lattice moving
// with velocity `drift`.
float coverage(vec3 dir, ivec3 cell, float side, float r0, float depth, vec3 drift, int salt,
               bool snow) {
    vec3 h = hash3(cell, salt + int(u_seed));
    vec3 g = hash3(cell, salt + 7 + int(u_seed));
    float expected = u_particles.x * side * side * depth;
    if (g.x >= expected) return 0.0;  // no particle here
    // its diameter: exponential above the smallest drawn (melted, for a flake)
    float d_mm = u_particles.z - log(max(1.0 - g.y, 1e-7)) / u_particles.y;
    float size_mm = d_mm * (snow ? u_particle_scale.x : 1.0);
    vec3 v = velocity(size_mm, snow);
    // where it is when the exposure opens: its seeded place in the cube, carried by the
    // lattice's drift and by its own speed's difference (within its cube), then moved
    // along its direction from the camera to its seeded depth in the shell
    vec3 place = (vec3(cell) + h) * side + drift * u_motion.w;
    place += mod((v - drift) * u_motion.w, side);
    place.z -= u_particle_scale.y;  // the camera is at the origin, the lattice on the ground
    place = normalize(place) * (r0 + g.z * depth);
    // a flake flutters: its velocity wanders by ~0.3 m/s about the wind's, each its own way
    if (snow) v.xy += 0.3 * sin(u_motion.w * vec2(1.3, 0.9) + 6.2832 * h.yz);
    vec3 path = v * u_motion.z;     // its motion over the exposure
    // the closest approach of the view ray (from the origin along dir) to the path
    float len = length(path);
    vec3 along = len > 1e-6 ? path / len : vec3(0.0, 0.0, -1.0);
    float b = dot(dir, along);
    float denom = max(1.0 - b * b, 1e-6);
    float s = clamp((b * dot(place, dir) - dot(place, along)) / denom, 0.0, len);
    vec3 point = place + along * s;
    float t = dot(point, dir);
    if (t <= 0.05) return 0.0;
    float miss = length(point - dir * t);
    float width = size_mm * 1e-3;          // the particle's size (m)
    float pixel = u_pixel_rad * t;         // the pixel's footprint there (m)
    float reach = 0.5 * (width + pixel);   // the closest approach at which it touches the pixel
    if (miss > reach) return 0.0;
    // Its share of the pixel over the exposure, the same wherever it passes within reach
    // (softened at the edge): over every place it could pass, the shares add up to its
    // cross-section pi w^2 / 4 over the pixel's area, as the time-averaged overlap of a disk
    // moving across a square does; so the mean share of a pixel covered is the particles'
    // projected area per unit area of the view (unbiased, whatever the streak's length).
    float across = len * sqrt(denom);      // the streak's length across the view ray (m)
    float band = 1.5 * reach;              // the edge profile's integral across the path
    float share = 0.7853982 * width * width / (band * (across + band));
    return min(share, 1.0) * (1.0 - smoothstep(0.5 * reach, reach, miss));
}

void main() {
    vec4 behind = texelFetch(u_behind, ivec2(gl_FragCoord.xy), 0);
    frag = behind;
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) return;
    bool snow = u_particles.w > 0.5;
    // the lattice drifts with a typical particle (a millimetre drop, a centimetre flake)
    vec3 drift = velocity(snow ? 10.0 : 1.0, snow);
    vec4 light = behind;
    // far to near: a nearer particle covers a farther one
    float depth = (u_far_m - NEAR_M) / float(SHEETS);
    for (int k = SHEETS - 1; k >= 0; --k) {
        float r0 = NEAR_M + float(k) * depth;
        float side = inversesqrt(max(u_particles.x * depth, 1e-9));
        vec3 p = dir * (r0 + 0.5 * depth) + vec3(0.0, 0.0, u_particle_scale.y) - drift * u_motion.w;
        if (p.z + drift.z * u_motion.w < 0.0) continue;  // below the ground
        // the cubes a particle passing here in the exposure started from: back along the
        // lattice's motion over the exposure (at most MAX_CUBES)
        vec3 back = drift * u_motion.z;
        int cubes = min(int(ceil(length(back) / side)) + 1, MAX_CUBES);
        float a = 0.0;
        ivec3 last = ivec3(-2147483647);
        for (int j = 0; j < cubes; ++j) {
            ivec3 cell = ivec3(floor((p - back * (float(j) / float(max(cubes - 1, 1)))) / side));
            if (cell == last) continue;
            last = cell;
            a += coverage(dir, cell, side, r0, depth, drift, 17 * k, snow);
        }
        light = mix(light, u_particle_radiance, min(a, 1.0));
    }
    frag = light;
}
