// Sky-view table pass (atmosphere/sky_view_mapping.glsl): per texel, the phase-free sky values of the
// precomputed tables for one light at unit scale, (R, G, B, scotopic) in cd/m^2:
//   location 0: Rayleigh + orders >= 2 (/ P_R), plus, below the horizon, the lit ground seen
//               through the air divided by P_R(nu) (the frame multiplies by P_R again);
//   location 1: single Mie (/ P_M).
// Drawn in two halves (viewports): GROUND_HALF is compiled for the lower one only, since CPU
// rasterizers run a branch's body for every pixel.
#include "atmosphere/surface_radiance.glsl"
#include "atmosphere/sky_view_mapping.glsl"

uniform vec3 u_light_direction;  // unit, ENU

layout(location = 0) out vec4 frag_scattering;
layout(location = 1) out vec4 frag_single_mie;

void main() {
    vec3 light = u_light_direction;
    bool hits_ground;
    vec3 dir = sky_view_texel_direction(ivec2(gl_FragCoord.xy), light, u_sky_view_size, hits_ground);
    // Each half's rays all hit the ground or all leave the air: a constant, so that the
    // compiler drops the other arm of every hits_ground choice below (a CPU rasterizer would
    // run both: the sky half 2.3 -> 1.6 ms at 256^2 on llvmpipe).
#ifdef GROUND_HALF
    hits_ground = true;
#else
    hits_ground = false;
#endif
    float r = u_view_radius;
    vec3 camera = vec3(0.0, 0.0, r);
    float mu = dir.z;
    float nu = clamp_cosine(dot(dir, light));
    vec4 single_mie;
    vec4 scattering = combined_scattering(r, mu, clamp_cosine(light.z), nu, hits_ground, single_mie);
#ifdef GROUND_HALF
    scattering += ground_radiance(camera, dir, r, mu, light) / rayleigh_phase(nu);
#endif
    frag_scattering = scattering;
    frag_single_mie = single_mie;
}
