// Light shafts (skydome.clouds.layer): the length (km) of each view ray's air that lies in the
// clouds' shadow, for the atmosphere's HAS_SHADOW_MAP input (atmosphere/sky_view.glsl takes
// the light scattered along that length off the sky: Bruneton's shadow length, which puts the
// shadowed part next to the camera). Marched over the first u_shaft_km of the ray, or to the
// ground, in SHAFT_STEPS equal steps, each sampled at an offset that runs through a 2 x 2
// ordered pattern of pixels (a shadow's edge then moves the length by a quarter step per
// pixel, not a whole one: equal samples everywhere draw the shadow length as contours), the
// pattern averaged by the upsampling's tent filter (clouds/upsample.glsl; shafts are smooth:
// the pass runs at a reduced resolution); each sample's shadow from light_transmittance
// (clouds/cloud_paths.glsl) with 3 samples per shell crossing.
#include "common/camera.glsl"
#include "atmosphere/precomputed_lookup.glsl"
#include "clouds/cloud_paths.glsl"

uniform vec3 u_camera_position;  // km, planet-centred
uniform vec3 u_sun_direction;
uniform float u_shaft_km;

layout(location = 0) out vec4 frag;

const int SHAFT_STEPS = 24;

void main() {
    frag = vec4(0.0);
    vec3 d;
    if (!camera_ray(gl_FragCoord.xy, d)) return;
    vec3 o = u_camera_position;
    vec2 ground = ray_sphere(o, d, u_bottom_radius);
    float end = min(ground.x > 0.0 ? ground.x : 1e30, u_shaft_km);
    vec2 top = ray_sphere(o, d, u_top_radius);
    end = min(end, max(top.y, 0.0));
    if (end <= 0.0) return;
    float dt = end / float(SHAFT_STEPS);
    ivec2 xy = ivec2(gl_FragCoord.xy) & 1;
    float t = (0.125 + 0.25 * float(xy.x * 2 + (xy.x ^ xy.y))) * dt;
    float shadowed = 0.0;
    for (int i = 0; i < SHAFT_STEPS; ++i, t += dt)
        shadowed += (1.0 - light_transmittance(o + d * t, u_sun_direction, 3)) * dt;
    frag = vec4(shadowed);
}
