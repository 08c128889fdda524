// The light that lies behind a volume layer, as the frame graph hands it over: the space
// layers' light at full resolution in u_behind and, with BEHIND_SMOOTH, the light of the
// smooth space layers (airglow, zodiacal light, Milky Way: no detail below a pixel of a
// coarser grid) drawn at 1/f of the resolution with a margin of one texel, in
// u_behind_smooth, read bilinearly (skydome.scene.graph). `tile_xy` is gl_FragCoord.xy.
uniform sampler2D u_behind;  // radiance from beyond the layer along each ray, cd/m^2
#ifdef BEHIND_SMOOTH
uniform sampler2D u_behind_smooth;
uniform vec4 u_smooth_map;   // texture coordinate = tile_xy * xy + zw
#endif

vec4 light_behind(vec2 tile_xy) {
    vec4 behind = texelFetch(u_behind, ivec2(tile_xy), 0);
#ifdef BEHIND_SMOOTH
    behind += texture(u_behind_smooth, tile_xy * u_smooth_map.xy + u_smooth_map.zw);
#endif
    return behind;
}
