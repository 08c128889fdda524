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
// Gauss-Legendre rules on [0, 1]: (node, weight), with RAY_SAMPLES, RAY_SAMPLES / 2, / 4 and / 8
// points (the smaller ones for the pieces of a split ray; / 4 and / 8 only when RAY_SAMPLES is a
// multiple of 8, which the split at the aerosol's kink needs).
uniform vec2 u_ray_rule[RAY_SAMPLES];
uniform vec2 u_ray_rule_half[RAY_SAMPLES / 2];
#if RAY_SAMPLES % 8 == 0
#define RAY_KINK_SPLIT 1
uniform vec2 u_ray_rule_quarter[RAY_SAMPLES / 4];
uniform vec2 u_ray_rule_eighth[RAY_SAMPLES / 8];
uniform vec2 u_ray_rule_three_quarters[3 * RAY_SAMPLES / 4];
#endif
// Radius (km) where the aerosol's density has a kink (a layered profile's layer boundary: the
// mixing-layer top), 0 for none (atmosphere/uniforms.py, geometry_uniforms).
uniform float u_kink_radius;

// Node j of the rule with m points (m = RAY_SAMPLES or a half, quarter or eighth of it).
vec2 ray_rule(int m, int j) {
    if (m == RAY_SAMPLES) return u_ray_rule[j];
#ifdef RAY_KINK_SPLIT
    if (m == RAY_SAMPLES / 4) return u_ray_rule_quarter[j];
    if (m == RAY_SAMPLES / 8) return u_ray_rule_eighth[j];
    if (m == 3 * RAY_SAMPLES / 4) return u_ray_rule_three_quarters[j];
#endif
    return u_ray_rule_half[j];
}

// Node j of m on the piece [a, b] of a ray over which the altitude is monotonic, mapped with
// t = low + l u^2 from its low-altitude end (`up`: a is the lower end; the air is densest
// there, and the density is a smooth function of u: exp(-c u^2) going up, exp(-c u^4) from a
// perigee) and integrated with Gauss-Legendre in u: integral f dt = integral f(t(u)) 2 l u du.
void piece_node(int j, int m, float a, float b, bool up, out float t, out float dt) {
    vec2 q = ray_rule(m, j);
    float l = b - a;
    t = up ? a + l * q.x * q.x : b - l * q.x * q.x;
    dt = 2.0 * l * q.x * q.y;
}

// The pieces of [a, b] over which a ray's rule of n nodes (RAY_SAMPLES, or half of it for one
// of two lit intervals) is split where the integrand is not smooth: at the perigee t_p = -r mu
// (when `at_perigee`), where the altitude turns, and, with RAY_KINK_SPLIT, where the ray
// crosses u_kink_radius, where the aerosol's ln density has a kink (a Gauss-Legendre rule
// across a kink converges as 1/n^2: 16 nodes left `earth`'s single scattering 1.2-1.6 % low,
// from the ground, at a 2 km mixing-layer top). One piece gets all n nodes, two get n/2 each
// (at the kink alone: a quarter below it, 3/4 above, when n is RAY_SAMPLES), three n/2 (the
// first), n/4 and n/4, four n/4 each. Made once per ray (split_ray), then read per node
// (split_ray_node): the breakpoints do not depend on the node.
struct RaySplit {
    float a, b;        // the interval
    float p1, p2, p3;  // inner breakpoints, sorted; b when unused
    int k;             // number of pieces
    int m1;            // nodes of the first of two pieces
    int n;             // nodes in all
    bvec4 up;          // per piece: the altitude at its start <= at its end (dense at the start)
};

RaySplit split_ray(int n, float r, float mu, float a, float b, bool at_perigee) {
    RaySplit s;
    s.a = a;
    s.b = b;
    s.n = n;
    s.p1 = b;
    s.p2 = b;
    s.p3 = b;
    s.k = 1;
    float t_p = -r * mu;
    if (at_perigee && t_p > a && t_p < b) {
        s.p1 = t_p;
        s.k = 2;
    }
#ifdef RAY_KINK_SPLIT
    float rk = u_kink_radius;
    float disc = rk * rk - r * r * (1.0 - mu * mu);
    if (rk > 0.0 && disc > 0.0) {
        float h = sqrt(disc);
        for (int c = 0; c < 2; ++c) {
            float x = c == 0 ? t_p - h : t_p + h;
            if (x > a && x < b) {  // insert x into (p1, p2, p3)
                if (x < s.p1) {
                    s.p3 = s.p2;
                    s.p2 = s.p1;
                    s.p1 = x;
                } else if (x < s.p2) {
                    s.p3 = s.p2;
                    s.p2 = x;
                } else {
                    s.p3 = x;
                }
                s.k += 1;
            }
        }
    }
#endif
    // at the perigee: half each; at the kink alone, a quarter below it, 3/4 above
    s.m1 = n / 2;
    if (s.k == 2 && n == RAY_SAMPLES && s.p1 != t_p)
        s.m1 = altitude_at(r, mu, a) < altitude_at(r, mu, b) ? n / 4 : 3 * n / 4;
    float h_a = altitude_at(r, mu, a), h_1 = altitude_at(r, mu, s.p1);
    float h_2 = altitude_at(r, mu, s.p2), h_3 = altitude_at(r, mu, s.p3);
    s.up = lessThanEqual(vec4(h_a, h_1, h_2, h_3), vec4(h_1, h_2, h_3, altitude_at(r, mu, b)));
    return s;
}

// Node i of the split rule `s` (t, dt, km). The piece of node i (its first node's index, its
// nodes and its ends) is chosen before one piece_node (llvmpipe runs every branch any pixel
// of a SIMD group takes, and a call in each branch, seven inlined rules, cost the passes that
// march rays a fifth).
void split_ray_node(RaySplit s, int i, float r, float mu, out float t, out float dt) {
    int n = s.n;
    int first = 0, m = n, piece = 0;
    float lo = s.a, hi = s.b;
    if (s.k == 2) {
        bool upper = i >= s.m1;
        first = upper ? s.m1 : 0;
        m = upper ? n - s.m1 : s.m1;
        lo = upper ? s.p1 : s.a;
        hi = upper ? s.b : s.p1;
        piece = upper ? 1 : 0;
    } else if (s.k == 3) {
        int q = n / 4;
        piece = i < 2 * q ? 0 : i < 3 * q ? 1 : 2;
        first = i < 2 * q ? 0 : i < 3 * q ? 2 * q : 3 * q;
        m = i < 2 * q ? 2 * q : q;
        lo = i < 2 * q ? s.a : i < 3 * q ? s.p1 : s.p2;
        hi = i < 2 * q ? s.p1 : i < 3 * q ? s.p2 : s.b;
    } else if (s.k >= 4) {
        int q = n / 4;
        piece = i / q;
        first = piece * q;
        m = q;
        lo = piece == 0 ? s.a : piece == 1 ? s.p1 : piece == 2 ? s.p2 : s.p3;
        hi = piece == 0 ? s.p1 : piece == 1 ? s.p2 : piece == 2 ? s.p3 : s.b;
    }
    // (the unused breakpoints are b, so the last piece's flag compares with b's altitude)
    piece_node(i - first, m, lo, hi, s.up[piece], t, dt);
}

// The rule for the whole ray of length L from radius r with cosine mu (ray_node's nodes).
RaySplit whole_ray_split(float r, float mu, float L) {
    return split_ray(RAY_SAMPLES, r, mu, 0.0, L, true);
}

// Node i (t, dt, km) of the rule for the whole ray of length L from radius r with cosine mu.
void ray_node(int i, float r, float mu, float L, out float t, out float dt) {
    split_ray_node(whole_ray_split(r, mu, L), i, r, mu, t, dt);
}

// The same rule restricted to the sunlit part of the ray (single scattering is zero in the
// planet's shadow): in twilight the lit part is a short segment high up, far from the ray's
// dense low end, and a rule over the whole ray puts few nodes there (5% errors at a Sun 12 deg
// below the horizon). `lit` = (a0, b0, a1, b1), the lit intervals from lit_segments (empty when
// b <= a). One lit interval gets the full rule (split as split_ray says); two get half the
// nodes each (split at the kink, not at the perigee).
vec4 lit_segments(float r, float mu, float mu_s, float nu, float L) {
    vec2 s = shadow_interval(r, mu, mu_s, nu, L);
    if (s.y <= s.x) return vec4(0.0, L, L, L);
    return vec4(0.0, s.x, s.y, L);
}

// The lit rule of a ray: the split of its first (or only) lit interval and of its second.
struct LitRule {
    RaySplit first;
    RaySplit second;
    bool both;  // two lit intervals, half the nodes each
    bool none;  // no lit interval
};

LitRule lit_rule(float r, float mu, vec4 lit) {
    LitRule q;
    bool first = lit.y > lit.x;
    bool second = lit.w > lit.z;
    q.both = first && second;
    q.none = !first && !second;
    const int half_n = RAY_SAMPLES / 2;
    vec2 ends = second && !first ? lit.zw : lit.xy;
    q.first = split_ray(q.both ? half_n : RAY_SAMPLES, r, mu, ends.x, ends.y, !q.both);
    q.second = q.first;  // read only with two lit intervals (twilight rays): made only then
    if (q.both) q.second = split_ray(half_n, r, mu, lit.z, lit.w, false);
    return q;
}

void lit_rule_node(LitRule q, int i, float r, float mu, out float t, out float dt) {
    if (q.none) {
        t = 0.0;
        dt = 0.0;
        return;
    }
    // the interval of node i and its index there, chosen before one split_ray_node (see there)
    const int half_n = RAY_SAMPLES / 2;
    bool in_second = q.both && i >= half_n;
    split_ray_node(in_second ? q.second : q.first, in_second ? i - half_n : i, r, mu, t, dt);
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
