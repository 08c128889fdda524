// Overlay: one text label as a screen-aligned quad of its bitmap in the label atlas.
// Per instance: the anchor (apparent unit ENU direction), a second direction (mode 1 only),
// the box's offset from the anchor (px) and alignment (fractions of its size), its size and
// its origin in the atlas (texels), its colour and mode. Mode 0: box lower-left = anchor +
// offset - align * size. Mode 1 (marks on the horizon): the box is centred half its height
// plus offset.y px from the anchor towards in_up (screen direction of increasing altitude).
// The box's corner is snapped to a whole pixel so that texels map one to one onto pixels.
// u_copy: in the equirect frame a label is drawn a second time one frame width to the left
// or right (a label at the seam is seen on both sides).
#include "common/camera_project.glsl"

in vec3 in_anchor;
in vec3 in_up;
in vec2 in_offset;
in vec2 in_align;
in vec2 in_size;
in vec2 in_atlas;
in vec4 in_colour;
in float in_mode;

uniform vec2 u_viewport;
uniform int u_copy;

flat out vec2 v_box;    // frame px: the box's lower-left corner (whole pixels)
flat out vec2 v_atlas;  // texels: its origin in the atlas
flat out vec2 v_size;
flat out vec4 v_colour;

void main() {
    vec2 p;
    bool keep = camera_project(in_anchor, p);
    vec2 box = floor(p + in_offset - in_align * in_size + 0.5);
    if (in_mode > 0.5) {
        vec2 q;
        camera_project(in_up, q);
        vec2 up = q - p;
        up = length(up) > 1e-6 ? up / length(up) : vec2(0.0, 1.0);
        box = floor(p + up * (0.5 * in_size.y + in_offset.y) - 0.5 * in_size + 0.5);
    }
#if CAMERA_MODEL == 2
    if (u_copy == 1) box.x += box.x + 0.5 * in_size.x > 0.5 * u_resolution.x ? -u_resolution.x : u_resolution.x;
#else
    if (u_copy == 1) keep = false;
#endif
    v_box = box;
    v_atlas = in_atlas;
    v_size = in_size;
    v_colour = in_colour;
    if (!keep) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    int corner = gl_VertexID;  // triangle strip
    vec2 c = box + in_size * vec2(float(corner & 1), float(corner >> 1));
    gl_Position = vec4((c - u_tile_offset) / u_viewport * 2.0 - 1.0, 0.0, 1.0);
}
