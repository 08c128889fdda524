// Night vision, the final pass: the mesopic blend of the photopic colour and the scotopic
// luminance (CIE 191:2010 MES2 weights) and the temporal noise, on the (blurred) frame.
// Twin: skydome/reference/night_vision.py (mesopic_blend, add_noise).
//
// With w_p = m / (m + (1 - m) V'(555)) (u_wp, from m computed on the CPU) each pixel's
// mesopic luminance is L_mes = w_p L_p + (1 - w_p) L_s. The photopic share keeps the pixel's
// colour; the scotopic share is drawn in one desaturated blue grey C_b of unit luminance (the
// blue shift of Thompson, Shirley & Ferwerda 2002, JGT 7(1)): out = w_p RGB + (1 - w_p) L_s
// C_b. The blend is linear with the same weights everywhere, so blending after the acuity
// blur equals blending before it. NV_SCOTOPIC_ONLY (m = 0): out = L_s C_b.
// The source (NV_SOURCE): 0 the frame or its blur across, with NV_VRADIUS > 0 taps down taken
// here (weights u_weights, as post/acuity_blur.glsl); 1 the packed scotopic blur of
// post/night_scotopic_blur.glsl (pixel x in component x mod 4 of texel x / 4); 2 a level 2^-k
// of the pyramid, enlarged bilinearly (u_uv_scale = 1 / (2^k size_k)).
#include "post/night_noise.glsl"

#ifndef NV_VRADIUS
#define NV_VRADIUS 0
#endif

uniform sampler2D u_src;            // RGBA32F, GL rows
#include "post/mesopic_blend.glsl"
#if NV_VRADIUS > 0
uniform float u_weights[NV_VRADIUS + 1];
#endif
#if NV_SOURCE == 2
uniform vec2 u_uv_scale;
#endif
out vec4 frag;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
#if NV_SOURCE == 0 && NV_VRADIUS > 0
    int last = textureSize(u_src, 0).y - 1;
    vec4 c = u_weights[0] * texelFetch(u_src, p, 0);
    for (int i = 1; i <= NV_VRADIUS; ++i) {
        c += u_weights[i] * (texelFetch(u_src, ivec2(p.x, min(p.y + i, last)), 0)
                             + texelFetch(u_src, ivec2(p.x, max(p.y - i, 0)), 0));
    }
#elif NV_SOURCE == 0
    vec4 c = texelFetch(u_src, p, 0);
#elif NV_SOURCE == 1
    vec4 t = texelFetch(u_src, ivec2(p.x >> 2, p.y), 0);
    vec4 c = vec4(0.0, 0.0, 0.0, t[p.x & 3]);
#else
    // Bilinear by hand (four fetches, float weights): hardware filtering may keep only 8 bits
    // of the fraction.
    ivec2 last = textureSize(u_src, 0) - 1;
    vec2 t = gl_FragCoord.xy * u_uv_scale * vec2(last + 1) - 0.5;
    vec2 j = floor(t);
    vec2 fr = t - j;
    ivec2 j0 = clamp(ivec2(j), ivec2(0), last);
    ivec2 j1 = clamp(ivec2(j) + 1, ivec2(0), last);
    vec4 c = mix(mix(texelFetch(u_src, j0, 0), texelFetch(u_src, ivec2(j1.x, j0.y), 0), fr.x),
                 mix(texelFetch(u_src, ivec2(j0.x, j1.y), 0), texelFetch(u_src, j1, 0), fr.x),
                 fr.y);
#endif
#if NV_SCOTOPIC_ONLY
    vec3 rgb = c.a * u_blue_grey;
#else
    vec3 rgb = mesopic_blend(c);
#endif
#if NV_NOISE
    rgb *= 1.0 + night_noise(p, c.a);
#endif
    frag = vec4(rgb, c.a);
}
