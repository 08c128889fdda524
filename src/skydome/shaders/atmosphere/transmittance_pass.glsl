// Fills the transmittance (column density) table: one texel per (r, mu), integrated with
// Simpson's rule on TRANSMITTANCE_STEPS (even) intervals.
#include "atmosphere/transmittance_lut.glsl"

in vec2 v_uv;
out vec4 frag;

void main() {
    float r, mu;
    transmittance_r_mu(gl_FragCoord.xy / u_transmittance_size, r, mu);
    float dx = distance_to_top(r, mu) / float(TRANSMITTANCE_STEPS);
    vec3 column = vec3(0.0);
    for (int i = 0; i <= TRANSMITTANCE_STEPS; ++i) {
        float t = float(i) * dx;
        float ri = sqrt(t * t + 2.0 * r * mu * t + r * r);
        float w = (i == 0 || i == TRANSMITTANCE_STEPS) ? 1.0 : ((i & 1) == 1 ? 4.0 : 2.0);
        column += w * densities(ri - u_bottom_radius);
    }
    frag = vec4(column * (dx / 3.0), 0.0);
}
