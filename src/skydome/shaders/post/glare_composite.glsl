// Glare, the last pass (skydome.display.glare): every texel of the frame with the halo added
// (post/glare_halo.glsl: the frame's core share plus the pyramid's sum at half resolution
// enlarged by the cubic B-spline). All four channels (RGB in cd/m^2, scotopic) alike.
#include "post/glare_halo.glsl"
uniform sampler2D u_src;            // RGBA32F, the frame, GL rows
out vec4 frag;

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    frag = add_glare_halo(texelFetch(u_src, texel, 0), texel);
}
