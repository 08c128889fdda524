// Night vision, loss of acuity: one axis of a separable Gaussian blur (NV_AXIS 0: across,
// 1: down), NV_RADIUS taps on each side with the normalised weights u_weights[0..r] of
// skydome.display.night_vision.gaussian_weights (Ferwerda et al. 1996's acuity as the
// Gaussian whose transfer function is 1/2 at the acuity limit; width and taps chosen on the
// CPU). Edges clamped, so a flat field stays flat. Used on the full frame, on the packed
// scotopic texture (down only) and on the levels of the pyramid.
// Twin: skydome/reference/night_vision.py (acuity_blur).
uniform sampler2D u_src;            // RGBA32F
uniform float u_weights[NV_RADIUS + 1];
out vec4 frag;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(u_src, 0) - 1;
    vec4 sum = u_weights[0] * texelFetch(u_src, p, 0);
    for (int i = 1; i <= NV_RADIUS; ++i) {
#if NV_AXIS == 0
        vec4 a = texelFetch(u_src, ivec2(min(p.x + i, last.x), p.y), 0);
        vec4 b = texelFetch(u_src, ivec2(max(p.x - i, 0), p.y), 0);
#else
        vec4 a = texelFetch(u_src, ivec2(p.x, min(p.y + i, last.y)), 0);
        vec4 b = texelFetch(u_src, ivec2(p.x, max(p.y - i, 0)), 0);
#endif
        sum += u_weights[i] * (a + b);
    }
    frag = sum;
}
