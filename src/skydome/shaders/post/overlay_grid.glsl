// Overlay: the altitude/azimuth grid over a tone-mapped (8-bit display) image.
// Altitude circles every u_alt_step, azimuth lines every u_az_step (up to u_az_max_alt),
// the horizon brighter and wider. Per pixel: the distance in pixels to the nearest line is
// the angular distance divided by the local pixel scale (the gradient of altitude or
// azimuth across the pixel, from the directions of its neighbours half a pixel away: a
// central difference), then a box-filtered coverage of a line u_line_width pixels wide.
// Output premultiplied (rgb * a, a) for blending ONE, ONE_MINUS_SRC_ALPHA.
#include "common/camera.glsl"

uniform float u_line_width;     // px
uniform float u_alt_step;       // rad
uniform float u_az_step;        // rad
uniform float u_az_max_alt;     // rad: azimuth lines stop at this |altitude|
uniform vec3 u_colour;          // display (sRGB-encoded) colour of the grid
uniform vec3 u_horizon_colour;  // and of the horizon
uniform float u_opacity;        // of the grid lines above the horizon
uniform float u_below_opacity;  // below it
uniform float u_horizon_opacity;

out vec4 frag_colour;

// The view direction at tile position xy. The fisheye's equidistant mapping is continued a
// few pixels past its rim (where camera_ray sees nothing) so that the horizon, which lies
// on the rim, is drawn whole: the same formula as camera.glsl's model 1, unclipped.
bool grid_direction(vec2 xy, out vec3 dir) {
    if (camera_ray(xy, dir)) return true;
#if CAMERA_MODEL == 1
    float side = min(u_resolution.x, u_resolution.y);
    vec2 p = (xy + u_tile_offset - 0.5 * u_resolution) / (0.5 * side);
    float rho = length(p);
    if (rho > 1.0 + (u_line_width + 2.0) / (0.5 * side)) return false;
    float zenith = rho * 0.5 * PI;
    float az = atan(-p.x, p.y);
    dir = vec3(sin(zenith) * sin(az), sin(zenith) * cos(az), cos(zenith));
    return true;
#else
    return false;
#endif
}

float altitude_of(vec3 d) { return atan(d.z, length(d.xy)); }
float azimuth_of(vec3 d) { return atan(d.x, d.y); }
float wrap_pi(float a) { return a - 2.0 * PI * floor(a / (2.0 * PI) + 0.5); }

// Coverage of a line of width w px by a pixel at distance d px from its centre line.
float coverage(float d, float w) { return clamp(0.5 * w + 0.5 - d, 0.0, 1.0); }

void main() {
    vec2 xy = gl_FragCoord.xy;
    vec3 d, dx0, dx1, dy0, dy1;
    if (!grid_direction(xy, d)) discard;
    // Neighbours half a pixel away on each side; at the edge of the fisheye's extended disk
    // the missing one is the centre (a one-sided difference, doubled).
    bool ax0 = grid_direction(xy - vec2(0.5, 0.0), dx0);
    bool ax1 = grid_direction(xy + vec2(0.5, 0.0), dx1);
    bool ay0 = grid_direction(xy - vec2(0.0, 0.5), dy0);
    bool ay1 = grid_direction(xy + vec2(0.0, 0.5), dy1);
    if (!ax0) dx0 = d;
    if (!ax1) dx1 = d;
    if (!ay0) dy0 = d;
    if (!ay1) dy1 = d;
    float sx = (ax0 && ax1) ? 1.0 : 2.0;
    float sy = (ay0 && ay1) ? 1.0 : 2.0;

    float alt = altitude_of(d);
    float az = azimuth_of(d);
    // Per-pixel rates (rad per px) of altitude and azimuth.
    vec2 g_alt = vec2(altitude_of(dx1) - altitude_of(dx0), altitude_of(dy1) - altitude_of(dy0))
        * vec2(sx, sy);
    vec2 g_az = vec2(wrap_pi(azimuth_of(dx1) - azimuth_of(dx0)),
                     wrap_pi(azimuth_of(dy1) - azimuth_of(dy0))) * vec2(sx, sy);
    float rate_alt = max(length(g_alt), 1e-9);
    float rate_az = max(length(g_az), 1e-9);

    // Horizon.
    float c_hor = coverage(abs(alt) / rate_alt, 1.5 * u_line_width);
    // Altitude circles (the horizon excluded: it has its own line).
    float k = floor(alt / u_alt_step + 0.5);
    float c_alt = 0.0;
    if (k != 0.0 && abs(k * u_alt_step) < 0.5 * PI - 1e-3)
        c_alt = coverage(abs(alt - k * u_alt_step) / rate_alt, u_line_width);
    // Azimuth lines.
    float c_az = 0.0;
    if (abs(alt) <= u_az_max_alt) {
        float m = floor(az / u_az_step + 0.5);
        c_az = coverage(abs(wrap_pi(az - m * u_az_step)) / rate_az, u_line_width);
    }
    float opacity = alt >= 0.0 ? u_opacity : u_below_opacity;
    float a_grid = max(c_alt, c_az) * opacity;
    float a_hor = c_hor * u_horizon_opacity;
    float a = max(a_grid, a_hor);
    if (a <= 0.0) discard;
    vec3 rgb = a_hor >= a_grid ? u_horizon_colour : u_colour;
    frag_colour = vec4(rgb * a, a);
}
