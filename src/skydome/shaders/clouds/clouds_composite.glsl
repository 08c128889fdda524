// The clouds over what lies behind them (skydome.clouds.layer), per pixel of the frame:
//   out = behind T_c + (1 - T_c) S(0 -> d) + T(0 -> d) L_c
// with L_c and T_c the clouds' radiance and transmittance (clouds/clouds_march.glsl, possibly
// at a reduced resolution: read bilinearly), d the light-weighted distance to them, S(0 -> d)
// the air's in-scattered light in front of them and T(0 -> d) its transmittance (the
// atmosphere's tables): behind already holds S(0 -> d) + T(0 -> d) X, the light X reaching
// the clouds from beyond, so this is S + T (L_c + T_c X) exactly. Where the ray ends on the
// ground in a cloud's shadow, the direct light of the ground is taken off. A pixel the clouds
// leave untouched is passed through bit for bit.
#include "common/camera.glsl"
#include "atmosphere/surface_radiance.glsl"

uniform sampler2D u_behind;
uniform sampler2D u_cloud_radiance;
uniform sampler2D u_cloud_data;
uniform vec4 u_cloud_map;          // texture coordinate of a frame pixel = tile_xy * xy + zw
uniform vec3 u_camera_position;    // km, planet-centred
uniform vec3 u_sun_direction;
uniform float u_sun_scale;
#ifdef HAS_LIGHT2
uniform vec3 u_light2_direction;
uniform vec4 u_light2_scale;
#endif
uniform vec3 u_light_direction;    // the key light of the march (its shadows)
uniform vec4 u_light_scale;

layout(location = 0) out vec4 frag;

void main() {
    vec4 behind = texelFetch(u_behind, ivec2(gl_FragCoord.xy), 0);
    frag = behind;
    vec3 d;
    if (!camera_ray(gl_FragCoord.xy, d)) return;
    vec2 uv = gl_FragCoord.xy * u_cloud_map.xy + u_cloud_map.zw;
    vec4 cloud = texture(u_cloud_data, uv);
    float T = cloud.x;
    if (T >= 1.0 && cloud.z >= 1.0) return;
    vec3 o = u_camera_position;
    vec4 result = behind * T;
    if (T < 1.0) {
        vec3 point = o + d * max(cloud.y, 1e-3);
        vec4 air = u_sun_scale * sky_radiance_to_point(o, point, 0.0, u_sun_direction);
#ifdef HAS_LIGHT2
        air += u_light2_scale * sky_radiance_to_point(o, point, 0.0, u_light2_direction);
#endif
        vec3 entry = o;
        float r, rmu;
        vec4 t_air = vec4(1.0);
        if (enter_atmosphere(entry, d, r, rmu)) {
            float mu = clamp_cosine(rmu / r);
            float along = max(cloud.y - length(entry - o), 0.0);
            t_air = output_transmittance(column_along_ray(r, mu, along, ray_hits_ground(r, mu)));
        }
        result += (1.0 - T) * air + t_air * texture(u_cloud_radiance, uv);
    }
    if (cloud.z < 1.0) {
        vec3 entry;
        float r, rmu;
        if (ray_ends_on_ground(o, d, entry, r, rmu)) {
            // the ground's direct light only (common/ground_shading.glsl), seen through the air
            float mu = clamp_cosine(rmu / r);
            float d_ground = distance_to_bottom(r, mu);
            vec3 n = normalize(entry + d * d_ground);
            vec4 direct = u_light_scale * lambertian_ground(n * u_bottom_radius, n, u_light_direction,
                                                            column_along_ray(r, mu, d_ground, true), false);
            result = max(result - T * (1.0 - cloud.z) * direct, vec4(0.0));
        }
    }
    frag = result;
}
