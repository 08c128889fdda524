// Night vision, step 0: the scene's photopic and scotopic log luminances on a fixed
// power-of-two grid of samples (the grid and the sampling of post/log_luminance.glsl), for
// skydome.display.gpu_exposure.GridMean to average: (ln(delta + L_p), ln(delta + L_s), 1)
// where the pixel holds light, (0, 0, 0) where it holds none. The mean's ratio g/b - r/b is
// the log of the adaptation field's S/P ratio (geometric mean over the frame), which CIE 191:2010's MES2
// needs besides the photopic adaptation luminance. Twin: skydome/reference/night_vision.py.
uniform sampler2D u_hdr;            // RGBA32F frame, GL rows: R, G, B (cd/m^2), A scotopic
uniform vec3 u_luminance_weights;   // SRGB_LUMINANCE
uniform float u_delta;              // cd/m^2, guards ln(0)
#ifdef GLARE_HALO
#include "post/glare_halo.glsl"
#endif
out vec4 frag;

void main() {
    ivec2 size = textureSize(u_hdr, 0);
    vec2 grid = vec2(float(GRID_W), float(GRID_H));
    ivec2 src = min(ivec2(gl_FragCoord.xy * vec2(size) / grid), size - 1);
    vec4 c = texelFetch(u_hdr, src, 0);
#ifdef GLARE_HALO
    // the frame with its glare, as post/glare_composite.glsl writes it (the tone map adds
    // it then: skydome.display.glare.GlareHalo)
    c = add_glare_halo(c, src);
#endif
    float lp = dot(c.rgb, u_luminance_weights);
    float ls = c.a;
    frag = (lp > 0.0 || ls > 0.0)
        ? vec4(log(u_delta + max(lp, 0.0)), log(u_delta + max(ls, 0.0)), 1.0, 0.0)
        : vec4(0.0);
}
