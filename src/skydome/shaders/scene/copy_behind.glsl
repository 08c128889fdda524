// What lies behind a volume layer, copied unchanged (a layer with nothing to add).
uniform sampler2D u_behind;
layout(location = 0) out vec4 frag;
void main() { frag = texelFetch(u_behind, ivec2(gl_FragCoord.xy), 0); }
