// Overlay: coverage of a constellation line piece (vertex shader post/overlay_lines_vs.glsl).
// Distance from the pixel centre to the segment between the piece's projected ends (a
// capsule: round ends, so consecutive pieces join without gaps), then a box-filtered
// coverage of a line u_line_width px wide. Written into a one-channel coverage target with
// MAX blending, so that overlapping pieces (joints, figures meeting at a star) do not add
// up; post/overlay_composite.glsl then lays the coverage over the image. Pixels that see
// nothing (outside the fisheye's disk) or below u_min_z (the horizon) get nothing.
#include "common/camera.glsl"

uniform float u_line_width;  // px
uniform float u_min_z;       // lowest z of the pixel's direction that gets lines

flat in vec2 v_a;
flat in vec2 v_b;

out vec4 frag_coverage;

void main() {
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir) || dir.z < u_min_z) discard;
    vec2 p = gl_FragCoord.xy + u_tile_offset;  // frame px
    vec2 ab = v_b - v_a;
    float t = clamp(dot(p - v_a, ab) / max(dot(ab, ab), 1e-12), 0.0, 1.0);
    float d = length(p - v_a - t * ab);
    float c = clamp(0.5 * u_line_width + 0.5 - d, 0.0, 1.0);
    if (c <= 0.0) discard;
    frag_coverage = vec4(c);
}
