// Frame pass: the sky from the precomputed tables (every scattering order), the ground lit by
// the Sun and the sky, the Sun's disk, an optional second light source, optional light
// shafts (a shadow length per pixel) and optional aerial perspective in front of a user's
// scene (a distance per pixel). Output (R, G, B, scotopic) in cd/m^2.
// With COMPOSITE_BEHIND (the scene's frame graph), the light from beyond the atmosphere in
// u_behind is seen through the air along each ray that does not end on the ground, and the
// Sun's disk is left to the Sun layer (the surface pass draws the ground only).
#include "common/camera.glsl"
#include "atmosphere/surface_radiance.glsl"

uniform vec3 u_camera_position;    // km, planet centred, ENU axes of the observer
uniform vec3 u_sun_direction;      // unit, ENU
uniform float u_sun_scale;         // the Sun's irradiance / the params' solar spectrum
#ifdef HAS_LIGHT2
// A second light (compiled in only when used: CPU rasterizers pay for untaken branches).
uniform vec3 u_light2_direction;   // e.g. the Moon, unit, ENU
uniform vec4 u_light2_scale;       // per output channel: its irradiance in units of the
                                   // params' solar spectrum times its colour
#endif
#ifdef HAS_SHADOW_MAP
#include "atmosphere/shadow_map.glsl"
#endif
#ifdef HAS_DEPTH_MAP
uniform sampler2D u_depth_map;     // distance to the user's scene along each ray, km (<= 0: none)
layout(location = 1) out vec4 frag_transmittance;
#endif
layout(location = 0) out vec4 frag;
#ifdef HAS_ECLIPSE
#include "atmosphere/eclipse_sky.glsl"
#endif
#ifdef COMPOSITE_BEHIND
#include "common/behind.glsl"
const bool DRAW_DISK = false;
#else
const bool DRAW_DISK = true;
#endif

// Radiance of the surfaces at the end of the ray, seen through the air, for one light at unit
// scale: the Lambertian ground or the light's disk (atmosphere/surface_radiance.glsl).
vec4 surface_radiance(vec3 camera, vec3 dir, vec3 light, bool with_disk) {
    vec3 entry;
    float r, rmu;
    bool hits_ground = ray_ends_on_ground(camera, dir, entry, r, rmu);
    if (hits_ground) return ground_radiance(entry, dir, r, clamp_cosine(rmu / r), light);
    if (with_disk && r > 0.0 && sees_disk(dir, light)) return disk_radiance(r, clamp_cosine(rmu / r));
    return vec4(0.0);
}

// True where a pixel needs surface_radiance (for the sky pass to mark it).
bool needs_surface(vec3 camera, vec3 dir) {
    vec3 entry;
    float r, rmu;
    bool ground = ray_ends_on_ground(camera, dir, entry, r, rmu);
    return ground || (DRAW_DISK && r > 0.0 && sees_disk(dir, u_sun_direction));
}

void main() {
#ifndef SURFACE_PASS
    gl_FragDepth = 1.0;  // no surface pass here unless set to 0.5 below
#endif
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) {
        frag = vec4(0.0);
#ifdef HAS_DEPTH_MAP
        frag_transmittance = vec4(1.0);
#endif
        return;
    }
    float shadow_length = 0.0, shadow_start = 0.0;
#ifdef HAS_SHADOW_MAP
    shadow_map_at(ivec2(gl_FragCoord.xy), shadow_length, shadow_start);
#endif
#ifdef HAS_DEPTH_MAP
    float depth = texelFetch(u_depth_map, ivec2(gl_FragCoord.xy), 0).r;
    if (depth > 0.0) {
        // Aerial perspective: in-scattered light between the camera and the scene point, and
        // the transmittance the scene's own radiance is multiplied by.
        vec3 point = u_camera_position + dir * depth;
        frag = u_sun_scale * sky_radiance_to_point(u_camera_position, point, shadow_length, u_sun_direction);
#ifdef HAS_LIGHT2
        frag += u_light2_scale * sky_radiance_to_point(u_camera_position, point, 0.0, u_light2_direction);
#endif
        float r, rmu;
        vec3 cam = u_camera_position;
        vec3 column = vec3(0.0);
        if (enter_atmosphere(cam, dir, r, rmu)) {
            float mu = clamp_cosine(rmu / r);
            bool hits_ground = ray_hits_ground(r, mu);
            float d = min(max(depth - length(cam - u_camera_position), 0.0), ray_length(r, mu, hits_ground));
            column = column_along_ray(r, mu, d, hits_ground);
        }
        frag_transmittance = vec4(transmittance_rgb(column), 1.0);
        return;
    }
    frag_transmittance = vec4(0.0, 0.0, 0.0, 1.0);  // no scene: the sky below is all there is
#ifdef SURFACE_PASS
    frag_transmittance = vec4(0.0);  // added to the sky pass's value
#endif
#endif
    // Two passes (CPU rasterizers run a branch body for whole pixel blocks, so the surface
    // shading lives in its own pass, which an early depth test limits to the pixels that
    // need it): SKY_PASS writes the sky and a depth of 0.5 where a surface is seen (1.0
    // elsewhere); SURFACE_PASS adds the surfaces where the depth is 0.5.
#ifdef SURFACE_PASS
    frag = u_sun_scale * surface_radiance(u_camera_position, dir, u_sun_direction, DRAW_DISK);
#ifdef HAS_LIGHT2
    frag += u_light2_scale * surface_radiance(u_camera_position, dir, u_light2_direction, false);
#endif
#else
    vec3 column;
    frag = u_sun_scale * sky_radiance(u_camera_position, dir, shadow_start > 0.0 ? 0.0 : shadow_length,
                                      u_sun_direction, column);
#ifdef HAS_ECLIPSE
    // a solar eclipse: the uneclipsed Sun's sky, weighted by the sunlit part of the ray
    // (u_sun_scale is the eclipsed Sun's: 0 in totality)
    frag = u_eclipse_sky_scale * eclipse_sky_weight(length(u_camera_position), dir, u_sun_direction)
         * sky_radiance(u_camera_position, dir, shadow_start > 0.0 ? 0.0 : shadow_length,
                        u_sun_direction, column);
#endif
#ifdef HAS_SHADOW_MAP
    // a shadow away from the camera (the clouds' shafts): the air between its start and end
    // scatters no sunlight: its aerial perspective there taken off
    if (shadow_start > 0.0) {
        vec3 o = u_camera_position;
        frag -= u_sun_scale * (sky_radiance_to_point(o, o + dir * (shadow_start + shadow_length), 0.0, u_sun_direction)
                             - sky_radiance_to_point(o, o + dir * shadow_start, 0.0, u_sun_direction));
        frag = max(frag, vec4(0.0));
    }
#endif
#ifdef HAS_LIGHT2
    frag += u_light2_scale * sky_radiance(u_camera_position, dir, 0.0, u_light2_direction, column);
#endif
    bool surface = needs_surface(u_camera_position, dir);
#ifdef COMPOSITE_BEHIND
    // The ground hides what lies beyond; column is 0 where the ray misses the atmosphere.
    if (!surface) frag += light_behind(gl_FragCoord.xy) * behind_transmittance(column);
#endif
    gl_FragDepth = surface ? 0.5 : 1.0;
#endif
}
