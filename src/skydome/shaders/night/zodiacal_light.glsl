// Zodiacal light layer (space stage): Leinert et al. 1998 table 17 (skydome.night.zodiacal),
// the 500 nm brightness by helioecliptic longitude and ecliptic latitude, interpolated
// bilinearly in the table's own (unevenly spaced) nodes with four texel fetches (exact at
// the nodes), symmetric in both angles; coloured by the reddened solar spectrum, whose
// reddening (Leinert sec. 8.1) is interpolated in solar elongation between 30 and 90 deg.
// The pixel's airless direction is used: the light comes from beyond the atmosphere.
// Output: (R, G, B, scotopic) cd/m^2 (or a spectral basis's 4 wavelengths); drawn added.
#include "common/camera.glsl"
#include "common/refraction.glsl"

#define N_DLON 19
#define N_BETA 11
uniform sampler2D u_zodiacal_table;      // N_DLON x N_BETA texels: cd/m^2 of solar-type light
uniform float u_dlon_nodes[N_DLON];      // deg
uniform float u_beta_nodes[N_BETA];      // deg
uniform mat3 u_enu_to_helioecliptic;     // x: the Sun's ecliptic longitude, z: ecliptic pole
uniform vec4 u_colour_near;              // channels per cd/m^2 at elongation <= 30 deg
uniform vec4 u_colour_far;               // at elongation >= 90 deg
out vec4 frag;

// Index of the node interval holding x (nodes increasing) and the fraction across it.
void bracket_dlon(float x, out int i, out float f) {
    i = N_DLON - 2;
    for (int k = 0; k < N_DLON - 1; ++k) {
        if (x < u_dlon_nodes[k + 1]) { i = k; break; }
    }
    f = clamp((x - u_dlon_nodes[i]) / (u_dlon_nodes[i + 1] - u_dlon_nodes[i]), 0.0, 1.0);
}

void bracket_beta(float x, out int j, out float f) {
    j = N_BETA - 2;
    for (int k = 0; k < N_BETA - 1; ++k) {
        if (x < u_beta_nodes[k + 1]) { j = k; break; }
    }
    f = clamp((x - u_beta_nodes[j]) / (u_beta_nodes[j + 1] - u_beta_nodes[j]), 0.0, 1.0);
}

void main() {
    frag = vec4(0.0);
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) return;
    vec3 h = u_enu_to_helioecliptic * airless_direction(dir);
    float dlon = abs(degrees(atan(h.y, h.x)));            // [0, 180]
    float beta = abs(degrees(atan(h.z, length(h.xy))));   // [0, 90]
    int i, j;
    float fx, fy;
    bracket_dlon(dlon, i, fx);
    bracket_beta(beta, j, fy);
    float v00 = texelFetch(u_zodiacal_table, ivec2(i, j), 0).r;
    float v10 = texelFetch(u_zodiacal_table, ivec2(i + 1, j), 0).r;
    float v01 = texelFetch(u_zodiacal_table, ivec2(i, j + 1), 0).r;
    float v11 = texelFetch(u_zodiacal_table, ivec2(i + 1, j + 1), 0).r;
    float lum = mix(mix(v00, v10, fx), mix(v01, v11, fx), fy);
    // Solar elongation from cos(e) = cos(dlon) cos(beta) = h.x / |h|.
    float elong = degrees(acos(clamp(h.x / length(h), -1.0, 1.0)));
    float w = clamp((elong - 30.0) / 60.0, 0.0, 1.0);
    frag = lum * mix(u_colour_near, u_colour_far, w);
}
