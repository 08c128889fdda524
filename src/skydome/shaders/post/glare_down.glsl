// Glare, one halving of the pyramid (skydome.display.glare): texel j of the coarser level
// weighs texels 2j - 1 .. 2j + 2 of the finer one by [1, 3, 3, 1] / 8 on each axis (the
// linear B-spline of post/night_downsample.glsl, 0.75 texel^2 of variance), here in four
// bilinear look-ups: the pair (2j - 1, 2j) is one look-up at 2j - 0.25 (weights 1/4, 3/4 of
// half the sum), the pair (2j + 1, 2j + 2) one at 2j + 1.25. The source is sampled with
// bilinear filtering and clamped edges (the fractions 1/4, 3/4 are exact in 8 bits).
uniform sampler2D u_src;            // RGBA32F, the finer level (LINEAR, CLAMP_TO_EDGE)
out vec4 frag;

void main() {
    vec2 inv = 1.0 / vec2(textureSize(u_src, 0));
    vec2 q2 = 2.0 * floor(gl_FragCoord.xy);
    vec2 a = (q2 + 0.25) * inv;  // centre of texel 2j - 1 plus 3/4: (2j - 0.25 + 0.5) / size
    vec2 b = (q2 + 1.75) * inv;  // (2j + 1.25 + 0.5) / size
    frag = 0.25 * (texture(u_src, a) + texture(u_src, vec2(b.x, a.y))
                   + texture(u_src, vec2(a.x, b.y)) + texture(u_src, b));
}
