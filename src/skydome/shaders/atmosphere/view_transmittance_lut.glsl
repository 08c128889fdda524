// Table pass of atmosphere/view_transmittance.glsl: texel i holds behind_transmittance of the
// column from the camera's radius to the top along mu(x_i), x_i = i / (n - 1), so that
// x = 0 is the horizon and x = 1 the zenith exactly.
#include "atmosphere/precomputed_lookup.glsl"
#include "atmosphere/view_transmittance.glsl"

uniform float u_view_radius;  // km
uniform float u_table_size;   // n
out vec4 frag;

void main() {
    float x = floor(gl_FragCoord.x) / (u_table_size - 1.0);
    float mu = view_transmittance_mu(x);
    frag = behind_transmittance(column_to_top(u_view_radius, mu));
}
