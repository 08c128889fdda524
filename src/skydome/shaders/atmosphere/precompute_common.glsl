// Shared by the precomputation passes (precompute_*.glsl): quadratures along rays and over
// the sphere of directions, and the local frame of a (r, mu, mu_s, nu) texel.
//
// Defines expected: NUM_GROUPS (wavelength groups of this pass), RAY_SAMPLES (even).
// Optional: N_MU_SKY, N_MU_GROUND, N_PHI (direction quadrature).
#include "atmosphere/precomputed_params.glsl"
#include "atmosphere/single_scattering.glsl"

// Spectral samples of group g -> the values the tables store: (X, Y, Z, scotopic) luminance
// (non-negative, so that tables can hold logarithms; the lookups convert to R, G, B), or the
// identity for output="spectral".
uniform mat4 u_spectral_to_table[NUM_GROUPS];

// ---------------------------------------------------------------- quadrature along a ray
// Gauss-Legendre rules on [0, 1]: (node, weight), RAY_SAMPLES and RAY_SAMPLES / 2 points.
uniform vec2 u_ray_rule[RAY_SAMPLES];
uniform vec2 u_ray_rule_half[RAY_SAMPLES / 2];

// Node i (t, dt, km) of the rules below for a piece [a, b] of a ray with its perigee t_p inside:
// half the nodes on each side, t = t_p -+ l u^2 with l = t_p - a before it and b - t_p after
// it, dense at the perigee.
void perigee_node(int i, float t_p, float a, float b, out float t, out float dt) {
    if (i < RAY_SAMPLES / 2) {
        vec2 q = u_ray_rule_half[i];
        float l = t_p - a;
        t = t_p - l * q.x * q.x;
        dt = 2.0 * l * q.x * q.y;
    } else {
        vec2 q = u_ray_rule_half[i - RAY_SAMPLES / 2];
        float l = b - t_p;
        t = t_p + l * q.x * q.x;
        dt = 2.0 * l * q.x * q.y;
    }
}

// Node i (t, dt) of the rule for a ray of length L from radius r with cosine mu.
// The air is densest at the lowest point of the ray: the start (mu >= 0), the end (rays that
// hit the ground), or the perigee t_p = -r mu in between. Each monotonic piece [low, high] is
// mapped with t = low + l u^2 (dense at the low end, where the density is a smooth function of
// u: exp(-c u^2) going up, exp(-c u^4) around a perigee) and integrated with Gauss-Legendre in
// u: integral f dt = integral f(t(u)) 2 l u du. A ray through its perigee gets half the nodes
// on each side (perigee_node).
void ray_node(int i, float r, float mu, float L, out float t, out float dt) {
    float t_p = clamp(-r * mu, 0.0, L);
    if (t_p <= 0.0) {
        vec2 q = u_ray_rule[i];
        t = L * q.x * q.x;
        dt = 2.0 * L * q.x * q.y;
    } else if (t_p >= L) {
        vec2 q = u_ray_rule[i];
        t = L * (1.0 - q.x * q.x);
        dt = 2.0 * L * q.x * q.y;
    } else {
        perigee_node(i, t_p, 0.0, L, t, dt);
    }
}

// The same rule restricted to the sunlit part of the ray (single scattering is zero in the
// planet's shadow): in twilight the lit part is a short segment high up, far from the ray's
// dense low end, and a rule over the whole ray puts few nodes there (5% errors at a Sun 12 deg
// below the horizon). `lit` = (a0, b0, a1, b1), the lit intervals from lit_segments (empty when
// b <= a). One lit interval gets the full rule of ray_node (split at the perigee if inside);
// two get half the nodes each, dense at their lower end.
vec4 lit_segments(float r, float mu, float mu_s, float nu, float L) {
    vec2 s = shadow_interval(r, mu, mu_s, nu, L);
    if (s.y <= s.x) return vec4(0.0, L, L, L);
    return vec4(0.0, s.x, s.y, L);
}

void segment_node(int i, float r, float mu, float a, float b, bool full, out float t, out float dt) {
    float l = b - a;
    float t_p = clamp(-r * mu, a, b);
    if (full && t_p > a && t_p < b) {
        perigee_node(i, t_p, a, b, t, dt);
        return;
    }
    vec2 q = full ? u_ray_rule[i] : u_ray_rule_half[i];
    bool up = altitude_at(r, mu, a) <= altitude_at(r, mu, b);  // dense at the lower end
    t = up ? a + l * q.x * q.x : b - l * q.x * q.x;
    dt = 2.0 * l * q.x * q.y;
}

void lit_ray_node(int i, float r, float mu, vec4 lit, out float t, out float dt) {
    bool first = lit.y > lit.x;
    bool second = lit.w > lit.z;
    if (first && second) {
        if (i < RAY_SAMPLES / 2) segment_node(i, r, mu, lit.x, lit.y, false, t, dt);
        else segment_node(i - RAY_SAMPLES / 2, r, mu, lit.z, lit.w, false, t, dt);
    } else if (first) {
        segment_node(i, r, mu, lit.x, lit.y, true, t, dt);
    } else if (second) {
        segment_node(i, r, mu, lit.z, lit.w, true, t, dt);
    } else {
        t = 0.0;
        dt = 0.0;
    }
}

// Column densities (km) from the start of a ray to the point at (r_t, mu_t) on it, given c0 =
// column_to_top(r, hits_ground ? -mu : mu) at the start (atmosphere/single_scattering.glsl).
vec3 view_column(vec3 c0, float r_t, float mu_t, bool hits_ground) {
    return column_between(c0, r_t, mu_t, hits_ground);
}

// ---------------------------------------------------------------- local frame of a texel
// Unit vectors in the frame z = zenith, x = towards the Sun's azimuth: the Sun s (cosine mu_s)
// and a view direction v with v.z = mu and v.s = nu (v.y >= 0: the other side is its mirror
// image, which sees the same sky).
vec3 sun_in_frame(float mu_s) { return vec3(safe_sqrt(1.0 - mu_s * mu_s), 0.0, mu_s); }

vec3 view_in_frame(float mu, float mu_s, float nu) {
    float sx = safe_sqrt(1.0 - mu_s * mu_s);
    float vx = sx > 1e-6 ? (nu - mu * mu_s) / sx : 0.0;
    vx = clamp(vx, -safe_sqrt(1.0 - mu * mu), safe_sqrt(1.0 - mu * mu));
    return vec3(vx, safe_sqrt(1.0 - mu * mu - vx * vx), mu);
}

// ---------------------------------------------------------------- quadrature over directions
#ifdef N_PHI
#define N_MU (N_MU_SKY + N_MU_GROUND)
#define N_DIR (N_MU * N_PHI)
// Gauss-Legendre rules on [-1, 1] for the cosines above and below the horizon, and the
// (cos, sin) of the azimuths (j + 0.5) 2 pi / N_PHI measured from the Sun's azimuth.
uniform vec2 u_mu_rule_sky[N_MU_SKY];
uniform vec2 u_mu_rule_ground[N_MU_GROUND];
uniform vec2 u_phi_cs[N_PHI];

// Cosine of the horizon seen from radius r (0 on the ground, < 0 above it).
float horizon_mu(float r) {
    float s = u_bottom_radius / r;
    return -safe_sqrt(1.0 - s * s);
}

// Cosine node a (sky nodes first) and its weight at radius r. The split at the horizon puts
// the jump between sky and ground radiance on a quadrature boundary, instead of inside a cell,
// and on each side mu = mu_h +- span s^2 with Gauss-Legendre in s crowds the nodes towards the
// horizon: in twilight the light arriving at a point high up comes from a band a few degrees
// wide around its horizon (the sunlit limb), which 8 + 4 evenly spread nodes miss by 20-40%.
vec2 mu_node(int a, float r) {
    float mu_h = horizon_mu(r);
    if (a < N_MU_SKY) {
        vec2 q = u_mu_rule_sky[a];
        float s = 0.5 * (q.x + 1.0);
        float span = 1.0 - mu_h;
        return vec2(mu_h + span * s * s, span * s * q.y);
    }
    vec2 q = u_mu_rule_ground[a - N_MU_SKY];
    float s = 0.5 * (q.x + 1.0);
    float span = mu_h + 1.0;
    return vec2(mu_h - span * s * s, span * s * q.y);
}

// Direction a * N_PHI + j of the quadrature in the texel frame, with its solid angle (sr).
vec3 quadrature_direction(int a, int j, float r, out float weight) {
    vec2 m = mu_node(a, r);
    float s = safe_sqrt(1.0 - m.x * m.x);
    weight = m.y * (2.0 * PI / float(N_PHI));
    return vec3(s * u_phi_cs[j].x, s * u_phi_cs[j].y, m.x);
}
#endif
