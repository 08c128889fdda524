// Frame pass from sky-view tables (atmosphere/sky_view_lut.glsl): two bilinear fetches per pixel and light,
// the phase functions evaluated exactly, and the Sun's disk. Output (R, G, B, scotopic) in
// cd/m^2. The camera is inside the atmosphere, on the z axis at u_view_radius.
// Two passes, as in atmosphere/sky_precomputed.glsl (CPU rasterizers run a branch's body for every
// pixel): the sky, writing a depth of 0.5 on the Sun's disk and 1.0 elsewhere; then, with
// SURFACE_PASS, the disk added where an early depth test finds 0.5.
// With HAS_DEPTH_MAP, pixels with a scene (distance > 0) get the aerial perspective from the
// aerial-perspective tables (atmosphere/aerial_view_lut.glsl) instead, and location 1 the RGB
// transmittance to the scene point, as in atmosphere/sky_precomputed.glsl. With HAS_SHADOW_MAP (light
// shafts: the first `shadow length` of each ray lies in an occluder's shadow), the Sun's light
// scattered along that part, read from the same tables, is taken off the sky: Bruneton's
// T(x, x_p) S(x_p) is exactly S(x) - [S(x) - T(x, x_p) S(x_p)], the sky minus the aerial
// perspective of the shadowed part; where a scene is given too, the aerial perspective of its
// distance less the shadowed length.
// With COMPOSITE_BEHIND (the scene's frame graph), the light from beyond the atmosphere that
// the space layers drew (u_behind: the Sun's and the Moon's disks, later the stars) is seen
// through the air along each ray that leaves it, and the disk is not drawn here (it belongs
// to the Sun layer): one sky pass, no surface pass.
#include "common/camera.glsl"
#include "atmosphere/surface_radiance.glsl"
#include "atmosphere/sky_view_mapping.glsl"

uniform vec3 u_sun_direction;  // unit, ENU
uniform float u_sun_scale;     // the Sun's irradiance / the params' solar spectrum
uniform sampler2D u_sun_scattering;
uniform sampler2D u_sun_single_mie;
#ifdef HAS_LIGHT2
uniform vec3 u_light2_direction;
uniform vec4 u_light2_scale;   // per output channel: its irradiance and colour (e.g. the Moon)
uniform sampler2D u_light2_scattering;
uniform sampler2D u_light2_single_mie;
#endif
layout(location = 0) out vec4 frag;
#ifdef COMPOSITE_BEHIND
#include "common/behind.glsl"
#include "atmosphere/view_transmittance.glsl"
#endif
#ifdef HAS_SHADOW_MAP
#include "atmosphere/shadow_map.glsl"
#endif
#if defined(HAS_DEPTH_MAP) || defined(HAS_SHADOW_MAP)
#include "atmosphere/aerial_lookup.glsl"
#endif
#ifdef HAS_DEPTH_MAP
uniform sampler2D u_depth_map;  // distance to the user's scene along each ray, km (<= 0: none)
layout(location = 1) out vec4 frag_transmittance;
#endif
#ifdef HAS_ECLIPSE
#include "atmosphere/eclipse_sky.glsl"
#endif

// The sky from a light's tables: `unit` = sky_view_unit of the pixel for that light, nu the
// cosine of the angle between the view and the light.
vec4 sky_from_table(sampler2D scattering, sampler2D single_mie, vec3 unit, float nu) {
    vec2 uv = sky_view_texcoords(unit, u_sky_view_size);
    return texture(scattering, uv) * rayleigh_phase(nu)
         + texture(single_mie, uv) * mie_phase_channels(nu);
}

void main() {
#ifndef SURFACE_PASS
    gl_FragDepth = 1.0;
#endif
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) {
        frag = vec4(0.0);
#ifdef HAS_DEPTH_MAP
        frag_transmittance = vec4(1.0);
#endif
        return;
    }
    float r = u_view_radius;
    bool hits_ground = ray_hits_ground(r, dir.z);
    bool scene = false;
#ifdef HAS_DEPTH_MAP
    float depth = texelFetch(u_depth_map, ivec2(gl_FragCoord.xy), 0).r;
    scene = depth > 0.0;
#endif
#ifdef SURFACE_PASS
    frag = u_sun_scale * disk_radiance(r, dir.z);
#ifdef HAS_DEPTH_MAP
    frag_transmittance = vec4(0.0);  // added to the sky pass's value
#endif
#else
    // The table coordinates and phase angle of each light, computed once for all its tables.
    vec3 sun_unit = sky_view_unit(azimuth_from_light(dir, u_sun_direction), dir.z, hits_ground);
    float sun_nu = dot(dir, u_sun_direction);
#ifdef HAS_ECLIPSE
    // a solar eclipse: the uneclipsed Sun's sky, weighted by the sunlit part of the ray
    frag = u_eclipse_sky_scale * eclipse_sky_weight(r, dir, u_sun_direction)
         * sky_from_table(u_sun_scattering, u_sun_single_mie, sun_unit, sun_nu);
#else
    frag = u_sun_scale * sky_from_table(u_sun_scattering, u_sun_single_mie, sun_unit, sun_nu);
#endif
#if defined(HAS_DEPTH_MAP) || defined(HAS_SHADOW_MAP)
    float ray_length_km = ray_length(r, dir.z, hits_ground);
#endif
    float shadow_length = 0.0, shadow_start = 0.0;
#ifdef HAS_SHADOW_MAP
    shadow_map_at(ivec2(gl_FragCoord.xy), shadow_length, shadow_start);
    if (shadow_length > 0.0) {
        // the aerial perspective of the shadowed segment: up to its end, less up to its start
        // (none when it starts at the camera)
        vec4 shadowed = aerial_from_table(u_sun_aerial_scattering, u_sun_aerial_single_mie,
                                          sun_unit, sun_nu, shadow_start + shadow_length,
                                          ray_length_km);
        if (shadow_start > 0.0)
            shadowed -= aerial_from_table(u_sun_aerial_scattering, u_sun_aerial_single_mie,
                                          sun_unit, sun_nu, shadow_start, ray_length_km);
        frag = max(frag - u_sun_scale * max(shadowed, vec4(0.0)), vec4(0.0));
    }
#endif
#ifdef HAS_LIGHT2
    vec3 light2_unit = sky_view_unit(azimuth_from_light(dir, u_light2_direction), dir.z, hits_ground);
    float light2_nu = dot(dir, u_light2_direction);
    frag += u_light2_scale * sky_from_table(u_light2_scattering, u_light2_single_mie, light2_unit,
                                            light2_nu);
#endif
#ifdef HAS_DEPTH_MAP
    frag_transmittance = vec4(0.0, 0.0, 0.0, 1.0);  // no scene: the sky below is all there is
    if (scene) {
        float d = min(depth, ray_length_km);
        // With light shafts, the last shadow_length before the scene scatters no sunlight
        // (Bruneton 2017 GetSkyRadianceToPoint: the distance is shortened by it).
        frag = u_sun_scale * aerial_from_table(u_sun_aerial_scattering, u_sun_aerial_single_mie,
                                               sun_unit, sun_nu, max(d - shadow_length, 0.0),
                                               ray_length_km);
#ifdef HAS_LIGHT2
        frag += u_light2_scale * aerial_from_table(u_light2_aerial_scattering,
                                                   u_light2_aerial_single_mie, light2_unit,
                                                   light2_nu, d, ray_length_km);
#endif
        frag_transmittance = vec4(transmittance_rgb(column_along_ray(r, dir.z, d, hits_ground)), 1.0);
    }
#endif
#ifdef COMPOSITE_BEHIND
    // What lies beyond, seen through the air (hidden by the ground and a user's scene): one
    // fetch from the table of this altitude's view transmittance.
    if (!scene && !hits_ground)
        frag += light_behind(gl_FragCoord.xy) * view_transmittance(dir.z);
#else
    gl_FragDepth = !scene && !hits_ground && sees_disk(dir, u_sun_direction) ? 0.5 : 1.0;
#endif
#endif
}
