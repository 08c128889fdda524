// Airglow layer (space stage): the night sky's own emission from a thin layer at ~90 km
// (OI 557.7 nm, Na D, OI 630/636 nm, OH, O2 and the continuum; skydome.night.airglow), seen
// brighter towards the horizon by the van Rhijn factor 1 / sqrt(1 - (r/R_l)^2 sin^2 z)
// (the layer's slant thickness over its vertical one). The atmosphere layer applies each
// ray's transmittance; nothing is drawn where the ray meets the ground.
// Output: (R, G, B, scotopic) cd/m^2, or the 4 wavelengths of a spectral basis; drawn added.
#include "common/camera.glsl"

uniform vec4 u_airglow_zenith;   // channels of the zenith airglow (cd/m^2 per channel)
uniform float u_radius_ratio_sq; // (r_observer / r_layer)^2, < 1
uniform float u_dip_sin;         // sin of the ground horizon's dip below the horizontal
out vec4 frag;

// The van Rhijn factor at the cosine of the zenith angle: 1 / sqrt(1 - (r/R_l)^2 sin^2 z).
// twin: skydome.night.airglow.van_rhijn(np.arccos(cos_z)) cos_z=-1..1 CAMERA_MODEL=0
float van_rhijn(float cos_z) {
    return inversesqrt(1.0 - u_radius_ratio_sq * max(1.0 - cos_z * cos_z, 0.0));
}

void main() {
    frag = vec4(0.0);
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) return;
    if (dir.z < -u_dip_sin) return;  // the ground
    frag = u_airglow_zenith * van_rhijn(dir.z);
}
