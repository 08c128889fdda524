// The clouds over what lies behind them (skydome.clouds.layer), per pixel of the frame:
// behind T_c + A, with T_c the clouds' transmittance and A what they add seen through the air
// (clouds/clouds_march.glsl, possibly at a reduced resolution). A pixel the clouds leave
// untouched (T_c = 1, A = 0) is passed through bit for bit.
//
// The march's texels are read bilinearly, but only those whose ray ends as this pixel's does
// (on the ground, or not: the march's data.w): at the horizon a texel of the ground must not
// lend its T_c = 1 to a pixel of the sky behind a cloud (a bright line of the clear horizon
// seen through it) nor a cloud's texel its light to the ground.
//
// With DIRECTION_TABLE the march is a table of view directions (a fog alone, the same
// everywhere: clouds/direction_table.glsl), read bilinearly at this pixel's direction (its
// halves keep the ground's rays from the sky's).
#include "common/camera.glsl"
#ifdef DIRECTION_TABLE
#include "clouds/direction_table.glsl"
#endif

uniform sampler2D u_behind;
uniform sampler2D u_cloud_radiance;
uniform sampler2D u_cloud_data;
uniform vec4 u_cloud_map;  // texture coordinate of a frame pixel = tile_xy * xy + zw
uniform vec4 u_ground_sphere;  // the camera (km, planet-centred) and the ground's radius (km)

layout(location = 0) out vec4 frag;

// 1 where the ray of this pixel misses the ground, else 0 (as the march's data.w).
float sky_class(vec2 tile_xy) {
    vec3 d;
    if (!camera_ray(tile_xy, d)) return 1.0;
    vec3 o = u_ground_sphere.xyz;
    float b = dot(o, d), c = dot(o, o) - u_ground_sphere.w * u_ground_sphere.w;
    return (b < 0.0 && b * b >= c) ? 0.0 : 1.0;
}

void main() {
    vec4 behind = texelFetch(u_behind, ivec2(gl_FragCoord.xy), 0);
#ifdef DIRECTION_TABLE
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) { frag = behind; return; }
    vec2 uv = direction_table_uv(dir);
    float T = texture(u_cloud_data, uv).x;
    vec4 added = texture(u_cloud_radiance, uv);
#else
    vec2 uv = gl_FragCoord.xy * u_cloud_map.xy + u_cloud_map.zw;
    ivec2 size = textureSize(u_cloud_data, 0);
    vec2 p = uv * vec2(size) - 0.5;
    ivec2 i0 = ivec2(floor(p));
    vec2 f = p - vec2(i0);
    float klass = sky_class(gl_FragCoord.xy);
    vec4 added = vec4(0.0);
    float T = 0.0, weight = 0.0;
    vec4 any_added = vec4(0.0);
    float any_T = 0.0;
    for (int k = 0; k < 4; ++k) {
        ivec2 o = ivec2(k & 1, k >> 1);
        ivec2 q = clamp(i0 + o, ivec2(0), size - 1);
        float w = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y);
        vec4 data = texelFetch(u_cloud_data, q, 0);
        vec4 rad = texelFetch(u_cloud_radiance, q, 0);
        any_T += w * data.x;
        any_added += w * rad;
        if (data.w == klass) {
            T += w * data.x;
            added += w * rad;
            weight += w;
        }
    }
    if (weight > 1e-6) {
        T /= weight;
        added /= weight;
    } else {  // no texel of this pixel's kind around (a thin sliver): all four
        T = any_T;
        added = any_added;
    }
#endif
    frag = (T >= 1.0 && added == vec4(0.0)) ? behind : max(behind * T + added, vec4(0.0));
}
