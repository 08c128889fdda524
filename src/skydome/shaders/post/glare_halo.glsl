// The glare's last step where a pass reads the frame (skydome.display.glare.GlareHalo, with
// GLARE_HALO): the frame's core share plus the halo, the pyramid's sum at half the frame's
// size enlarged by the cubic B-spline, what post/glare_composite.glsl writes at that texel.
#include "post/glare_upsample.glsl"
uniform sampler2D u_glare_halo;     // RGBA32F, half the frame's size (LINEAR, clamped)
uniform float u_glare_core;

vec4 add_glare_halo(vec4 frame_texel, ivec2 texel) {
    return u_glare_core * frame_texel + glare_enlarge(u_glare_halo, vec2(texel) + 0.5);
}
