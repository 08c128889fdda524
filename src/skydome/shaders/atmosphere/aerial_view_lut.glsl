// Aerial-perspective table pass (atmosphere/sky_view_mapping.glsl; layered: one layer per distance slice):
// per texel, the phase-free light scattered towards the camera by the air between it and the
// point at the slice's distance along the texel's direction, for one light at unit scale
// (scattering_to_point), (R, G, B, scotopic) in cd/m^2:
//   location 0: Rayleigh + orders >= 2 (/ P_R);   location 1: single Mie (/ P_M).
// Hillaire 2020 keeps such a volume in camera-frustum coordinates; here the directions of the
// sky-view tables make it independent of the camera model and of where the camera looks.
#include "atmosphere/precomputed_lookup.glsl"
#include "atmosphere/sky_view_mapping.glsl"

uniform vec3 u_light_direction;  // unit, ENU

flat in int v_layer;
layout(location = 0) out vec4 frag_scattering;
layout(location = 1) out vec4 frag_single_mie;

void main() {
    vec3 light = u_light_direction;
    bool hits_ground;
    vec3 dir = sky_view_texel_direction(ivec2(gl_FragCoord.xy), light, u_aerial_size.xy, hits_ground);
    float d = aerial_slice_distance(v_layer, ray_length(u_view_radius, dir.z, hits_ground));
    scattering_to_point(vec3(0.0, 0.0, u_view_radius), dir, d, 0.0, light, frag_scattering,
                        frag_single_mie);
}
