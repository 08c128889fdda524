// Light shafts (skydome.clouds.layer): the length (km) of each view ray's air that lies in the
// clouds' shadow and its first moment (km^2), for the atmosphere's HAS_SHADOW_MAP input
// (atmosphere/shadow_map.glsl: the sky loses the light scattered along a segment of that length
// about the shadow's mean distance: a low Sun's shafts lie tens of kilometres away, where
// Bruneton's shadow next to the camera would take off the near air's light). Marched over
// the first u_shaft_km of the ray, to the ground or to the clouds' top (no shadow above it), in
// SHAFT_STEPS equal steps, each sampled at an offset that runs through a 2 x 2
// ordered pattern of pixels (a shadow's edge then moves the length by a quarter step per
// pixel, not a whole one: equal samples everywhere draw the shadow length as contours), the
// pattern averaged by the upsampling's tent filter (clouds/upsample.glsl; shafts are smooth:
// the pass runs at a reduced resolution); each sample's shadow through the clouds' shells,
// sampled every SHAFT_SAMPLE_KM of each crossing.
#include "common/camera.glsl"
#include "atmosphere/precomputed_lookup.glsl"
#include "clouds/cloud_paths.glsl"

uniform vec3 u_camera_position;  // km, planet-centred
uniform vec3 u_sun_direction;
uniform float u_shaft_km;

layout(location = 0) out vec4 frag;

const int SHAFT_STEPS = 24;
// A shadow's crossing of a shell is sampled every SHAFT_SAMPLE_KM (3 to 16 samples): towards
// a low Sun it runs tens of kilometres through the layer, where 3 samples hit or miss its
// cells at random (blobs, not rays)
const float SHAFT_SAMPLE_KM = 1.0;

float crossing_transmittance(vec3 p, vec3 L, float r_lo, float r_hi) {
    vec2 seg;
    if (r_hi <= r_lo || !shell_segment(p, L, r_lo, r_hi, 1e30, seg)) return 1.0;
    int n = clamp(int((seg.y - seg.x) / SHAFT_SAMPLE_KM), 3, 16);
    return exp(-optical_depth_along(p + L * seg.x, L, seg.y - seg.x, n, false));
}

float shaft_transmittance(vec3 p, vec3 L) {
    return crossing_transmittance(p, L, u_cloud_shell.x, u_cloud_shell.y)
         * crossing_transmittance(p, L, u_cloud_shell.z, u_cloud_shell.w)
         * crossing_transmittance(p, L, u_ground_layer.x, max(u_ground_layer.y, u_ground_layer.z));
}

void main() {
    frag = vec4(0.0);
    vec3 d;
    if (!camera_ray(gl_FragCoord.xy, d)) return;
    vec3 o = u_camera_position;
    vec2 ground = ray_sphere(o, d, u_bottom_radius);
    float end = min(ground.x > 0.0 ? ground.x : 1e30, u_shaft_km);
    // the air above the clouds' tops is in no cloud's shadow (the Sun above the horizon):
    // the main layer's top, or the cirrus's without one
    float r_shadows = u_cloud_shell.y > u_cloud_shell.x ? u_cloud_shell.y : u_cloud_shell.w;
    vec2 top = ray_sphere(o, d, min(max(r_shadows, u_ground_layer.y), u_top_radius));
    end = min(end, max(top.y, 0.0));
    if (end <= 0.0) return;
    float dt = end / float(SHAFT_STEPS);
    ivec2 xy = ivec2(gl_FragCoord.xy) & 1;
    float t = (0.125 + 0.25 * float(xy.x * 2 + (xy.x ^ xy.y))) * dt;
    vec2 shadowed = vec2(0.0);  // the length and its first moment
    for (int i = 0; i < SHAFT_STEPS; ++i, t += dt)
        shadowed += (1.0 - shaft_transmittance(o + d * t, u_sun_direction)) * dt * vec2(1.0, t);
    frag = vec4(shadowed, 0.0, 0.0);
}
