// The clouds over what lies behind them (skydome.clouds.layer), per pixel of the frame:
// behind T_c + A, with T_c the clouds' transmittance and A what they add seen through the air
// (clouds/clouds_march.glsl, possibly at a reduced resolution: read bilinearly). A pixel the
// clouds leave untouched (T_c = 1, A = 0) is passed through bit for bit.
uniform sampler2D u_behind;
uniform sampler2D u_cloud_radiance;
uniform sampler2D u_cloud_data;
uniform vec4 u_cloud_map;  // texture coordinate of a frame pixel = tile_xy * xy + zw

layout(location = 0) out vec4 frag;

void main() {
    vec4 behind = texelFetch(u_behind, ivec2(gl_FragCoord.xy), 0);
    vec2 uv = gl_FragCoord.xy * u_cloud_map.xy + u_cloud_map.zw;
    float T = texture(u_cloud_data, uv).x;
    vec4 added = texture(u_cloud_radiance, uv);
    frag = (T >= 1.0 && added == vec4(0.0)) ? behind : max(behind * T + added, vec4(0.0));
}
