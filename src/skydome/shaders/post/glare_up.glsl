// Glare, climbing the pyramid (skydome.display.glare): this level's share of the halo,
// u_weight times its own image (u_src, the frame halved k times), plus the sum of the coarser
// levels (u_coarse) enlarged by the cubic B-spline (post/glare_upsample.glsl); u_coarse_on is 0
// at the coarsest level, which has nothing coarser.
#include "post/glare_upsample.glsl"
uniform sampler2D u_src;            // RGBA32F, this level
uniform sampler2D u_coarse;         // RGBA32F, the coarser levels' sum (LINEAR, clamped)
uniform float u_weight;
uniform float u_coarse_on;
out vec4 frag;

void main() {
    vec4 c = u_weight * texelFetch(u_src, ivec2(gl_FragCoord.xy), 0);
    if (u_coarse_on > 0.0) c += glare_enlarge(u_coarse, gl_FragCoord.xy);
    frag = c;
}
