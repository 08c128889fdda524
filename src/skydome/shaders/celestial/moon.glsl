// Moon layer (space stage): the Moon's disk beyond the atmosphere, a sphere lit by the Sun
// from its true direction (so the terminator and the bright limb fall where they are) and by
// the Earth (earthshine on the night side), with the albedo map of maria and highlands
// turned by the libration and the axis position angle. Photometric law: Lommel-Seeliger,
// L = k A mu0 / (mu0 + mu), with k set per phase so the disk integrates to the Moon's
// illuminance of the astronomy (Allen's phase law; skydome.celestial.moon). The earthlit
// side is seen at opposition (the Earth lights it from the observer's side): mu0 = mu.
// Output: the output channels of the Moon's colour (solar spectrum x lunar spectral albedo),
// drawn added; the atmosphere layer applies the transmittance.
#include "celestial/disk_pixel.glsl"
#include "celestial/surface_laws.glsl"

uniform vec3 u_moon_direction_true;   // airless, unit ENU, observer -> Moon centre
uniform float u_sin_angular_radius;
uniform vec3 u_moon_to_sun;           // unit ENU
uniform mat3 u_enu_to_moon;           // ENU -> Moon-fixed (x lon 0, y lon 90 E, z north)
uniform sampler2D u_albedo_map;       // relative albedo: lon -180..180 in s, lat +90..-90 in t
uniform float u_sunlit_scale;         // luminance (cd/m^2) per unit albedo x mu0 / (mu0 + mu)
uniform float u_earthlit_scale;       // luminance (cd/m^2) per unit albedo on the earthlit side
uniform vec4 u_colour;                // output channels per cd/m^2 of the Moon's light
out vec4 frag;

void main() {
    frag = vec4(0.0);
    vec3 true_dir;
    if (!pixel_sees_sphere(gl_FragCoord.xy, u_moon_direction_true, u_sin_angular_radius, true_dir)) return;
    vec3 n = sphere_normal(true_dir, u_moon_direction_true, u_sin_angular_radius);
    float mu = max(dot(n, -true_dir), 0.0);
    float mu0 = dot(n, u_moon_to_sun);
    vec3 m = u_enu_to_moon * n;
    vec2 st = vec2(atan(m.y, m.x) / (2.0 * PI) + 0.5, 0.5 - atan(m.z, length(m.xy)) / PI);
    float albedo = texture(u_albedo_map, st).r;
    frag = u_colour * (albedo * (u_sunlit_scale * lommel_seeliger_law(mu0, mu) + u_earthlit_scale));
}
