// A reduced-resolution texture read at each pixel of a larger target (u_scale = source size /
// target size), filtered by a tent two source texels wide: four bilinear reads half a texel
// apart, so that the source's 2 x 2 ordered sample offsets (clouds/cloud_shafts.glsl) average
// out instead of showing as a pattern.
uniform sampler2D u_source;
uniform vec2 u_scale;
layout(location = 0) out vec4 frag;
void main() {
    vec2 size = vec2(textureSize(u_source, 0));
    vec2 uv = gl_FragCoord.xy * u_scale / size;
    vec2 h = 0.5 / size;
    frag = 0.25 * (texture(u_source, uv + vec2(-h.x, -h.y)) + texture(u_source, uv + vec2(h.x, -h.y))
                 + texture(u_source, uv + vec2(-h.x, h.y)) + texture(u_source, uv + vec2(h.x, h.y)));
}
