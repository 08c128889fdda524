// Point sources (stars, planets), fragment stage: each pixel of a source's quad (see
// celestial/point_sources_vs.glsl) gets the fraction of the source's light that a Gaussian
// PSF puts on it: the PSF's integral over the pixel (products of differences of the normal
// distribution function along x and y) over its integral over the whole quad, so that the
// weights of a quad sum to 1 exactly (the differences telescope). The radiance is the
// illuminance times the weight over the pixel's own solid angle: the summed flux
// (radiance x solid angle) is the source's illuminance at any resolution and field of view.
// Pixels inside an occluding disk (the Moon, in front of the stars) get nothing.
// Output (R, G, B, scotopic) cd/m^2, or the basis's 4 wavelengths; drawn added.
#include "common/camera_project.glsl"

#ifndef MAX_OCCLUDERS
#define MAX_OCCLUDERS 4
#endif

uniform vec4 u_occluders[MAX_OCCLUDERS];  // xyz: apparent unit ENU centre, w: cos(radius)
uniform int u_num_occluders;

flat in vec4 v_channels;
flat in vec2 v_centre;
flat in vec2 v_sigma;
flat in vec2 v_lo;
flat in vec2 v_hi;
flat in int v_face;
out vec4 frag;

// erfc(x) for x >= 0: Abramowitz & Stegun (1964) 7.1.26 (Hastings' approximation),
// erf(x) = 1 - (a1 t + ... + a5 t^5) exp(-x^2), t = 1 / (1 + p x), |error| <= 1.5e-7.
float erfc_pos(float x) {
    float t = 1.0 / (1.0 + 0.3275911 * x);
    float poly = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741
               + t * (-1.453152027 + t * 1.061405429))));
    return poly * exp(-x * x);
}

// P(a < X < b) for a standard normal X. Written as a difference of the same function at both
// ends (so that the pixels' values telescope to the quad's), from the tail that keeps digits:
// Phi(u) = 1 - erfc(u / sqrt 2) / 2 for u >= 0, erfc(-u / sqrt 2) / 2 for u < 0.
float normal_upper(float u) {  // 1 - Phi(u) for u >= 0
    return 0.5 * erfc_pos(u * 0.70710678);
}
float normal_between(float a, float b) {
    if (a >= 0.0) return normal_upper(a) - normal_upper(b);
    if (b <= 0.0) return normal_upper(-b) - normal_upper(-a);
    return 1.0 - normal_upper(-a) - normal_upper(b);
}

void main() {
    frag = vec4(0.0);
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) return;  // the pixel sees nothing
#if CAMERA_MODEL == 3
    if (v_face >= 0 && int(floor((gl_FragCoord.x + u_tile_offset.x) / u_resolution.y)) != v_face)
        return;  // another face's pixel: that face's copy of the source lights it
#endif
    for (int i = 0; i < MAX_OCCLUDERS; ++i) {
        if (i >= u_num_occluders) break;
        if (dot(dir, u_occluders[i].xyz) > u_occluders[i].w) return;
    }
    vec2 cell = floor(gl_FragCoord.xy);
    vec2 a = (cell - v_centre) / v_sigma;
    vec2 b = (cell + 1.0 - v_centre) / v_sigma;
    vec2 a0 = (v_lo - v_centre) / v_sigma;
    vec2 b0 = (v_hi - v_centre) / v_sigma;
    float wx = normal_between(a.x, b.x) / normal_between(a0.x, b0.x);
    float wy = normal_between(a.y, b.y) / normal_between(a0.y, b0.y);
    frag = v_channels * (wx * wy / camera_pixel_solid_angle(dir));
}
