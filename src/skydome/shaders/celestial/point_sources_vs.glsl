// Point sources (stars, planets), vertex stage: one instanced quad per source, aligned to
// whole frame pixels, that holds the source's point-spread function out to >= 4 sigma.
// Quads, not GL_POINTS: a point whose centre leaves the viewport is clipped whole, which
// would lose light at tile and frame edges; a quad is clipped to the pixels it covers.
// Per instance: the apparent unit ENU direction and the illuminance in the 4 output channels.
// u_copy: 0 the source itself; for an equirect frame 1 = its copy one frame width over (a
// source near the seam); for a cubemap the face (0-5) on whose extended plane it is drawn.
// The fragment stage (celestial/point_sources.glsl) integrates the PSF over each pixel.
#include "common/camera_project.glsl"

in vec3 in_direction;
in vec4 in_channels;

uniform vec2 u_tile_size;          // pixels of the tile drawn (the viewport)
uniform float u_psf_sigma_px;      // the PSF's own sigma, frame pixels
uniform float u_seeing_sigma_rad;  // the seeing disk's sigma, radians (0: none)
uniform int u_copy;

flat out vec4 v_channels;
flat out vec2 v_centre;     // the source's position, tile pixels
flat out vec2 v_sigma;      // the PSF's sigma along x and y, pixels
flat out vec2 v_lo;         // the quad's lower-left corner, tile pixels (whole pixels)
flat out vec2 v_hi;         // its upper-right corner
flat out int v_face;        // cubemap: the only face this copy may write (-1: any)

const float MAX_SIGMA_PX = 64.0;  // bounds the quad (a seeing disk near an equirect pole)

void discard_instance() {
    gl_Position = vec4(2.0, 2.0, 0.0, 1.0);  // all six vertices alike: no area, no fragments
    v_channels = vec4(0.0);
    v_centre = v_sigma = v_lo = v_hi = vec2(0.0);
    v_face = -1;
}

// The frame position of `dir` for this copy; false if this copy draws nothing.
bool copy_position(vec3 dir, out vec2 c) {
#if CAMERA_MODEL == 3
    // Gnomonic projection on the plane of face u_copy, extended beyond the face.
    vec3 axes[6] = vec3[6](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0),
                           vec3(0, 0, 1), vec3(0, 0, -1));
    float m = dot(dir, axes[u_copy]);
    c = vec2(-1e9);
    if (m < 0.5) return false;  // more than 60 deg off the face's axis: far from it
    vec3 q = dir / m;
    vec2 p;
    if (u_copy == 0) p = vec2(-q.y, q.z);
    else if (u_copy == 1) p = vec2(q.y, q.z);
    else if (u_copy == 2) p = vec2(q.x, q.z);
    else if (u_copy == 3) p = vec2(-q.x, q.z);
    else if (u_copy == 4) p = vec2(-q.x, q.y);
    else p = vec2(q.x, q.y);
    float side = u_resolution.y;
    c = vec2(float(u_copy) * side, 0.0) + (p + 1.0) * 0.5 * side;
    return true;
#else
    return camera_project(dir, c);
#endif
}

void main() {
    int corner = gl_VertexID % 6;
    vec3 dir = normalize(in_direction);
    vec2 c;
    if (!copy_position(dir, c) || all(equal(in_channels, vec4(0.0)))) {
        discard_instance();
        return;
    }
    // Pixels per radian along x and y at the source (finite differences of the projection
    // along two tangent directions), to turn the seeing's angle into pixels.
    vec2 sigma = vec2(u_psf_sigma_px);
    if (u_seeing_sigma_rad > 0.0) {
        vec3 ref = abs(dir.z) < 0.9 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
        vec3 t1 = normalize(cross(ref, dir));
        vec3 t2 = cross(dir, t1);
        const float H = 1e-3;  // rad
        vec2 c1, c2;
        copy_position(normalize(dir + H * t1), c1);
        copy_position(normalize(dir + H * t2), c2);
        vec2 d1 = c1 - c, d2 = c2 - c;
#if CAMERA_MODEL == 2
        // Across the seam the difference jumps by a frame width.
        d1.x -= u_resolution.x * round(d1.x / u_resolution.x);
        d2.x -= u_resolution.x * round(d2.x / u_resolution.x);
#endif
        // Marginal variances of an isotropic Gaussian of sigma s mapped by J = [d1 d2] / H:
        // (J J^T)_xx s^2 and (J J^T)_yy s^2 (the correlation is dropped: the quad's PSF is
        // separable; the weights still sum to 1).
        vec2 seeing2 = (d1 * d1 + d2 * d2) / (H * H) * u_seeing_sigma_rad * u_seeing_sigma_rad;
        sigma = sqrt(sigma * sigma + seeing2);
    }
    sigma = clamp(sigma, vec2(1e-3), vec2(MAX_SIGMA_PX));
    vec2 half_size = ceil(4.0 * sigma);
    v_face = -1;
#if CAMERA_MODEL == 2
    if (u_copy == 1) {
        float w = u_resolution.x;
        if (c.x - half_size.x - 1.0 < 0.0) c.x += w;
        else if (c.x + half_size.x + 1.0 > w) c.x -= w;
        else { discard_instance(); return; }  // clear of the seam: the first copy holds it
    }
#elif CAMERA_MODEL == 3
    float side = u_resolution.y;
    float f0 = float(u_copy) * side;
    if (c.x + half_size.x + 1.0 < f0 || c.x - half_size.x - 1.0 > f0 + side) {
        discard_instance();  // this face's plane holds none of the quad
        return;
    }
    v_face = u_copy;
#endif
    vec2 cell = floor(c);
    vec2 lo = cell - half_size;        // frame pixels: edges on whole pixels
    vec2 hi = cell + 1.0 + half_size;  // so the quad covers whole pixels and no partial ones
    vec2 offsets[6] = vec2[6](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
    vec2 corner_px = mix(lo, hi, offsets[corner]) - u_tile_offset;
    gl_Position = vec4(corner_px / u_tile_size * 2.0 - 1.0, 0.0, 1.0);
    v_channels = in_channels;
    v_centre = c - u_tile_offset;
    v_sigma = sigma;
    v_lo = lo - u_tile_offset;
    v_hi = hi - u_tile_offset;
}
