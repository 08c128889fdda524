// The CIE standard general sky (ISO 15469 / CIE S 011; float64 twin:
// skydome.atmosphere.cie.relative_luminance): a sky element at zenith angle Z and angular
// distance chi from the Sun has L = L_z f(chi) phi(Z) / (f(Z_s) phi(0)), with the gradation
// phi(Z) = 1 + a exp(b / cos Z) and the indicatrix f(chi) = 1 + c (exp(d chi) -
// exp(d pi / 2)) + e cos^2 chi. Below the horizon: the ground, a uniform luminance.
// Output: (R, G, B, scotopic) cd/m^2, or the 4 wavelengths of a spectral basis.
#include "common/camera.glsl"

uniform vec2 u_cie_gradation;   // (a, b)
uniform vec3 u_cie_indicatrix;  // (c, d in 1/rad, e)
uniform vec3 u_cie_sun;         // the Sun's unit direction (east, north, up)
uniform vec4 u_cie_zenith;      // channels of L_z / (f(Z_s) phi(0)) (cd/m^2 per channel)
uniform vec4 u_cie_ground;      // channels of the ground's luminance
out vec4 frag;

float cie_gradation(float cos_z) {
    return cos_z > 0.0 ? 1.0 + u_cie_gradation.x * exp(u_cie_gradation.y / cos_z) : 1.0;
}

float cie_indicatrix(float chi) {
    float c = cos(chi);
    return 1.0 + u_cie_indicatrix.x * (exp(u_cie_indicatrix.y * chi)
                                       - exp(u_cie_indicatrix.y * 0.5 * PI))
           + u_cie_indicatrix.z * c * c;
}

void main() {
    frag = vec4(0.0);
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) return;
    if (dir.z < 0.0) {
        frag = u_cie_ground;
        return;
    }
    // the angle from the Sun by atan2 (acos loses digits near the Sun)
    float chi = atan(length(cross(dir, u_cie_sun)), dot(dir, u_cie_sun));
    frag = u_cie_zenith * (cie_indicatrix(chi) * cie_gradation(dir.z));
}
