// Planets layer (space stage): one planet's disk beyond the atmosphere, a sphere lit by
// parallel sunlight from its true planet -> Sun direction, seen through refraction and hidden
// where the Moon's disk lies in front. Photometric law (skydome.celestial.planets):
// Lambert, L = k mu0 (LAW 0), or Lommel-Seeliger, L = k mu0 / (mu0 + mu) (LAW 1); k is set
// on the CPU so that the disk integrates to the planet's illuminance. A planet disk is a few
// pixels across, so each pixel averages u_samples x u_samples rays spread over its footprint
// (the pixel's mean radiance, so radiance x pixel solid angle sums to the illuminance).
// Output: the planet's colour (solar spectrum x its albedo spectrum) in the frame's output
// channels, drawn added; the atmosphere layer applies the transmittance.
#include "celestial/disk_pixel.glsl"
#include "celestial/surface_laws.glsl"

uniform vec3 u_planet_direction_true;  // airless, unit ENU, observer -> planet centre
uniform float u_sin_angular_radius;
uniform vec3 u_planet_to_sun;          // unit ENU
uniform vec3 u_moon_direction_true;    // airless, unit ENU (the occulting Moon)
uniform float u_moon_sin_radius;       // 0: no Moon
uniform float u_scale;                 // cd/m^2 per unit of the law
uniform vec4 u_colour;                 // output channels per cd/m^2 of the planet's light
uniform int u_samples;                 // rays per pixel along each axis
out vec4 frag;

float law(vec3 true_dir) {
    if (!ray_meets_sphere(true_dir, u_planet_direction_true, u_sin_angular_radius)) return 0.0;
    if (u_moon_sin_radius > 0.0 && ray_meets_sphere(true_dir, u_moon_direction_true, u_moon_sin_radius))
        return 0.0;
    vec3 n = sphere_normal(true_dir, u_planet_direction_true, u_sin_angular_radius);
    float mu0 = dot(n, u_planet_to_sun);
    if (mu0 <= 0.0) return 0.0;
#if LAW == 0
    return lambert_law(mu0);
#else
    return lommel_seeliger_law(mu0, max(dot(n, -true_dir), 0.0));
#endif
}

void main() {
    float sum = 0.0;
    float step = 1.0 / float(u_samples);
    for (int j = 0; j < u_samples; ++j) {
        for (int i = 0; i < u_samples; ++i) {
            vec2 offset = (vec2(float(i), float(j)) + 0.5) * step - 0.5;
            vec3 dir;
            if (!camera_ray(gl_FragCoord.xy + offset, dir)) continue;
            sum += law(airless_direction(dir));
        }
    }
    frag = u_colour * (u_scale * sum * step * step);
}
