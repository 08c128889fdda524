// The surfaces a view ray can end on, seen through the air, for one light at unit scale
// (R, G, B, scotopic in cd/m^2): the Lambertian ground lit by the light and the sky, and the
// light's disk. Spectral: each wavelength group is attenuated on its own, then converted.
#include "common/ground_shading.glsl"

// Where the ray from `camera` along `dir` ends: on the ground (true), else at the top. The
// test must agree with the one of sky_radiance (same r, mu), or pixels at the horizon would
// get the wrong column. Also gives the entry point, r and r mu there.
bool ray_ends_on_ground(vec3 camera, vec3 dir, out vec3 entry, out float r, out float rmu) {
    entry = camera;
    return enter_atmosphere(entry, dir, r, rmu) && ray_hits_ground(r, clamp_cosine(rmu / r));
}

bool sees_disk(vec3 dir, vec3 light) { return dot(dir, light) > cos(u_sun_angular_radius); }

// The ground where the ray from `entry` (radius r, view cosine mu; it must hit the ground)
// along `dir` meets it, lit by `light` and the sky, seen through the air (common/ground_shading.glsl).
vec4 ground_radiance(vec3 entry, vec3 dir, float r, float mu, vec3 light) {
    float d_ground = distance_to_bottom(r, mu);
    vec3 column = column_along_ray(r, mu, d_ground, true);
    vec3 n = normalize(entry + dir * d_ground);
    return lambertian_ground(n * u_bottom_radius, n, light, column, true);
}

// The light's disk seen from radius r along a ray of view cosine mu that leaves the
// atmosphere: its radiance (irradiance / (pi sin^2 of the angular radius), a uniform disk)
// times the transmittance to the top.
vec4 disk_radiance(float r, float mu) {
    vec3 column = column_to_top(r, mu);
    float disk = 1.0 / (PI * sin(u_sun_angular_radius) * sin(u_sun_angular_radius));
    vec4 radiance = vec4(0.0);
    for (int g = 0; g < NUM_GROUPS; ++g) radiance += u_spectral_to_rgbs[g] * (disk * exp(-optical_depth(g, column)));
    return radiance;
}

// Spectral transmittance groups -> (R, G, B) of a white (solar) spectrum seen through them,
// normalised so that T = 1 gives 1: what a scene's linear sRGB colour is multiplied by.
vec3 transmittance_rgb(vec3 column) {
    vec4 t = vec4(0.0), one = vec4(0.0);
    for (int g = 0; g < NUM_GROUPS; ++g) {
        t += u_spectral_to_rgbs[g] * exp(-optical_depth(g, column));
        one += u_spectral_to_rgbs[g] * vec4(1.0);
    }
    return t.rgb / one.rgb;
}
