// Frame graph: adds the smooth space layers' light, drawn at a reduced resolution, to the
// full-resolution target (blend ONE, ONE) where no volume layer merges it itself.
#define BEHIND_SMOOTH 1
uniform sampler2D u_behind_smooth;
uniform vec4 u_smooth_map;   // texture coordinate = tile_xy * xy + zw
out vec4 frag;

void main() {
    frag = texture(u_behind_smooth, gl_FragCoord.xy * u_smooth_map.xy + u_smooth_map.zw);
}
