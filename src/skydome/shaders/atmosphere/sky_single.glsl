// Frame pass: single-scattering sky seen by a camera, output (R, G, B, scotopic) in cd/m^2.
#include "common/camera.glsl"
#include "atmosphere/single_scattering.glsl"

uniform vec3 u_camera_position;  // km, planet centred, axes of the observer's ENU frame
uniform vec3 u_sun_direction;    // unit, ENU
uniform int u_view_samples;
uniform int u_jitter;            // 1: per-pixel 4x4 ordered offsets (seed 000 eq. 5.14)
uniform float u_output_scale;    // solar irradiance scale (1 = the spectrum of the params)

out vec4 frag;

// 4x4 Bayer matrix: sample offsets that differ between neighbouring pixels, so that the
// banding of a coarse ray march turns into a fine, regular pattern (seed 000, eq. 5.14).
float ray_offset(vec2 frag_xy) {
    if (u_jitter == 0) return 0.5;
    const int bayer[16] = int[16](0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5);
    ivec2 q = ivec2(frag_xy) & 3;
    return (float(bayer[q.y * 4 + q.x]) + 0.5) / 16.0;
}

void main() {
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) { frag = vec4(0.0); return; }
#ifdef OUTPUT_DIRECTIONS
    frag = vec4(dir, 1.0);
    return;
#endif
    vec4 radiance[NUM_GROUPS];
    single_scattering(u_camera_position, dir, u_sun_direction, u_view_samples,
                      ray_offset(gl_FragCoord.xy), radiance);
    vec4 rgbs = vec4(0.0);
    for (int g = 0; g < NUM_GROUPS; ++g) rgbs += u_spectral_to_rgbs[g] * radiance[g];
    frag = rgbs * u_output_scale;
}
