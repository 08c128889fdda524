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
// t = low + l u^2 from its low-altitude end (the air is densest there, and the density is a
// smooth function of u: exp(-c u^2) going up, exp(-c u^4) from a perigee) and integrated with
// Gauss-Legendre in u: integral f dt = integral f(t(u)) 2 l u du.
void piece_node(int j, int m, float r, float mu, float a, float b, out float t, out float dt) {
    vec2 q = ray_rule(m, j);
    float l = b - a;
    bool up = altitude_at(r, mu, a) <= altitude_at(r, mu, b);  // dense at the lower end
    t = up ? a + l * q.x * q.x : b - l * q.x * q.x;
    dt = 2.0 * l * q.x * q.y;
}

// The pieces of a ray's rule, decided once per ray and read at each node: node i lies in
// piece j when start[j] <= i < start[j + 1], which has start[j + 1] - start[j] nodes on
// [lo[j], hi[j]]. (Made at every node, inside the passes' loops, the decisions were up to 21
// inlined copies of piece_node, and llvmpipe runs every branch any pixel of a SIMD group
// takes: the single-scattering pass took 0.94 s, 0.56 s with one fixed rule, 0.76 s so;
// the tables are bit-identical.)
#ifdef RAY_KINK_SPLIT
#define MAX_RAY_PIECES 8
#else
#define MAX_RAY_PIECES 4
#endif
struct RayPlan {
    int count;                       // pieces (0: no node, t = dt = 0)
    int start[MAX_RAY_PIECES + 1];
    float lo[MAX_RAY_PIECES];
    float hi[MAX_RAY_PIECES];
};

void add_piece(inout RayPlan plan, int nodes, float lo, float hi) {
    plan.lo[plan.count] = lo;
    plan.hi[plan.count] = hi;
    plan.start[plan.count + 1] = plan.start[plan.count] + nodes;
    plan.count += 1;
}

// n nodes (RAY_SAMPLES, or half of it for one of two lit intervals) on [a, b], split where
// the integrand is not smooth: at the perigee t_p = -r mu (when `at_perigee`), where the
// altitude turns, and, with RAY_KINK_SPLIT, where the ray crosses u_kink_radius, where the
// aerosol's ln density has a kink (a Gauss-Legendre rule across a kink converges as 1/n^2:
// 16 nodes left `earth`'s single scattering 1.2-1.6 % low, from the ground, at a 2 km
// mixing-layer top). One piece gets all n nodes, two get n/2 each, three n/2 (the first),
// n/4 and n/4, four n/4 each.
void split_pieces(inout RayPlan plan, int n, float r, float mu, float a, float b, bool at_perigee) {
    float p1 = b, p2 = b, p3 = b;  // inner breakpoints, sorted; b when unused
    int k = 1;
    float t_p = -r * mu;
    if (at_perigee && t_p > a && t_p < b) {
        p1 = t_p;
        k = 2;
    }
#ifdef RAY_KINK_SPLIT
    float rk = u_kink_radius;
    float disc = rk * rk - r * r * (1.0 - mu * mu);
    if (rk > 0.0 && disc > 0.0) {
        float h = sqrt(disc);
        for (int c = 0; c < 2; ++c) {
            float x = c == 0 ? t_p - h : t_p + h;
            if (x > a && x < b) {  // insert x into (p1, p2, p3)
                if (x < p1) {
                    p3 = p2;
                    p2 = p1;
                    p1 = x;
                } else if (x < p2) {
                    p3 = p2;
                    p2 = x;
                } else {
                    p3 = x;
                }
                k += 1;
            }
        }
    }
#endif
    if (k == 1) {
        add_piece(plan, n, a, b);
    } else if (k == 2) {
        // at the perigee: half each; at the kink alone, a quarter below it, 3/4 above
        int m = n / 2;
        if (n == RAY_SAMPLES && p1 != t_p) m = altitude_at(r, mu, a) < altitude_at(r, mu, b) ? n / 4 : 3 * n / 4;
        add_piece(plan, m, a, p1);
        add_piece(plan, n - m, p1, b);
    } else if (k == 3) {
        int m = n / 4;
        add_piece(plan, 2 * m, a, p1);
        add_piece(plan, m, p1, p2);
        add_piece(plan, m, p2, b);
    } else {
        int m = n / 4;
        add_piece(plan, m, a, p1);
        add_piece(plan, m, p1, p2);
        add_piece(plan, m, p2, p3);
        add_piece(plan, m, p3, b);
    }
}

RayPlan empty_plan() {
    RayPlan plan;
    plan.count = 0;
    for (int j = 0; j <= MAX_RAY_PIECES; ++j) plan.start[j] = 0;
    for (int j = 0; j < MAX_RAY_PIECES; ++j) plan.lo[j] = plan.hi[j] = 0.0;
    return plan;
}

// The rule for the whole ray of length L from radius r with cosine mu.
RayPlan ray_plan(float r, float mu, float L) {
    RayPlan plan = empty_plan();
    split_pieces(plan, RAY_SAMPLES, r, mu, 0.0, L, true);
    return plan;
}

// Node i (t, dt, km) of a plan of the ray from radius r with cosine mu (the piece chosen by
// selects over constant indices: no per-pixel array indexing).
void plan_node(RayPlan plan, int i, float r, float mu, out float t, out float dt) {
    if (plan.count == 0) {
        t = 0.0;
        dt = 0.0;
        return;
    }
    int first = 0, nodes = plan.start[1];
    float lo = plan.lo[0], hi = plan.hi[0];
    for (int j = 1; j < MAX_RAY_PIECES; ++j) {
        if (j < plan.count && i >= plan.start[j]) {
            first = plan.start[j];
            nodes = plan.start[j + 1] - plan.start[j];
            lo = plan.lo[j];
            hi = plan.hi[j];
        }
    }
    piece_node(i - first, nodes, r, mu, lo, hi, t, dt);
}

// The same rule restricted to the sunlit part of the ray (single scattering is zero in the
// planet's shadow): in twilight the lit part is a short segment high up, far from the ray's
// dense low end, and a rule over the whole ray puts few nodes there (5% errors at a Sun 12 deg
// below the horizon). `lit` = (a0, b0, a1, b1), the lit intervals from lit_segments (empty when
// b <= a). One lit interval gets the full rule (split as split_pieces says); two get half the
// nodes each (split at the kink, not at the perigee).
vec4 lit_segments(float r, float mu, float mu_s, float nu, float L) {
    vec2 s = shadow_interval(r, mu, mu_s, nu, L);
    if (s.y <= s.x) return vec4(0.0, L, L, L);
    return vec4(0.0, s.x, s.y, L);
}

RayPlan lit_plan(float r, float mu, vec4 lit) {
    RayPlan plan = empty_plan();
    bool first = lit.y > lit.x;
    bool second = lit.w > lit.z;
    const int half_n = RAY_SAMPLES / 2;
    if (first && second) {
        split_pieces(plan, half_n, r, mu, lit.x, lit.y, false);
        split_pieces(plan, half_n, r, mu, lit.z, lit.w, false);
    } else if (first) {
        split_pieces(plan, RAY_SAMPLES, r, mu, lit.x, lit.y, true);
    } else if (second) {
        split_pieces(plan, RAY_SAMPLES, r, mu, lit.z, lit.w, true);
    }
    return plan;
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
