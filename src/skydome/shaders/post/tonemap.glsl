// Tone mapping pass: HDR frame (R, G, B in cd/m^2, A scotopic) -> sRGB-encoded display colour.
// Twin of skydome/display/tonemap.py (the float64 reference); the operator is chosen by
// u_operator = ToneMapOperator.gl_id, so one program serves all operators.
//
// Define TONEMAP_QUANTIZE 1 to snap the output to 8-bit code values in the shader, so that an
// RGBA8 target stores round(255 v) whichever float -> unorm rounding the driver uses.
#include "common/srgb.glsl"

#ifndef TONEMAP_QUANTIZE
#define TONEMAP_QUANTIZE 0
#endif
#if !defined(FILMIC_INPUT_CAP) || !defined(FILMIC_DESATURATION_STOPS)
#error "define FILMIC_INPUT_CAP and FILMIC_DESATURATION_STOPS (skydome.display.tonemap)"
#endif

uniform sampler2D u_hdr;            // RGBA32F, GL rows (row 0 = bottom of the image)
uniform vec2 u_viewport;            // target size in pixels
#ifdef TONEMAP_OPERATOR
// One operator compiled in (a CPU rasterizer runs every branch of a per-pixel if chain,
// uniform or not: five operators cost five): u_operator is then unused.
#define OPERATOR TONEMAP_OPERATOR
#else
uniform int u_operator;             // 0 linear, 1 exponential, 2 reinhard, 3 hvs, 4 filmic
#define OPERATOR u_operator
#endif
uniform float u_exposure;           // exposure scale, m^2/cd (skydome.display.exposure)
uniform vec3 u_luminance_weights;   // SRGB_LUMINANCE (seed 001 eq. 5.3)
uniform float u_exp_k;              // exponential: T_s of seed 000 eq. 4.14
uniform float u_inv_white_sq;       // reinhard: 1 / L_white^2 (0 for L_white = inf)
uniform float u_hvs_a;              // hvs: a, b of seed 003 eq. 7
uniform float u_hvs_b;
uniform float u_hvs_x_scale;        // hvs: I_max / white (exposed luminance -> x)
uniform float u_filmic_pre_scale;   // filmic: input scale before the fit
#ifdef MESOPIC_BLEND
// The eye's colours (skydome.display.night_vision.MesopicBlend), applied here instead of by
// post/night_vision.glsl's pass over the frame.
#include "post/mesopic_blend.glsl"
#endif
#ifdef GLARE_HALO
// The glare's halo, added here instead of by post/glare_composite.glsl's pass over the whole
// frame (skydome.display.glare.GlareHalo).
#include "post/glare_halo.glsl"
#endif
#ifdef AUTO_EXPOSURE
// Automatic exposure on the GPU (skydome.display.gpu_exposure): u_exposure is then
// key * 2^compensation, divided here by the frame's log-average luminance, read from the
// mean of the log-luminance grid (GridMean: one texel, level 0) (sum of w ln(delta + L), sum of w).
uniform sampler2D u_log_luminance;
uniform float u_log_luminance_level;
uniform float u_delta;
float exposure_scale() {
    vec2 s = textureLod(u_log_luminance, vec2(0.5), u_log_luminance_level).rg;
    float average = s.g > 0.0 ? max(exp(s.r / s.g) - u_delta, u_delta) : u_delta;
    return u_exposure / average;
}
#else
float exposure_scale() { return u_exposure; }
#endif

out vec4 frag;

const float INV_LN10 = 0.434294481903252;

// C_d = (C / L) * L_d (seed 001 eq. 5.4); C / L <= 1 / min weight, so no overflow.
vec3 scale_by_luminance(vec3 c, float lum, float lum_display) {
    return lum > 0.0 ? c / lum * lum_display : vec3(0.0);
}

// Seed 000 eq. 4.14, per channel.
vec3 tm_exponential(vec3 c) { return 1.0 - exp(-u_exp_k * c); }

// Seed 001 eq. 5.2 as a ratio L_d / L = (1 + L / Lw^2) / (1 + L): no L*L overflow in float32.
vec3 tm_reinhard(vec3 c) {
    float lum = dot(c, u_luminance_weights);
    return c * ((1.0 + lum * u_inv_white_sq) / (1.0 + lum));
}

// Seed 003 eq. 7 / 255 on x = I_max L / white; its output is a display code value.
vec3 tm_hvs(vec3 c) {
    float lum = dot(c, u_luminance_weights);
    float x = u_hvs_x_scale * lum;
    float f = x >= u_hvs_a + 1.0 ? log(x - u_hvs_a) * INV_LN10 + u_hvs_b
                                 : -log(u_hvs_a + 2.0 - x) * INV_LN10 + u_hvs_b;
    return scale_by_luminance(c, lum, srgb_decode(clamp(f, 0.0, 1.0)));
}

// Narkowicz 2016, ACES filmic fit (not clipped).
// twin: skydome.display.tonemap.aces_narkowicz(x) x=0..64 FILMIC_INPUT_CAP=64.0 FILMIC_DESATURATION_STOPS=3.0
float aces_narkowicz(float x) { return (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14); }

// The fit on n = max(R, G, B), colour scaled by f(n) / n (hue preserved), then above n = 1
// blended towards the grey f(n) with t = smoothstep(log2(n) / 3): highlights go to white.
// FILMIC_INPUT_CAP (f(n) = 1 from n = 7.24 on; keeps x^2 finite in float32) and
// FILMIC_DESATURATION_STOPS are defined by skydome.display.gpu_tonemap from tonemap.py.
vec3 tm_filmic(vec3 c) {
    vec3 x = c * u_filmic_pre_scale;
    float n = max(x.r, max(x.g, x.b));
    if (n <= 0.0) return vec3(0.0);
    float n_display = clamp(aces_narkowicz(min(n, FILMIC_INPUT_CAP)), 0.0, 1.0);
    float u = clamp(log2(max(n, 1.0)) / FILMIC_DESATURATION_STOPS, 0.0, 1.0);
    float t = u * u * (3.0 - 2.0 * u);
    float white = t * n_display;
    return x * ((n_display - white) / n) + white;  // f(n) (r + t (1 - r)), r = x / n
}

// The operator OPERATOR on exposed linear RGB, clamped to [0, 1] (display-linear).
// twin: skydome.display.tonemap.tonemap_linear(exposed, name, 1.0) exposed=-0.5..12
vec3 tonemap_display_linear(vec3 exposed) {
    vec3 c = max(exposed, vec3(0.0));  // negative (out-of-gamut) components -> 0
    vec3 d;
    if (OPERATOR == 1) d = tm_exponential(c);
    else if (OPERATOR == 2) d = tm_reinhard(c);
    else if (OPERATOR == 3) d = tm_hvs(c);
    else if (OPERATOR == 4) d = tm_filmic(c);
    else d = c;
    return clamp(d, 0.0, 1.0);
}

void main() {
    // Nearest source texel; exact (no filtering) when target and source have the same size.
    ivec2 size = textureSize(u_hdr, 0);
    ivec2 src = min(ivec2(gl_FragCoord.xy * vec2(size) / u_viewport), size - 1);
    vec4 texel = texelFetch(u_hdr, src, 0);
#ifdef GLARE_HALO
    // The glare's last step here, as post/glare_composite.glsl writes it at texel src.
    texel = add_glare_halo(texel, src);
#endif
#ifdef MESOPIC_BLEND
    // The eye's colours here, as post/night_vision.glsl writes them (no blur, no noise).
    vec3 hdr = mesopic_blend(texel);
#else
    vec3 hdr = texel.rgb;
#endif
    vec3 v = srgb_encode(tonemap_display_linear(hdr * exposure_scale()));
#if TONEMAP_QUANTIZE
    // round(255 v), stored as (k + 0.25) / 255: both round-to-nearest and truncating
    // float -> unorm8 conversions then give k.
    v = (floor(v * 255.0 + 0.5) + 0.25) / 255.0;
#endif
    frag = vec4(v, 1.0);
}
