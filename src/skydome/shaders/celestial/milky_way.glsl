// Milky Way layer (space stage): the Galaxy's diffuse light beyond the atmosphere, looked up
// in a galactic equirectangular map (skydome.celestial.milky_way: S10, the catalogue's stars
// removed; column s = (180 deg - l) / 360 deg, row t = (90 deg - b) / 180 deg, top first).
// Each pixel's airless direction, from the refraction table (common/airless_table.glsl;
// unnormalised: the angles are atan ratios), is turned into galactic
// coordinates by one matrix made on the CPU per update (galactic -> ICRS -> of date -> ENU,
// transposed). The map is sampled with mipmaps (linear within and between levels, wrapping in
// l, clamped at the poles) at a level made here, not by the texture unit: log2 of the angle
// between neighbouring pixels' directions (the larger of the two screen axes, from the
// derivatives of the galactic vector, which has no seam) in texels of the map (as many per
// radian along b as along l on the equator). This is the level textureGrad gave for the
// derivatives of (s, t) with s's scaled by cos(b) (Tarini 2012, JGT 16(3)), without the seam
// at l = 180 deg or the blur of b near the poles. A DirectionsCamera's pixels are not
// neighbours: it reads the base level. Output: luminance x the light's colour (u_colour =
// output channels per S10), drawn added; the atmosphere layer applies the transmittance.
#include "common/camera.glsl"
#include "common/airless_table.glsl"

uniform mat3 u_enu_to_galactic;
uniform sampler2D u_milky_way;        // S10
uniform float u_log2_texels_per_rad;  // log2(map width / 2 pi)
uniform vec4 u_colour;                // output channels per S10 of the Milky Way's light
out vec4 frag;

void main() {
    frag = vec4(0.0);
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) return;
    vec3 g = u_enu_to_galactic * airless_from_table(dir);
    float lon = atan(g.y, g.x);
    float lat = atan(g.z, length(g.xy));  // not asin: Mesa's asin is off by up to 81"
    vec2 st = vec2(fract(0.5 - lon / (2.0 * PI)), 0.5 - lat / PI);
#if CAMERA_MODEL == 4
    float lod = 0.0;
#else
    vec3 gx = dFdx(g), gy = dFdy(g);
    float lod = 0.5 * log2(max(dot(gx, gx), dot(gy, gy))) + u_log2_texels_per_rad;
#endif
    frag = u_colour * textureLod(u_milky_way, st, lod).r;
}
