// Milky Way layer (space stage): the Galaxy's diffuse light beyond the atmosphere, looked up
// in a galactic equirectangular map (skydome.celestial.milky_way: S10, the catalogue's stars
// removed; column s = (180 deg - l) / 360 deg, row t = (90 deg - b) / 180 deg, top first).
// Each pixel's airless direction is turned into galactic coordinates by one matrix made on
// the CPU per update (galactic -> ICRS -> of date -> ENU, transposed). The map is sampled
// with mipmaps: linear within and between levels, wrapping in l, clamped at the poles; the
// level comes from the screen-space derivatives of (s, t), taking for s the smaller of the
// two derivatives of s and of s shifted by half a turn, so that the seam at l = 180 deg does
// not pick the coarsest level, scaled by cos(b) (Tarini 2012, "Cylindrical and toroidal parameterizations
// without vertex seams", JGT 16(3)). A DirectionsCamera's pixels are not neighbours: it reads
// the base level. Output: luminance x the light's colour (u_colour = output channels per S10),
// drawn added; the atmosphere layer applies the transmittance.
#include "common/camera.glsl"
#include "common/refraction.glsl"

uniform mat3 u_enu_to_galactic;
uniform sampler2D u_milky_way;  // S10
uniform vec4 u_colour;          // output channels per S10 of the Milky Way's light
out vec4 frag;

void main() {
    frag = vec4(0.0);
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) return;
    vec3 g = u_enu_to_galactic * airless_direction(dir);
    float lon = atan(g.y, g.x);
    float lat = atan(g.z, length(g.xy));  // not asin: Mesa's asin is off by up to 81"
    vec2 st = vec2(fract(0.5 - lon / (2.0 * PI)), 0.5 - lat / PI);
#if CAMERA_MODEL == 4
    float s10 = textureLod(u_milky_way, st, 0.0).r;
#else
    float s_shifted = fract(st.x + 0.5);
    vec2 dx = vec2(dFdx(st.x), dFdx(st.y));
    vec2 dy = vec2(dFdy(st.x), dFdy(st.y));
    float dxs = dFdx(s_shifted), dys = dFdy(s_shifted);
    if (abs(dxs) < abs(dx.x)) dx.x = dxs;
    if (abs(dys) < abs(dy.x)) dy.x = dys;
    // In angle a step in s is cos(b) times shorter: without this the level would follow the
    // converging meridians and blur b near the poles as well.
    float c = cos(lat);
    dx.x *= c;
    dy.x *= c;
    float s10 = textureGrad(u_milky_way, st, dx, dy).r;
#endif
    frag = u_colour * s10;
}
