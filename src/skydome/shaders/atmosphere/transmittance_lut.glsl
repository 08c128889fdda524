// Transmittance lookup table, stored as the column densities (km) of the three constituents
// between a point at radius r and the top of the atmosphere along direction cosine mu.
// Wavelength independent: T(λ) = exp(-(βR(λ) cR + βM_ext(λ) cM + βA(λ) cA)).
// Parametrization: Bruneton 2017 (GetTransmittanceTextureUvFromRMu): x_r = rho / H and
// x_mu = (d - d_min) / (d_max - d_min), accurate near the horizon (seed 004 8.2.2.1).
#include "common/atmosphere_common.glsl"

uniform sampler2D u_transmittance_lut;
uniform vec2 u_transmittance_size;  // (width, height) in texels
uniform float u_horizon_length;     // sqrt(top^2 - bottom^2), km: the horizon distance from the top

float texcoord_from_unit(float x, float n) { return 0.5 / n + x * (1.0 - 1.0 / n); }
float unit_from_texcoord(float u, float n) { return (u - 0.5 / n) / (1.0 - 1.0 / n); }

vec2 transmittance_uv(float r, float mu) {
    float H = u_horizon_length;
    float rho = safe_sqrt(r * r - u_bottom_radius * u_bottom_radius);
    float d = distance_to_top(r, mu);
    float d_min = u_top_radius - r;
    float d_max = rho + H;
    float x_mu = (d - d_min) / max(d_max - d_min, 1e-6);
    float x_r = rho / H;
    return vec2(texcoord_from_unit(x_mu, u_transmittance_size.x),
                texcoord_from_unit(x_r, u_transmittance_size.y));
}

void transmittance_r_mu(vec2 uv, out float r, out float mu) {
    float x_mu = unit_from_texcoord(uv.x, u_transmittance_size.x);
    float x_r = unit_from_texcoord(uv.y, u_transmittance_size.y);
    float H = u_horizon_length;
    float rho = H * x_r;
    r = sqrt(rho * rho + u_bottom_radius * u_bottom_radius);
    float d_min = u_top_radius - r;
    float d_max = rho + H;
    float d = d_min + x_mu * (d_max - d_min);
    mu = d == 0.0 ? 1.0 : (H * H - rho * rho - d * d) / (2.0 * r * d);
    mu = clamp_cosine(mu);
}

// Texture u for direction cosine mu at radius r, given rho = sqrt(r^2 - bottom^2): lets two
// lookups at the same radius share the square root.
float transmittance_u(float r, float rho, float mu) {
    float d = distance_to_top(r, mu);
    float d_min = u_top_radius - r;
    return texcoord_from_unit((d - d_min) / max(rho + u_horizon_length - d_min, 1e-6), u_transmittance_size.x);
}

// Columns to the top from one radius along two directions (neither may hit the ground).
void columns_to_top(float r, float mu_a, float mu_b, out vec3 column_a, out vec3 column_b) {
    float rho = safe_sqrt(r * r - u_bottom_radius * u_bottom_radius);
    float v = texcoord_from_unit(rho / u_horizon_length, u_transmittance_size.y);
    column_a = textureLod(u_transmittance_lut, vec2(transmittance_u(r, rho, mu_a), v), 0.0).rgb;
    column_b = textureLod(u_transmittance_lut, vec2(transmittance_u(r, rho, mu_b), v), 0.0).rgb;
}

// Column densities (km) from (r, mu) to the top; the ray must not hit the ground.
vec3 column_to_top(float r, float mu) {
    return textureLod(u_transmittance_lut, transmittance_uv(r, mu), 0.0).rgb;
}
