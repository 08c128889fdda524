// The clouds' light map (clouds/light_map_warp.glsl; skydome.clouds.light_map), LIGHT_MAP_TEXELS
// a side: for each texel, the point of the sphere of the clouds' lowest base (u_light_map_warp.y
// km) at its offsets from the map's centre (.zw), and the clouds' transmittance towards the
// key light from there (clouds/cloud_paths.glsl's clouds_transmittance, LIGHT_PATH_STEPS
// samples per shell crossing, as the march's light paths take them). The point is taken 10 m
// back along the light, inside the sphere: on it, rounding may put it outside, and the lower
// shell's crossing would be lost. Texels outside the disk, or past the sphere's horizon,
// hold 1.
#include "atmosphere/precomputed_lookup.glsl"
#include "clouds/cloud_paths.glsl"
#include "clouds/light_map_warp.glsl"

uniform vec3 u_light_direction;  // the key light (unit, ENU)
uniform vec4 u_light_map_warp;   // (a, the lowest base's radius, the centre's x, y; km)

layout(location = 0) out vec4 frag;

void main() {
    frag = vec4(1.0);
    vec2 uv = gl_FragCoord.xy / float(LIGHT_MAP_TEXELS);
    if (length(2.0 * uv - 1.0) >= 1.0) return;
    vec2 xy = u_light_map_warp.zw + light_map_xy(uv, u_light_map_warp.x);
    float r = u_light_map_warp.y;
    float z2 = r * r - dot(xy, xy);
    if (z2 <= 0.0) return;
    vec3 q = vec3(xy, sqrt(z2)) - 0.01 * u_light_direction;
    frag = vec4(clouds_transmittance(q, u_light_direction, LIGHT_PATH_STEPS));
}
