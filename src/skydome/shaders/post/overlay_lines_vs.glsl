// Overlay: one great-circle piece of a constellation line as a screen-space quad.
// Per instance: the piece's two ends, apparent unit ENU directions (in_a, in_b). Both are
// projected with common/camera_project.glsl (frame pixels), the quad covers the segment
// between them widened by the line's half width plus a pixel for the antialiased edge, and
// the fragment shader (post/overlay_lines.glsl) computes the coverage from the distance to
// the segment. Pieces are short (a few degrees): their chords follow the curve.
// u_copy: the equirect frame draws every piece twice; a piece that crosses the seam
// (its ends more than half the width apart) is drawn once next to each of its ends, one
// that does not is drawn by copy 0 only. A piece behind a perspective camera is dropped;
// one below the fisheye's horizon at both ends too (the fragment shader clips the rest).
#include "common/camera_project.glsl"

in vec3 in_a;
in vec3 in_b;

uniform vec2 u_viewport;     // px: the target tile's size
uniform float u_half_extent; // px: half the line width + 1 (the antialiasing margin)
uniform int u_copy;

flat out vec2 v_a;  // frame px
flat out vec2 v_b;

void main() {
    vec2 pa, pb;
    bool va = camera_project(in_a, pa);
    bool vb = camera_project(in_b, pb);
    bool keep = true;
#if CAMERA_MODEL == 0
    keep = va && vb;
#elif CAMERA_MODEL == 1
    keep = va || vb;
#elif CAMERA_MODEL == 2
    float w = u_resolution.x;
    bool crosses = abs(pa.x - pb.x) > 0.5 * w;
    if (crosses) {
        if (u_copy == 0) pb.x += pa.x > pb.x ? w : -w;
        else pa.x += pb.x > pa.x ? w : -w;
    } else {
        keep = u_copy == 0;
    }
#elif CAMERA_MODEL == 3
    vec2 fa, fb;
    keep = cube_face_of(in_a, fa) == cube_face_of(in_b, fb);  // split on the CPU at edges
#else
    keep = false;
#endif
    v_a = pa;
    v_b = pb;
    if (!keep) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: nothing drawn
        return;
    }
    vec2 along = pb - pa;
    float len = length(along);
    along = len > 1e-6 ? along / len : vec2(1.0, 0.0);
    vec2 across = vec2(-along.y, along.x);
    int corner = gl_VertexID;  // triangle strip: 0, 1 at a; 2, 3 at b
    vec2 p = corner < 2 ? pa - along * u_half_extent : pb + along * u_half_extent;
    p += across * u_half_extent * ((corner & 1) == 0 ? -1.0 : 1.0);
    vec2 ndc = (p - u_tile_offset) / u_viewport * 2.0 - 1.0;
    gl_Position = vec4(ndc, 0.0, 1.0);
}
