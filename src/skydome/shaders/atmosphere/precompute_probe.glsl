// Evaluates the lookups of atmosphere/precomputed_lookup.glsl at given points and directions, one texel
// per query (atmosphere/precompute_probe.py): for tests, benchmarks and illuminance values.
// PROBE_MODE 0: sky_radiance (+ the Lambertian ground for rays that hit it, PROBE_GROUND 1:
//               lit by the Sun only, like the single-scattering renderer; 2: Sun and sky;
//               common/ground_shading.glsl's lambertian_ground, as the frames draw it)
//               -> location 0; location 1 = column densities to the end of the ray (km).
// PROBE_MODE 1: sky_radiance_to_point, point = position + direction * distance (km).
// PROBE_MODE 2: sun_and_sky_irradiance with normal = direction -> location 0 the Sun's,
//               location 1 the sky's.
#include "common/ground_shading.glsl"

uniform sampler2D u_probe_points;  // xyz: planet-centred position (km)
uniform sampler2D u_probe_dirs;    // xyz: unit direction or normal; w: distance (km, mode 1)
uniform vec3 u_sun_direction;
uniform float u_shadow_length;     // km

layout(location = 0) out vec4 out_main;
layout(location = 1) out vec4 out_extra;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 x = texelFetch(u_probe_points, p, 0).xyz;
    vec4 dw = texelFetch(u_probe_dirs, p, 0);
    vec3 v = normalize(dw.xyz);
    vec3 s = normalize(u_sun_direction);
    out_extra = vec4(0.0);
#if PROBE_MODE == 0
    vec3 column;
    vec4 L = sky_radiance(x, v, u_shadow_length, s, column);
#if PROBE_GROUND
    vec2 t_ground = ray_sphere(x, v, u_bottom_radius);
    if (t_ground.x > 0.0) {
        vec3 n = normalize(x + v * t_ground.x);
        L += lambertian_ground(n * u_bottom_radius, n, s, column, PROBE_GROUND == 2);
    }
#endif
    out_main = L;
    out_extra = vec4(column, 0.0);
#elif PROBE_MODE == 1
    out_main = sky_radiance_to_point(x, x + v * dw.w, u_shadow_length, s);
#else
    vec4 sky;
    out_main = sun_and_sky_irradiance(x, v, s, sky);
    out_extra = sky;
#endif
}
