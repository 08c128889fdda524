// Night vision, step 1: mesopic blend of the photopic colour and the scotopic luminance
// (CIE 191:2010 MES2 weights). Twin: skydome/reference/night_vision.py (mesopic_blend).
//
// With w_p = m / (m + (1 - m) V'(555)) and w_s = 1 - w_p each pixel's mesopic luminance is
// L_mes = w_p L_p + w_s L_s (the standard's formula, applied per pixel with the global m of
// the adaptation field). The photopic share keeps the pixel's colour; the scotopic share is
// drawn in one desaturated blue grey C_b of unit luminance (the blue shift of Thompson,
// Shirley & Ferwerda 2002, JGT 7(1)), so out = w_p RGB + w_s L_s C_b has luminance L_mes.
// m = 1: the texel is copied unchanged (exact identity in photopic vision).
#include "post/night_adaptation.glsl"

uniform sampler2D u_hdr;            // RGBA32F, GL rows
uniform vec3 u_blue_grey;           // C_b, linear sRGB with luminance 1
out vec4 frag;

void main() {
    vec4 c = texelFetch(u_hdr, ivec2(gl_FragCoord.xy), 0);
    Adaptation a = adaptation_state();
    if (a.m >= 1.0) { frag = c; return; }
    float wp = a.m / (a.m + (1.0 - a.m) * NV_V_PRIME_555);
    frag = vec4(wp * c.rgb + (1.0 - wp) * c.a * u_blue_grey, c.a);
}
