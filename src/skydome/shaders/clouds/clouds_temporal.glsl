// The interactive mode's temporal accumulation (skydome.clouds.layer, quality "interactive"):
// each frame marches the clouds at a reduced resolution with a new sub-pixel and step offset;
// this pass blends it into the history of the frames before, reprojected to where the same
// direction lay in the previous frame (a perspective camera that turned; other models keep
// their pixels), with the history clamped to the current sample's 3x3 neighbourhood so that
// moving clouds leave no ghosts (Karis 2014). u_blend is the current frame's weight: 1 drops
// the history (the first frame, a jump).
#include "common/camera.glsl"

uniform sampler2D u_current_radiance;
uniform sampler2D u_current_data;
uniform sampler2D u_history_radiance;
uniform sampler2D u_history_data;
uniform float u_blend;
uniform mat3 u_prev_basis;        // the previous frame's perspective camera
uniform float u_prev_tan_half_fov;

layout(location = 0) out vec4 out_radiance;
layout(location = 1) out vec4 out_data;

void main() {
    ivec2 xy = ivec2(gl_FragCoord.xy);
    vec4 c = texelFetch(u_current_radiance, xy, 0);
    vec4 cd = texelFetch(u_current_data, xy, 0);
    out_radiance = c;
    out_data = cd;
    if (u_blend >= 1.0) return;
    vec2 uv = gl_FragCoord.xy / u_resolution;
#if CAMERA_MODEL == 0
    vec3 dir;
    camera_ray(gl_FragCoord.xy, dir);
    vec3 local = transpose(u_prev_basis) * dir;  // (right, up, forward) of the previous camera
    if (local.z <= 1e-6) return;
    float aspect = u_resolution.x / u_resolution.y;
    uv = (vec2(local.x / (local.z * u_prev_tan_half_fov),
               local.y / (local.z * u_prev_tan_half_fov / aspect)) + 1.0) * 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return;
#endif
    vec4 lo_r = c, hi_r = c, lo_d = cd, hi_d = cd;
    for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) {
            ivec2 q = clamp(xy + ivec2(i, j), ivec2(0), ivec2(u_resolution) - 1);
            vec4 r = texelFetch(u_current_radiance, q, 0), d = texelFetch(u_current_data, q, 0);
            lo_r = min(lo_r, r); hi_r = max(hi_r, r);
            lo_d = min(lo_d, d); hi_d = max(hi_d, d);
        }
    vec4 h = clamp(texture(u_history_radiance, uv), lo_r, hi_r);
    vec4 hd = clamp(texture(u_history_data, uv), lo_d, hi_d);
    out_radiance = mix(h, c, u_blend);
    out_data = mix(hd, cd, u_blend);
}
