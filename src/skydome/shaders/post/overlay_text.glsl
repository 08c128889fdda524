// Overlay: the pixels of one label (vertex shader post/overlay_text_vs.glsl). The atlas has
// two channels per texel: R the glyphs' coverage, G the coverage of the glyphs widened by
// their outline (Pillow's stroke), so G >= R. The label is the glyphs in their colour over
// the widened glyphs in the outline colour ("over", Porter & Duff 1984), premultiplied:
// a = f + o (1 - f), rgb = colour f + outline o (1 - f) with f = R alpha, o = G opacity,
// for blending ONE, ONE_MINUS_SRC_ALPHA.
uniform sampler2D u_atlas;
uniform vec3 u_outline_colour;
uniform float u_outline_opacity;

flat in vec2 v_box;
flat in vec2 v_atlas;
flat in vec2 v_size;
flat in vec4 v_colour;

uniform vec2 u_tile_offset;

out vec4 frag_colour;

void main() {
    vec2 local = floor(gl_FragCoord.xy + u_tile_offset - v_box);
    if (any(lessThan(local, vec2(0.0))) || any(greaterThanEqual(local, v_size))) discard;
    vec2 rg = texelFetch(u_atlas, ivec2(v_atlas + local), 0).rg;
    float fill = rg.r * v_colour.a;
    float ring = rg.g * u_outline_opacity;
    float a = fill + ring * (1.0 - fill);
    if (a <= 0.0) discard;
    frag_colour = vec4(v_colour.rgb * fill + u_outline_colour * ring * (1.0 - fill), a);
}
