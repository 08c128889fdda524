// The clouds' transmittance to a user's scene (the march's data.x at the frame's resolution)
// as an RGB transmittance, for frame.info["transmittance"].
uniform sampler2D u_cloud_data;
layout(location = 0) out vec4 frag;
void main() {
    float t = texelFetch(u_cloud_data, ivec2(gl_FragCoord.xy), 0).x;
    frag = vec4(t, t, t, 1.0);
}
