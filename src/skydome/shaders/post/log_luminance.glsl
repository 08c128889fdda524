// Exposure pass, step 1: the log luminance of an HDR frame on a fixed power-of-two grid of
// samples (u_grid texels spread evenly over the frame), for GridMean (post/grid_mean.glsl)
// to average: (w ln(delta + L), w) where L > 0, (0, 0) where the frame holds no light (outside a
// fisheye's circle, empty space), as skydome.display.exposure.log_average_luminance ignores
// those pixels. The mean of the two channels' ratio is Reinhard et al. 2002's eq. 1.
// The weight w is the metering's (skydome.display.exposure.metering_weights, its twin):
// METERING 0 every sample 1 (average, eye), 1 a Gaussian of CENTER_SIGMA_FRACTION of the
// frame's height about its centre (center), 2 a central disc of SPOT_AREA_FRACTION of the
// frame's area (spot); at the centre of the frame's pixel the sample reads.
#ifndef METERING
#define METERING 0
#endif
uniform sampler2D u_hdr;            // RGBA32F frame, GL rows
uniform vec3 u_luminance_weights;   // SRGB_LUMINANCE
uniform float u_delta;              // cd/m^2, guards ln(0)
out vec4 frag;

void main() {
    ivec2 size = textureSize(u_hdr, 0);
    vec2 grid = vec2(float(GRID_W), float(GRID_H));
    ivec2 src = min(ivec2((gl_FragCoord.xy) * vec2(size) / grid), size - 1);
    float lum = dot(texelFetch(u_hdr, src, 0).rgb, u_luminance_weights);
    float w = 1.0;
#if METERING != 0
    vec2 d = vec2(src) + 0.5 - 0.5 * vec2(size);
    float d2 = dot(d, d);
#if METERING == 1
    float sigma = CENTER_SIGMA_FRACTION * float(size.y);
    w = exp(-d2 / (2.0 * sigma * sigma));
#else
    w = d2 <= SPOT_AREA_FRACTION * float(size.x) * float(size.y) / 3.141592653589793 ? 1.0 : 0.0;
#endif
#endif
    frag = lum > 0.0 && w > 0.0 ? vec4(w * log(u_delta + lum), w, 0.0, 0.0) : vec4(0.0);
}
