// Glare, the last pass (skydome.display.glare): the frame's core share (u_weight = 1 - the
// halo's share) plus the halo, the pyramid's sum at level 1 enlarged by the cubic B-spline
// (post/glare_upsample.glsl). All four channels (RGB in cd/m^2, scotopic) alike.
#include "post/glare_upsample.glsl"
uniform sampler2D u_src;            // RGBA32F, the frame, GL rows
uniform sampler2D u_coarse;         // RGBA32F, the halo at half resolution
uniform float u_weight;
out vec4 frag;

void main() {
    frag = u_weight * texelFetch(u_src, ivec2(gl_FragCoord.xy), 0)
         + glare_enlarge(u_coarse, gl_FragCoord.xy);
}
