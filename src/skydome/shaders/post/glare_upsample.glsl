// Glare: the coarser level enlarged twice over, by the cubic B-spline (C2: no squares
// around a bright point, as a bilinear enlargement leaves), in four bilinear look-ups
// (Sigg & Hadwiger, GPU Gems 2, ch. 20). Texel q of the finer level lies at (q + 0.5) / 2 -
// 0.5 texels of the coarser one. Adds 4/3 finer texel^2 of variance per axis
// (skydome.display.glare.level_variance_px2). The coarser texture: LINEAR, CLAMP_TO_EDGE.
vec4 glare_enlarge(sampler2D coarse, vec2 frag_xy) {
    vec2 size = vec2(textureSize(coarse, 0));
    vec2 c = (floor(frag_xy) + 0.5) * 0.5 - 0.5;
    vec2 m = floor(c);
    vec2 f = c - m;
    vec2 f2 = f * f;
    vec2 f3 = f2 * f;
    vec2 w0 = (1.0 - 3.0 * f + 3.0 * f2 - f3) / 6.0;
    vec2 w1 = (4.0 - 6.0 * f2 + 3.0 * f3) / 6.0;
    vec2 w2 = (1.0 + 3.0 * f + 3.0 * f2 - 3.0 * f3) / 6.0;
    vec2 w3 = f3 / 6.0;
    vec2 g0 = w0 + w1;
    vec2 g1 = w2 + w3;
    vec2 h0 = (m - 1.0 + w1 / g0 + 0.5) / size;
    vec2 h1 = (m + 1.0 + w3 / g1 + 0.5) / size;
    return g0.y * (g0.x * texture(coarse, h0) + g1.x * texture(coarse, vec2(h1.x, h0.y)))
         + g1.y * (g0.x * texture(coarse, vec2(h0.x, h1.y)) + g1.x * texture(coarse, h1));
}
