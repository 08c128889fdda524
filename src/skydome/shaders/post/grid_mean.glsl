// The mean of a block of BLOCK_W x BLOCK_H texels of a sample grid (skydome.display.
// gpu_exposure.GridMean): texel (i, j) of the output averages the source's texels
// (BLOCK_W i + x, BLOCK_H j + y). Two such passes take the 256 x 128 log-luminance grids to
// their 1 x 1 mean, as their mipmap chain did: on Mesa's llvmpipe glGenerateMipmap costs
// 1.5-2.5 ms a frame in a running pipeline, these two passes a fifth of it.
uniform sampler2D u_src;            // RGBA32F sample grid (NEAREST)
out vec4 frag;

void main() {
    ivec2 origin = ivec2(gl_FragCoord.xy) * ivec2(BLOCK_W, BLOCK_H);
    vec4 sum = vec4(0.0);
    for (int y = 0; y < BLOCK_H; ++y) {
        vec4 row = vec4(0.0);
        for (int x = 0; x < BLOCK_W; ++x) row += texelFetch(u_src, origin + ivec2(x, y), 0);
        sum += row;
    }
    frag = sum / float(BLOCK_W * BLOCK_H);
}
