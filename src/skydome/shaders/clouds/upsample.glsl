// A reduced-resolution texture read bilinearly at each pixel of a larger target
// (u_scale = source size / target size).
uniform sampler2D u_source;
uniform vec2 u_scale;
layout(location = 0) out vec4 frag;
void main() { frag = texture(u_source, gl_FragCoord.xy * u_scale / vec2(textureSize(u_source, 0))); }
