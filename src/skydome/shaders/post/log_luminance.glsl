// Exposure pass, step 1: the log luminance of an HDR frame on a fixed power-of-two grid of
// samples (u_grid texels spread evenly over the frame), for a mipmap chain to average:
// (ln(delta + L), 1) where L > 0, (0, 0) where the frame holds no light (outside a
// fisheye's circle, empty space), as skydome.display.exposure.log_average_luminance ignores
// those pixels. The mean of the two channels' ratio is Reinhard et al. 2002's eq. 1.
uniform sampler2D u_hdr;            // RGBA32F frame, GL rows
uniform vec3 u_luminance_weights;   // SRGB_LUMINANCE
uniform float u_delta;              // cd/m^2, guards ln(0)
out vec4 frag;

void main() {
    ivec2 size = textureSize(u_hdr, 0);
    vec2 grid = vec2(float(GRID_W), float(GRID_H));
    ivec2 src = min(ivec2((gl_FragCoord.xy) * vec2(size) / grid), size - 1);
    float lum = dot(texelFetch(u_hdr, src, 0).rgb, u_luminance_weights);
    frag = lum > 0.0 ? vec4(log(u_delta + lum), 1.0, 0.0, 0.0) : vec4(0.0);
}
