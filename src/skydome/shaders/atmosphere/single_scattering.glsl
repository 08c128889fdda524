// Single scattering along a view ray (Nishita 1993, seed 002): the in-scattered radiance
// per unit solar irradiance (sr^-1), NUM_GROUPS x 4 wavelengths, with Earth's shadow, ozone,
// the Lambertian ground seen through the atmosphere, and the Sun's disk.
// Transmittances come from the column-density table (atmosphere/transmittance_lut.glsl).
#include "atmosphere/transmittance_lut.glsl"
#include "common/phase_functions.glsl"
#include "common/spectral.glsl"
#include "common/mie_phase.glsl"

uniform float u_sun_angular_radius;  // rad

// Column densities between the ray start and a point on the ray at radius r_t where the
// ray's direction cosine is mu_t, given the start's column to the boundary `c0`
// (column_to_top(r0, mu0), or column_to_top(r0, -mu0) for rays that hit the ground).
// T(x -> y) = T(x -> top) / T(y -> top) for rays that do not hit the ground, and with the
// directions reversed for rays that do (Bruneton 2017, GetTransmittance).
// One table fetch whichever the side: the choice is made on its argument, not between two
// fetched results (a CPU rasterizer runs both arms of a per-pixel choice).
vec3 column_between(vec3 c0, float r_t, float mu_t, bool hits_ground) {
    vec3 c_t = column_to_top(r_t, hits_ground ? -mu_t : mu_t);
    return max(hits_ground ? c_t - c0 : c0 - c_t, vec3(0.0));
}

// Column densities from radius r towards the Sun (cosine mu_s), or -1 if the planet blocks it.
vec3 column_to_sun(float r, float mu_s) {
    return ray_hits_ground(r, mu_s) ? vec3(-1.0) : column_to_top(r, mu_s);
}

// Radiance per unit solar irradiance for the ray from `position` (km, planet centred) along
// unit `dir`, Sun towards unit `sun`. `offset` in [0,1) places the samples in their
// segments (0.5 = midpoint) in the quadratic sample spacing. Writes NUM_GROUPS vec4s.
void single_scattering(vec3 position, vec3 dir, vec3 sun, int samples, float offset,
                       out vec4 radiance[NUM_GROUPS]) {
    for (int g = 0; g < NUM_GROUPS; ++g) radiance[g] = vec4(0.0);
    float nu = dot(dir, sun);
    bool sun_in_view = nu > cos(u_sun_angular_radius);
    float sun_disk = 1.0 / (PI * sin(u_sun_angular_radius) * sin(u_sun_angular_radius));

    // Move a camera outside the atmosphere to where the ray enters it.
    float r = length(position);
    if (r > u_top_radius) {
        vec2 t_top = ray_sphere(position, dir, u_top_radius);
        if (t_top.y < 0.0) {  // misses the atmosphere: the Sun seen from space
            if (sun_in_view) for (int g = 0; g < NUM_GROUPS; ++g) radiance[g] = vec4(sun_disk);
            return;
        }
        position += dir * max(t_top.x, 0.0);
        r = u_top_radius;
    }
    float mu = clamp_cosine(dot(position, dir) / r);
    bool hits_ground = ray_hits_ground(r, mu);
    float length_km = hits_ground ? distance_to_bottom(r, mu) : distance_to_top(r, mu);
    // Samples are spaced quadratically, t = L u^2 with u uniform, denser near the camera where
    // the air is densest (looking up) and the ray is lowest (looking along the horizon):
    // integral f dt = integral f(L u^2) 2 L u du, by the rectangle rule in u.
    float du = 1.0 / float(samples);

    vec3 c0 = column_to_top(r, hits_ground ? -mu : mu);
    float phase_r = rayleigh_phase(nu);
    vec4 phase_m[NUM_GROUPS];
    for (int g = 0; g < NUM_GROUPS; ++g) phase_m[g] = mie_phase_group(nu, g);
    for (int i = 0; i < samples; ++i) {
        float u = (float(i) + offset) * du;
        float t = length_km * u * u;
        float dt = 2.0 * length_km * u * du;
        vec3 p = position + dir * t;
        float r_t = clamp(length(p), u_bottom_radius, u_top_radius);
        float mu_s = dot(p, sun) / r_t;
        if (ray_hits_ground(r_t, mu_s)) continue;  // in the planet's shadow
        // Column sample -> Sun, and sample -> boundary along the view ray (reversed for rays
        // that hit the ground), from one radius: T(camera -> sample) = T(c0) / T(sample).
        float mu_t = clamp_cosine(dot(p, dir) / r_t);
        vec3 c_sun, c_t;
        columns_to_top(r_t, mu_s, hits_ground ? -mu_t : mu_t, c_sun, c_t);
        vec3 c = max(hits_ground ? c_t - c0 : c0 - c_t, vec3(0.0)) + c_sun;
        vec3 d = densities(r_t - u_bottom_radius) * dt;
        for (int g = 0; g < NUM_GROUPS; ++g) {
            vec4 scattering = u_rayleigh_scattering[g] * (d.x * phase_r) + u_mie_scattering[g] * (d.y * phase_m[g]);
            radiance[g] += scattering * exp(-optical_depth(g, c));
        }
    }

    vec3 c_view = c0;
    if (hits_ground) {
        // Lambertian ground lit by the attenuated Sun: albedo / pi * T_sun * cos(sun zenith),
        // seen through the atmosphere.
        vec3 p = position + dir * length_km;
        vec3 n = normalize(p);
        c_view = column_between(c0, u_bottom_radius, clamp_cosine(dot(n, dir)), true);
        float mu_s = dot(n, sun);
        vec3 c_sun = column_to_sun(u_bottom_radius, mu_s);
        if (c_sun.x >= 0.0 && mu_s > 0.0) {
            for (int g = 0; g < NUM_GROUPS; ++g)
                radiance[g] += u_ground_albedo[g] * INV_PI * mu_s * exp(-optical_depth(g, c_sun + c_view));
        }
    } else if (sun_in_view) {
        for (int g = 0; g < NUM_GROUPS; ++g) radiance[g] += sun_disk * exp(-optical_depth(g, c_view));
    }
}
