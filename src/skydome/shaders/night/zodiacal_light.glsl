// Zodiacal light layer (space stage): Leinert et al. 1998 table 17 (skydome.night.zodiacal),
// the 500 nm brightness by helioecliptic longitude and ecliptic latitude, coloured by the
// reddened solar spectrum (Leinert sec. 8.1, interpolated in solar elongation between 30 and
// 90 deg). Both are resampled on the CPU (zodiacal.zodiacal_grid) onto a regular grid over
// "diamond" pseudo-angles of the helioecliptic direction (zodiacal.grid_coordinates: ratios
// of its components, monotonic in |lambda - lambda_sun| and |beta|, no inverse trigonometry),
// holding (L, L w): one hardware bilinear fetch gives the luminance L of solar-type light and
// its far-colour share w. The pixel's airless direction comes from the refraction table
// (common/airless_table.glsl), unnormalised (the pseudo-angles are ratios).
// Output: (R, G, B, scotopic) cd/m^2 (or a spectral basis's 4 wavelengths); drawn added.
#include "common/camera.glsl"
#include "common/airless_table.glsl"

uniform sampler2D u_zodiacal_grid;       // RG: L (cd/m^2 of solar-type light), L w
uniform vec4 u_grid_map;                 // (u, v) -> texture coordinates: (u, v) * xy + zw
uniform mat3 u_enu_to_helioecliptic;     // x: the Sun's ecliptic longitude, z: ecliptic pole
uniform vec4 u_colour_near;              // channels per cd/m^2 at elongation <= 30 deg
uniform vec4 u_colour_far_minus_near;    // (at elongation >= 90 deg) - near
out vec4 frag;

void main() {
    frag = vec4(0.0);
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) return;
    vec3 h = u_enu_to_helioecliptic * airless_from_table(dir);
    vec3 a = abs(h);
    float rho = length(h.xy);
    // max(): at the ecliptic poles x = y = 0 (every u there reads the same brightness).
    vec2 uv = vec2(0.5 - 0.5 * h.x / max(a.x + a.y, 1e-30), a.z / (rho + a.z));
    vec2 lw = textureLod(u_zodiacal_grid, uv * u_grid_map.xy + u_grid_map.zw, 0.0).rg;
    frag = lw.x * u_colour_near + lw.y * u_colour_far_minus_near;
}
