// Night vision, a wide acuity blur: one halving of the pyramid on which it runs. Texel j of
// the coarser level weighs texels 2j - 1 .. 2j + 2 of the finer one by [1, 3, 3, 1] / 8 on each
// axis (edges clamped): the linear B-spline, which keeps a point's centroid for either phase
// and adds 0.75 texel^2 of variance, accounted for by skydome.display.night_vision.blur_plan.
// Twin: skydome/reference/night_vision.py (downsample).
uniform sampler2D u_src;            // RGBA32F, the finer level
out vec4 frag;

void main() {
    ivec2 q = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(u_src, 0) - 1;
    const float w[4] = float[4](0.125, 0.375, 0.375, 0.125);
    vec4 sum = vec4(0.0);
    for (int j = 0; j < 4; ++j) {
        int y = clamp(2 * q.y - 1 + j, 0, last.y);
        vec4 row = vec4(0.0);
        for (int i = 0; i < 4; ++i) {
            row += w[i] * texelFetch(u_src, ivec2(clamp(2 * q.x - 1 + i, 0, last.x), y), 0);
        }
        sum += w[j] * row;
    }
    frag = sum;
}
