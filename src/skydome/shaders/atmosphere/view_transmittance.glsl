// The transmittance of the air along view rays from a camera inside the atmosphere, per
// output channel for light of the solar spectrum's shape (behind_transmittance), tabulated
// once per camera altitude: from the camera's radius it depends on the view cosine mu alone.
// The table (n x 1 texels) covers the rays that leave the atmosphere, mu
// from the horizon's cosine mu_h (< 0 above the ground) to 1, with x = sqrt((mu - mu_h) /
// (1 - mu_h)): texels crowd at the horizon, where the transmittance changes fastest (a
// setting Sun's limbs 0.5 deg apart differ by tens of per cent). Rays that meet the ground
// see nothing beyond: the frame pass tests them exactly (ray_hits_ground).
uniform sampler2D u_view_transmittance;  // n x 1, RGBA32F, linear filtering
uniform float u_view_horizon_mu;         // mu_h of the camera's radius

float view_transmittance_x(float mu) {
    return sqrt(clamp((mu - u_view_horizon_mu) / (1.0 - u_view_horizon_mu), 0.0, 1.0));
}

float view_transmittance_mu(float x) { return u_view_horizon_mu + (1.0 - u_view_horizon_mu) * x * x; }

vec4 view_transmittance(float mu) {
    float n = float(textureSize(u_view_transmittance, 0).x);
    // Texel centres at x = (i + 0.5) / n hold the exact values: map x onto them.
    float u = (view_transmittance_x(mu) * (n - 1.0) + 0.5) / n;
    return texture(u_view_transmittance, vec2(u, 0.5));
}
