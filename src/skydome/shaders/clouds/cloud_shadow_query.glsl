// The shadow query (skydome.clouds.layer.CloudLayer.light_transmittance): for each texel of
// u_points (planet-centred positions, km, one per texel of a row), the transmittance of the
// clouds towards the key light (clouds/cloud_paths.glsl's light_transmittance with
// QUERY_STEPS samples per shell crossing, a define). A point inside a shell counts the cloud
// from it.
#include "atmosphere/precomputed_lookup.glsl"
#include "clouds/cloud_paths.glsl"

uniform sampler2D u_points;
uniform vec3 u_light_direction;

layout(location = 0) out vec4 frag;

void main() {
    vec3 p = texelFetch(u_points, ivec2(gl_FragCoord.xy), 0).xyz;
    frag = vec4(light_transmittance(p, u_light_direction, QUERY_STEPS));
}
