// Overlay: lays a coverage target (post/overlay_lines.glsl) over the image in one colour.
// Output premultiplied (rgb * a, a) for blending ONE, ONE_MINUS_SRC_ALPHA; pixels without
// coverage are discarded (the image stays bit for bit).
uniform sampler2D u_coverage;  // one channel, the tile's size
uniform vec2 u_origin;         // px: the tile's lower-left corner in the target
uniform vec3 u_colour;         // display (sRGB-encoded) colour
uniform float u_opacity;

out vec4 frag_colour;

void main() {
    float c = texelFetch(u_coverage, ivec2(gl_FragCoord.xy - u_origin), 0).r;
    float a = c * u_opacity;
    if (a <= 0.0) discard;
    frag_colour = vec4(u_colour * a, a);
}
