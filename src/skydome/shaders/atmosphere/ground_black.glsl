// Ground layer, "black" (volume stage, the last): zero wherever the camera's ray meets the
// planet, everything drawn in front of the ground included; what lies behind, unchanged,
// elsewhere. For environment maps whose user lights a scene with a ground of their own.
#include "common/camera.glsl"
#include "common/behind.glsl"

uniform float u_dip_sin;  // sin of the ground horizon's dip below the horizontal
out vec4 frag;

void main() {
    vec3 dir;
    frag = vec4(0.0);
    if (!camera_ray(gl_FragCoord.xy, dir)) return;
    if (dir.z < -u_dip_sin) return;  // the ray meets the ground
    frag = light_behind(gl_FragCoord.xy);
}
