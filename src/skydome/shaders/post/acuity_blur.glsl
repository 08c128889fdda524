// Night vision, step 2: loss of acuity, one direction of a separable Gaussian blur (run twice,
// u_direction = (1, 0) then (0, 1)). Twin: skydome/reference/night_vision.py (acuity_blur).
//
// The width follows Ferwerda et al. 1996's fit of Shaler's 1937 acuity data,
// R(L) = 17.25 atan(1.4 log10 L + 0.35) + 25.72 cycles/deg, as the Gaussian whose transfer
// function is 1/2 at R: sigma(L) = sqrt(ln 2 / 2) / (pi R) deg; the blur added is
// sqrt(sigma(L)^2 - sigma(5 cd/m^2)^2) (Gaussian widths add in quadrature; none in photopic
// vision), in pixels of u_pixel_angle_deg. Below NV_MIN_SIGMA_PX the texel is copied as is.
// Taps to 3 sigma (at most NV_MAX_RADIUS), weights normalised to sum 1 and edges clamped, so a
// flat field stays flat.
#include "post/night_adaptation.glsl"

uniform sampler2D u_hdr;            // RGBA32F, GL rows
uniform vec2 u_direction;           // (1, 0) or (0, 1)
uniform float u_pixel_angle_deg;    // angular size of a pixel at the centre, deg
out vec4 frag;

const float PI = 3.141592653589793;

float acuity_cycles_per_deg(float l) {
    return 17.25 * atan(1.4 * log(max(l, 1e-30)) * 0.434294481903252 + 0.35) + 25.72;
}

float blur_sigma_deg(float l) {
    float k = sqrt(log(2.0) / 2.0) / PI;
    float s = k / max(acuity_cycles_per_deg(l), 1e-3);
    float s_ref = k / acuity_cycles_per_deg(NV_PHOTOPIC_LIMIT);
    return sqrt(max(s * s - s_ref * s_ref, 0.0));
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    Adaptation a = adaptation_state();
    float sigma = a.m >= 1.0 ? 0.0 : blur_sigma_deg(a.lp) / u_pixel_angle_deg;
    if (!(sigma >= NV_MIN_SIGMA_PX)) { frag = texelFetch(u_hdr, p, 0); return; }
    int radius = min(int(ceil(3.0 * sigma)), NV_MAX_RADIUS);
    ivec2 size = textureSize(u_hdr, 0);
    ivec2 dir = ivec2(u_direction);
    float inv = -0.5 / (sigma * sigma);
    vec4 sum = texelFetch(u_hdr, p, 0);
    float wsum = 1.0;
    for (int i = 1; i <= radius; ++i) {
        float w = exp(float(i * i) * inv);
        sum += w * (texelFetch(u_hdr, clamp(p + i * dir, ivec2(0), size - 1), 0)
                    + texelFetch(u_hdr, clamp(p - i * dir, ivec2(0), size - 1), 0));
        wsum += 2.0 * w;
    }
    frag = sum / wsum;
}
