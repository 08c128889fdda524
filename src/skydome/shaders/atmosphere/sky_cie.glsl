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

// The angle (rad, 0..pi) whose sine and cosine are proportional to s >= 0 and c, to a few
// float32 ulps: the ratio of the smaller to the larger brought within tan(pi / 12) by
// atan(t) = pi / 6 + atan((t - 1 / sqrt 3) / (1 + t / sqrt 3)), then atan's odd series to
// t^15 (the rest < 1e-10). (A CPU rasterizer's atan errs by ~1e-6 rad, which the
// indicatrix's steep exp(d chi) near the Sun turns into ~4e-6 of the luminance.)
// twin: numpy.arctan2(s, c) s=0..2 c=-2..2
float angle_between(float s, float c) {
    float big = max(s, abs(c)), small = min(s, abs(c));
    float t = big > 0.0 ? small / big : 0.0;
    const float INV_SQRT3 = 0.57735026918962576;
    float offset = 0.0;
    if (t > 0.26794919243112270) {
        t = (t - INV_SQRT3) / (1.0 + t * INV_SQRT3);
        offset = PI / 6.0;
    }
    float t2 = t * t;
    float a = offset + t * (1.0 - t2 * (1.0 / 3.0 - t2 * (1.0 / 5.0 - t2 * (1.0 / 7.0 - t2
              * (1.0 / 9.0 - t2 * (1.0 / 11.0 - t2 * (1.0 / 13.0 - t2 * (1.0 / 15.0))))))));
    if (s > abs(c)) a = 0.5 * PI - a;
    return c < 0.0 ? PI - a : a;
}

// f(chi) for an angle chi from the Sun of cosine cos_chi.
float cie_indicatrix(float chi, float cos_chi) {
    float c = cos_chi;
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
    // the angle from the Sun (from its sine and cosine: acos loses digits near the Sun)
    float chi = angle_between(length(cross(dir, u_cie_sun)), dot(dir, u_cie_sun));
    frag = u_cie_zenith * (cie_indicatrix(chi, dot(dir, u_cie_sun)) * cie_gradation(dir.z));
}
