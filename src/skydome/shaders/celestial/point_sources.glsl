// Point sources (stars, planets), fragment stage: each pixel of a source's quad (see
// celestial/point_sources_vs.glsl) gets the fraction of the source's light that a Gaussian
// PSF puts on it: the PSF's integral over the pixel (products of differences of the normal
// distribution function along x and y) over its integral over the whole quad, so that the
// weights of a quad sum to 1 exactly (the differences telescope). The vertex stage (which
// includes this file for the PSF functions only) computes what is the same across a quad:
// with WEIGHT_TABLE 1 (quads of <= 8 pixels a side) the weights of its 8 columns and 8 rows
// themselves, picked here by the pixel's column and row; else the integral over the quad,
// the pixel's own integral being computed here. The radiance is
// the illuminance times the weight over the pixel's own solid angle: the summed flux
// (radiance x solid angle) is the source's illuminance at any resolution and field of view.
// The solid angle comes from the pixel's frame position in closed form (the same values as
// camera_pixel_solid_angle(camera_ray(...)), without the pixel's direction). With
// OCCLUDERS 1 (the quads near an occluding disk only), pixels inside a disk (the Moon, in
// front of the stars) get nothing.
// Output (R, G, B, scotopic) cd/m^2, or the basis's 4 wavelengths; drawn added.
#include "common/camera_project.glsl"

#ifndef MAX_OCCLUDERS
#define MAX_OCCLUDERS 4
#endif
#ifndef OCCLUDERS
#define OCCLUDERS 0
#endif
#ifndef WEIGHT_TABLE
#define WEIGHT_TABLE 0
#endif

// erfc(x) for x >= 0: Abramowitz & Stegun (1964) 7.1.26 (Hastings' approximation),
// erf(x) = 1 - (a1 t + ... + a5 t^5) exp(-x^2), t = 1 / (1 + p x), |error| <= 1.5e-7.
float erfc_pos(float x) {
    float t = 1.0 / (1.0 + 0.3275911 * x);
    float poly = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741
               + t * (-1.453152027 + t * 1.061405429))));
    return poly * exp(-x * x);
}

// Q(u) = 1 - Phi(|u|) = erfc(|u| / sqrt 2) / 2: the normal distribution's tail beyond |u|.
float normal_tail(float u) {
    return 0.5 * erfc_pos(abs(u) * 0.70710678);
}

// P(a < X < b), a <= b, for a standard normal X, from the tails that keep digits, given
// qa = Q(a) and qb = Q(b): Q(a) - Q(b) for a >= 0, Q(-b) - Q(-a) for b <= 0 and
// 1 - Q(-a) - Q(b) across 0; the case chosen by selects, not branches (on a CPU rasterizer a
// branch runs both sides across a SIMD block). Each end's tail depends on that end alone,
// so that neighbouring pixels' values telescope.
float between_tails(float a, float b, float qa, float qb) {
    return a >= 0.0 ? qa - qb : (b <= 0.0 ? qb - qa : 1.0 - qa - qb);
}
float normal_between(float a, float b) {
    return between_tails(a, b, normal_tail(a), normal_tail(b));
}

// What the vertex stage hands each pixel of a quad (flat: one value per quad).
#ifdef POINT_SOURCES_VERTEX_STAGE
#define STAGE_OUT flat out
#else
#define STAGE_OUT flat in
#endif
STAGE_OUT vec4 v_channels;  // illuminance (WEIGHT_TABLE 0: / the PSF's integral over the quad)
STAGE_OUT int v_face;       // cubemap: the only face this copy may write (-1: any)
STAGE_OUT vec2 v_lo;        // the quad's lower-left corner, tile pixels (whole pixels)
#if WEIGHT_TABLE
STAGE_OUT vec4 v_wx0;       // its columns' weights (8, left to right)
STAGE_OUT vec4 v_wx1;
STAGE_OUT vec4 v_wy0;       // its rows' weights (8, bottom to top)
STAGE_OUT vec4 v_wy1;
#else
STAGE_OUT vec2 v_centre;     // the source's position from v_lo, pixels
STAGE_OUT vec2 v_inv_sigma;  // 1 / the PSF's sigma along x and y, 1 / pixels
#endif

#ifndef POINT_SOURCES_VERTEX_STAGE

uniform vec4 u_occluders[MAX_OCCLUDERS];  // xyz: apparent unit ENU centre, w: cos(radius)
uniform int u_num_occluders;
out vec4 frag;

// Entry k (0-7) of the 8 values (lo, hi), by masks rather than a dynamic index.
float entry8(vec4 lo, vec4 hi, int k) {
    return dot(lo, vec4(equal(ivec4(k), ivec4(0, 1, 2, 3))))
         + dot(hi, vec4(equal(ivec4(k), ivec4(4, 5, 6, 7))));
}

// Solid angle (sr) of the frame's pixel centred at frag_xy (frame pixels); false where the
// pixel sees nothing (outside the fisheye's circle). The closed forms of camera.glsl's
// mapping followed by camera_pixel_solid_angle (common/camera_project.glsl).
bool pixel_solid_angle_at(vec2 frag_xy, out float omega) {
    omega = 0.0;
#if CAMERA_MODEL == 0
    // Tangent-plane pixel step^2 times cos^3 of the off-axis angle.
    float step_ = 2.0 * u_tan_half_fov / u_resolution.x;
    vec2 ndc = frag_xy / u_resolution * 2.0 - 1.0;
    float aspect = u_resolution.x / u_resolution.y;
    vec2 plane = vec2(ndc.x, ndc.y / aspect) * u_tan_half_fov;
    float f = inversesqrt(1.0 + dot(plane, plane));
    omega = step_ * step_ * f * f * f;
    return true;
#elif CAMERA_MODEL == 1
    float side = min(u_resolution.x, u_resolution.y);
    float rho = length(frag_xy - 0.5 * u_resolution) / (0.5 * side);
    float z = rho * 0.5 * PI;  // zenith angle
    float k = PI / side;       // rad per pixel
    omega = k * k * (z > 1e-4 ? sin(z) / z : 1.0);
    return rho <= 1.0;
#elif CAMERA_MODEL == 2
    // cos(elevation) = sin(pi * (distance to the nearer pole) / height): no loss of digits
    // near the poles.
    float to_pole = min(frag_xy.y, u_resolution.y - frag_xy.y);
    omega = (2.0 * PI / u_resolution.x) * (PI / u_resolution.y) * sin(PI * to_pole / u_resolution.y);
    return true;
#elif CAMERA_MODEL == 3
    float side = u_resolution.y;
    vec2 p = vec2(mod(frag_xy.x, side), frag_xy.y) / side * 2.0 - 1.0;
    float m = inversesqrt(1.0 + dot(p, p));  // the largest component of the unit direction
    float step_ = 2.0 / side;
    omega = step_ * step_ * m * m * m;
    return true;
#else
    return false;
#endif
}

void main() {
    frag = vec4(0.0);
    vec2 frame_xy = gl_FragCoord.xy + u_tile_offset;
    float omega;
    if (!pixel_solid_angle_at(frame_xy, omega)) return;  // the pixel sees nothing
#if CAMERA_MODEL == 3
    if (v_face >= 0 && int(floor(frame_xy.x / u_resolution.y)) != v_face)
        return;  // another face's pixel: that face's copy of the source lights it
#endif
#if OCCLUDERS
    vec3 dir;
    camera_ray(gl_FragCoord.xy, dir);
    for (int i = 0; i < MAX_OCCLUDERS; ++i) {
        if (i >= u_num_occluders) break;
        if (dot(dir, u_occluders[i].xyz) > u_occluders[i].w) return;
    }
#endif
    vec2 cell = floor(gl_FragCoord.xy);
#if WEIGHT_TABLE
    ivec2 k = ivec2(cell - v_lo);  // the pixel's column and row in the quad
    float weight = entry8(v_wx0, v_wx1, k.x) * entry8(v_wy0, v_wy1, k.y);
#else
    vec2 k = cell - v_lo;  // whole pixels: exact
    vec2 a = (k - v_centre) * v_inv_sigma;
    vec2 b = (k + 1.0 - v_centre) * v_inv_sigma;
    float weight = normal_between(a.x, b.x) * normal_between(a.y, b.y);
#endif
    frag = v_channels * (weight / omega);
}

#endif
