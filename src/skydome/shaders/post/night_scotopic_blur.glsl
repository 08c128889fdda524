// Night vision, loss of acuity at m = 0 (scotopic vision: the displayed image is the scotopic
// channel alone, in the blue grey): the blur across of the scotopic channel (A) of the frame,
// four neighbouring pixels packed in one texel: texel (X, y) holds pixels x = 4X .. 4X + 3 of
// row y. NV_RADIUS taps on each side, weights u_weights[0..r] as post/acuity_blur.glsl, edges
// clamped. Each input texel is fetched once for the four outputs (4 + 2r fetches for 4 px
// instead of 4 (2r + 1)); post/acuity_blur.glsl then blurs the packed texture down.
// Twin: skydome/reference/night_vision.py (acuity_blur on channel 3).
uniform sampler2D u_src;            // RGBA32F frame, GL rows
uniform float u_weights[NV_RADIUS + 1];
out vec4 frag;

void main() {
    ivec2 q = ivec2(gl_FragCoord.xy);
    int last = textureSize(u_src, 0).x - 1;
    int x0 = 4 * q.x - NV_RADIUS;
    float v[4 + 2 * NV_RADIUS];
    for (int i = 0; i < 4 + 2 * NV_RADIUS; ++i) {
        v[i] = texelFetch(u_src, ivec2(clamp(x0 + i, 0, last), q.y), 0).a;
    }
    vec4 sum;
    for (int j = 0; j < 4; ++j) {
        float s = u_weights[0] * v[j + NV_RADIUS];
        for (int i = 1; i <= NV_RADIUS; ++i) {
            s += u_weights[i] * (v[j + NV_RADIUS + i] + v[j + NV_RADIUS - i]);
        }
        sum[j] = s;
    }
    frag = sum;
}
