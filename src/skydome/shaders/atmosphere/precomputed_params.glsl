// Parametrizations of the precomputed 4D scattering tables and the 2D irradiance table, shared
// by the precomputation passes and the lookups (atmosphere/precomputed_lookup.glsl).
//
// A 4D table of size (NU, MU_S, MU, R) = `size` is stored in a 3D texture of
// (NU * MU_S) x MU x R texels: x = nu_index * MU_S + mu_s_texel. Hardware filtering covers
// mu_s, mu and r; nu is interpolated by hand between two fetches (Bruneton 2017,
// GetScatteringTextureUvwzFromRMuMuSNu / GetCombinedScattering; seed 004 ch. 5.2.2.3 / 8.2.2.3).
//
//  r:    x_r = rho / H, rho = sqrt(r^2 - Rb^2) the distance to the horizon, H = that of the top.
//  mu:   split at the horizon. Rays that hit the ground use the lower half of the texels,
//        x = (d - d_min) / (d_max - d_min) with d the distance to the ground, d_min = r - Rb,
//        d_max = rho; the others the upper half with d the distance to the top, d_min = Rt - r,
//        d_max = rho + H. The two halves never interpolate into each other (seed 004 8.2.2.3).
//  mu_s: x = max(1 - a / A, 0) / (1 + a), a = (d - d_min) / (d_max - d_min) with d the distance
//        from the ground to the top towards the Sun, A the same for mu_s_min: exactly 0 at
//        mu_s_min (the cut-off), 1 at the zenith, with texels crowded around the horizon where
//        sunsets change fastest (Bruneton 2017; seed 004's A = -2 mu_s_min Rb / (d_max - d_min)
//        approximates this A).
//        Tables of smooth, direction-dependent quantities (J and the orders >= 2, `smooth`
//        mappings) use for mu sqrt(x) instead, and for mu_s the Sun's elevation, uniformly
//        from asin(mu_s_min) to 90 degrees (their variation with the Sun's position is spread
//        over the whole sky, not crowded at sunset like single scattering's).
//        For mu, the distance mapping, made for single scattering
//        (nearly linear in d), spaces the texels near the zenith 40 degrees apart at the
//        ground (d - d_min grows as the square of the zenith angle), while sqrt(x) is uniform
//        in angle there and still dense at the horizon.
//  nu:   linear, x = (nu + 1) / 2.
#include "atmosphere/transmittance_lut.glsl"

// The multiple-scattering tables store natural logarithms: interpolating ln S is exact for the
// exponential fall-off of radiance with the Sun's depression in twilight (1-3 e-folds per
// degree) and with altitude, where linear interpolation overestimates by tens of percent.
// Their values are non-negative (luminance tables hold X, Y, Z, scotopic, not R, G, B); zeros
// are stored as LOG_FLOOR.
const float LOG_FLOOR = -87.0;  // ln of a value just above the smallest normal float32
vec4 to_log(vec4 v) { return log(max(v, vec4(exp(LOG_FLOOR)))); }

// Cosine of the lowest Sun zenith angle the tables resolve; below it the cut-off row is used.
uniform float u_mu_s_min;

// ---------------------------------------------------------------- the mu_s mapping
// The smooth tables' mapping is applied to the Sun's elevation relative to the local horizon of
// radius r: e -> e_loc, piecewise linear with e_loc = 0 at e = -dip(r) (dip = acos(Rb / r), the
// Sun setting for a point at r) and the ends e_min, pi/2 kept. J changes fastest when the Sun
// sets for the point itself (its surroundings go from sunlit to shadowed: J of a point at
// 35 km jumps at a Sun 6 degrees below the ground's horizon), and this puts that moment of
// every altitude on the mapping's densest texels. (The single-scattering tables keep the
// ground's horizon: measured better there for cameras at 0-10 km.)
float horizon_dip(float r) {
    float dip = acos(clamp(u_bottom_radius / r, 0.0, 1.0));
    return min(dip, -asin(u_mu_s_min) - 0.01);
}

float local_elevation(float r, float e) {
    float dip = horizon_dip(r);
    float e_min = asin(u_mu_s_min);
    return e < -dip ? e_min * (e + dip) / (e_min + dip) : 0.5 * PI * (e + dip) / (0.5 * PI + dip);
}

float elevation_from_local(float r, float e_loc) {
    float dip = horizon_dip(r);
    float e_min = asin(u_mu_s_min);
    return e_loc < 0.0 ? e_loc * (e_min + dip) / e_min - dip : e_loc * (0.5 * PI + dip) / (0.5 * PI) - dip;
}

// Bruneton's mapping of a (local) Sun cosine, by a = (d - d_min) / (d_max - d_min) of the distance
// d (km) from the ground to the top towards the Sun: d_min = Rt - Rb (zenith), d_max = H
// (horizon). A = a(mu_s_min), the cut-off.
float mu_s_distance_unit(float d) {
    float d_min = u_top_radius - u_bottom_radius;
    float d_max = u_horizon_length;
    return (d - d_min) / (d_max - d_min);
}

float mu_s_cutoff_unit() { return mu_s_distance_unit(distance_to_top(u_bottom_radius, u_mu_s_min)); }

float mu_s_unit_bruneton(float mu_s) {
    float a = mu_s_distance_unit(distance_to_top(u_bottom_radius, mu_s));
    float A = mu_s_cutoff_unit();
    return max(1.0 - a / A, 0.0) / (1.0 + a);
}

float mu_s_from_unit_bruneton(float x) {
    float H = u_horizon_length;
    float d_min = u_top_radius - u_bottom_radius;
    float d_max = H;
    float A = mu_s_cutoff_unit();
    float a = (A - x * A) / (1.0 + x * A);
    float d = d_min + min(a, A) * (d_max - d_min);
    // Law of cosines in the triangle (centre, ground point, exit point): Rt^2 = Rb^2 + d^2 + 2 Rb d mu_s.
    return d == 0.0 ? 1.0 : clamp_cosine((H * H - d * d) / (2.0 * u_bottom_radius * d));
}

float mu_s_unit(float r, float mu_s) { return mu_s_unit_bruneton(mu_s); }

float mu_s_from_unit(float r, float x) { return mu_s_from_unit_bruneton(x); }

// The mu_s mapping of the smooth tables: by the Sun's elevation e, w(e) = sign(e) e0 ln(1 + |e| /
// e0) (texels spaced as 1 + |e| / e0: densest at the horizon, where sunsets change the light
// fastest), x = (w(e) - w(e_min)) / (w(pi/2) - w(e_min)).
uniform float u_mu_s_knee;  // e0 (rad)
float elevation_warp(float e) { return sign(e) * u_mu_s_knee * log(1.0 + abs(e) / u_mu_s_knee); }
float elevation_unwarp(float w) { return sign(w) * u_mu_s_knee * (exp(abs(w) / u_mu_s_knee) - 1.0); }

float mu_s_unit_smooth(float r, float mu_s) {
    float lo = elevation_warp(asin(u_mu_s_min));
    float hi = elevation_warp(0.5 * PI);
    float e = local_elevation(r, asin(clamp_cosine(mu_s)));
    return clamp((elevation_warp(e) - lo) / (hi - lo), 0.0, 1.0);
}

float mu_s_from_unit_smooth(float r, float x) {
    float e_min = asin(u_mu_s_min);
    float lo = elevation_warp(e_min);
    float hi = elevation_warp(0.5 * PI);
    return sin(elevation_from_local(r, clamp(elevation_unwarp(lo + x * (hi - lo)), e_min, 0.5 * PI)));
}

// ---------------------------------------------------------------- 4D table <-> (r, mu, mu_s, nu)
// Texture coordinates (x_nu in [0, 1] unit range, u_mu_s, u_mu, u_r) of (r, mu, mu_s, nu) in a
// table of size (NU, MU_S, MU, R).
vec4 scattering_uvwz(float r, float mu, float mu_s, float nu, bool hits_ground, vec4 size,
                     bool smooth_mu) {
    float H = u_horizon_length;
    float Rb = u_bottom_radius;
    float rho = safe_sqrt(r * r - Rb * Rb);
    float u_r = texcoord_from_unit(rho / H, size.w);
    float r_mu = r * mu;
    float disc = r_mu * r_mu - r * r + Rb * Rb;
    float u_mu;
    if (hits_ground) {
        float d = -r_mu - safe_sqrt(disc);
        float d_min = r - Rb;
        float d_max = rho;
        float x = d_max == d_min ? 0.0 : clamp((d - d_min) / (d_max - d_min), 0.0, 1.0);
        if (smooth_mu) x = sqrt(x);
        u_mu = 0.5 - 0.5 * texcoord_from_unit(x, 0.5 * size.z);
    } else {
        float d = -r_mu + safe_sqrt(disc + H * H);
        float d_min = u_top_radius - r;
        float d_max = rho + H;
        float x = clamp((d - d_min) / (d_max - d_min), 0.0, 1.0);
        if (smooth_mu) x = sqrt(x);
        u_mu = 0.5 + 0.5 * texcoord_from_unit(x, 0.5 * size.z);
    }
    float u_mu_s = texcoord_from_unit(smooth_mu ? mu_s_unit_smooth(r, mu_s) : mu_s_unit(r, mu_s), size.y);
    return vec4(0.5 * (nu + 1.0), u_mu_s, u_mu, u_r);
}

// (r, mu, mu_s, nu) of a texel. `texel` = (x, y) texel indices (integers), `layer` the r index.
// nu is clamped to the values possible for mu and mu_s (Bruneton 2017).
void scattering_texel_params(ivec2 texel, int layer, vec4 size, bool smooth_mu, out float r,
                             out float mu, out float mu_s, out float nu, out bool hits_ground) {
    int n_mu_s = int(size.y);
    int i_nu = texel.x / n_mu_s;
    int i_mu_s = texel.x - i_nu * n_mu_s;
    float H = u_horizon_length;
    float Rb = u_bottom_radius;
    float rho = H * (size.w > 1.0 ? float(layer) / (size.w - 1.0) : 0.0);
    r = sqrt(rho * rho + Rb * Rb);
    float half_mu = 0.5 * size.z;
    float y = float(texel.y) + 0.5;
    if (y < half_mu) {
        // Texel centres of the lower half: x = 1 at the first (the horizon at the middle).
        float x = 1.0 - (y - 0.5) / (half_mu - 1.0);
        if (smooth_mu) x *= x;
        float d_min = r - Rb;
        float d_max = rho;
        float d = d_min + (d_max - d_min) * x;
        mu = d == 0.0 ? -1.0 : clamp_cosine(-(rho * rho + d * d) / (2.0 * r * d));
        hits_ground = true;
    } else {
        float x = (y - half_mu - 0.5) / (half_mu - 1.0);
        if (smooth_mu) x *= x;
        float d_min = u_top_radius - r;
        float d_max = rho + H;
        float d = d_min + (d_max - d_min) * x;
        mu = d == 0.0 ? 1.0 : clamp_cosine((H * H - rho * rho - d * d) / (2.0 * r * d));
        hits_ground = false;
    }
    float x_mu_s = float(i_mu_s) / (size.y - 1.0);
    mu_s = smooth_mu ? mu_s_from_unit_smooth(r, x_mu_s) : mu_s_from_unit(r, x_mu_s);
    nu = -1.0 + 2.0 * float(i_nu) / (size.x - 1.0);
    float s = sqrt(max((1.0 - mu * mu) * (1.0 - mu_s * mu_s), 0.0));
    nu = clamp(nu, mu * mu_s - s, mu * mu_s + s);
}

// Sample a 4D table stored in `tex` whose depth holds `groups` stacked tables of `size` (group
// `group` is sampled). Trilinear in (mu_s, mu, r), linear in nu by hand. Returns the
// interpolated stored value.
vec4 sample_scattering(sampler3D tex, vec4 uvwz, vec4 size, int group, int groups) {
    float x = uvwz.x * (size.x - 1.0);
    float x0 = min(floor(x), size.x - 2.0);
    float f = x - x0;
    float w = (float(group) + uvwz.w) / float(groups);
    vec4 a = texture(tex, vec3((x0 + uvwz.y) / size.x, uvwz.z, w));
    vec4 b = texture(tex, vec3((x0 + 1.0 + uvwz.y) / size.x, uvwz.z, w));
    return mix(a, b, f);
}

// Below mu_s_min a table holds its cut-off row (the value at mu_s_min); it is faded to zero over
// the next 0.05 of cosine (about 3 degrees), so that the night side of the planet is dark
// instead of holding the twilight of the cut-off.
float sun_cutoff_fade(float mu_s) { return smoothstep(u_mu_s_min - 0.05, u_mu_s_min, mu_s); }

// The value of a log-stored table (smooth-mu mapping) at (r, mu, mu_s, nu).
vec4 lookup_log_table(sampler3D tex, float r, float mu, float mu_s, float nu, bool hits_ground,
                       vec4 size, int group, int groups) {
    return exp(sample_scattering(tex, scattering_uvwz(r, mu, mu_s, nu, hits_ground, size, true),
                                 size, group, groups)) * sun_cutoff_fade(mu_s);
}

// ---------------------------------------------------------------- 2D irradiance table
// Linear in r (x_r = (r - Rb) / (Rt - Rb), Bruneton 2017) and the smooth tables' mu_s mapping
// (Bruneton's is linear in mu_s over [-1, 1]: 1.8 degrees per texel at 64 texels, too coarse
// for twilight, where the sky irradiance falls by an e-fold per degree; here 0.4 degrees at
// sunset). Stored as logarithms. size = (MU_S, R) texels.
void irradiance_texel_params(ivec2 texel, vec2 size, out float r, out float mu_s) {
    float x_r = float(texel.y) / (size.y - 1.0);
    r = u_bottom_radius + x_r * (u_top_radius - u_bottom_radius);
    mu_s = mu_s_from_unit_smooth(r, float(texel.x) / (size.x - 1.0));
}

// Where the value at (r, mu_s) is read in the irradiance table: the two rows around r, each
// with the mu_s texture coordinate of its own radius, mixed linearly in r (weight f of the
// second). The mu_s mapping depends on r through the horizon dip, which grows as
// sqrt(r - Rb), so one coordinate for both rows would read a point 10 m above the ground with
// its Sun shifted by 0.1 degree on the ground row (+8% sky irradiance at Sun -6 degrees).
// uv0, uv1 are within one table of `size`; irradiance_fetch places them in a group's band.
struct IrradianceCoords {
    vec2 uv0;
    vec2 uv1;
    float f;
};

IrradianceCoords irradiance_coords(float r, float mu_s, vec2 size) {
    float height = u_top_radius - u_bottom_radius;
    float y = clamp((r - u_bottom_radius) / height, 0.0, 1.0) * (size.y - 1.0);
    float y0 = min(floor(y), size.y - 2.0);
    vec2 uv[2];
    for (int k = 0; k < 2; ++k) {
        float row = y0 + float(k);
        float r_row = u_bottom_radius + height * row / (size.y - 1.0);
        uv[k] = vec2(texcoord_from_unit(mu_s_unit_smooth(r_row, mu_s), size.x), (row + 0.5) / size.y);
    }
    return IrradianceCoords(uv[0], uv[1], y - y0);
}

// The stored value at `c` in group `group` of a table whose height holds `groups` stacked
// tables.
vec4 irradiance_fetch(sampler2D tex, IrradianceCoords c, int group, int groups) {
    vec2 band = vec2(1.0, 1.0 / float(groups));
    vec2 offset = vec2(0.0, float(group) / float(groups));
    return mix(texture(tex, c.uv0 * band + offset), texture(tex, c.uv1 * band + offset), c.f);
}

// ---------------------------------------------------------------- the lit part of a ray
// Lowest altitude (km above the ground) of the sunlit part of the ray from radius r with view
// cosine mu, length L, Sun cosines (mu_s, nu); -1 if the whole ray is in the planet's shadow.
// The shadow of a point Sun is the half cylinder |p - (p.s) s| < Rb, p.s < 0 (the sample test of
// single scattering: the Sun ray from p hits the ground). Along p(t) = x + t v:
//   |p - (p.s) s|^2 = (1 - nu^2) t^2 + 2 r (mu - mu_s nu) t + r^2 (1 - mu_s^2),
//   p.s = r mu_s + t nu,   |p|^2 = r^2 + 2 r mu t + t^2 (convex: one minimum, at t = -r mu).
float altitude_at(float r, float mu, float t) {
    return max(sqrt(max(r * r + 2.0 * r * mu * t + t * t, 0.0)) - u_bottom_radius, 0.0);
}

float lowest_in(float r, float mu, float a, float b) {
    return altitude_at(r, mu, clamp(-r * mu, a, b));
}

// The part [s0, s1] of the ray [0, L] inside the planet's shadow (s1 <= s0: none).
vec2 shadow_interval(float r, float mu, float mu_s, float nu, float L) {
    float Rb = u_bottom_radius;
    // Cylinder interval [c0, c1].
    float qa = 1.0 - nu * nu;
    float qb = r * (mu - mu_s * nu);
    float qc = r * r * (1.0 - mu_s * mu_s) - Rb * Rb;
    float c0, c1;
    if (qa < 1e-9) {
        c0 = qc < 0.0 ? -1e30 : 1e30;
        c1 = qc < 0.0 ? 1e30 : -1e30;
    } else {
        float disc = qb * qb - qa * qc;
        if (disc <= 0.0) {
            c0 = 1e30;
            c1 = -1e30;
        } else {
            float sq = sqrt(disc);
            c0 = (-qb - sq) / qa;
            c1 = (-qb + sq) / qa;
        }
    }
    // Half-space p.s < 0: t beyond (nu < 0) or before (nu > 0) the terminator plane.
    float h0 = -1e30, h1 = 1e30;
    if (abs(nu) < 1e-9) {
        if (mu_s >= 0.0) { h0 = 1e30; h1 = -1e30; }
    } else if (nu > 0.0) {
        h1 = -r * mu_s / nu;
    } else {
        h0 = -r * mu_s / nu;
    }
    return vec2(max(max(c0, h0), 0.0), min(min(c1, h1), L));
}

float lowest_lit_altitude(float r, float mu, float mu_s, float nu, float L) {
    vec2 s = shadow_interval(r, mu, mu_s, nu, L);
    float s0 = s.x;
    float s1 = s.y;
    if (s1 <= s0) return lowest_in(r, mu, 0.0, L);  // no shadow on the ray
    float best = 1e30;
    if (s0 > 0.0) best = min(best, lowest_in(r, mu, 0.0, s0));
    if (s1 < L) best = min(best, lowest_in(r, mu, s1, L));
    return best > 1e29 ? -1.0 : best;
}

// Normalization F of the single-scattering tables (Rayleigh x, Mie y): the density at the lowest
// sunlit point of the ray over that at its lowest point; 0 for a ray entirely in the shadow.
// Single scattering is dominated by the densest lit air, so in twilight it falls with the
// rising shadow like rho(h_lit) (1-3 e-folds per degree of Sun depression: linear interpolation
// across mu_s texels would be off by tens of percent); S / F varies slowly and is interpolated
// linearly, then multiplied by the exact F of the lookup. F = 1 whenever the lowest point of
// the ray is sunlit (all of the day sky), where plain linear interpolation is best (Bruneton's
// mu mapping makes the radiance nearly linear in the texture coordinate). Exact zeros (rays in
// the shadow) stay zeros.
vec2 lit_density(float r, float mu, float mu_s, float nu, float L) {
    float h = lowest_lit_altitude(r, mu, mu_s, nu, L);
    if (h < 0.0) return vec2(0.0);
    float h_low = lowest_in(r, mu, 0.0, L);
    if (h <= h_low) return vec2(1.0);
    vec2 lit = vec2(profile_density(0, h), profile_density(1, h));
    vec2 low = vec2(profile_density(0, h_low), profile_density(1, h_low));
    return max(lit, vec2(1e-30)) / max(low, vec2(1e-30));
}

// ---------------------------------------------------------------- ray geometry helpers
// Radius, view cosine and Sun cosine at distance t along the ray (r, mu) with Sun (mu_s, nu)
// (Bruneton 2017, ComputeSingleScatteringIntegrand).
void ray_point(float r, float mu, float mu_s, float nu, float t, out float r_t, out float mu_t,
               out float mu_s_t) {
    r_t = clamp(sqrt(t * t + 2.0 * r * mu * t + r * r), u_bottom_radius, u_top_radius);
    mu_t = clamp_cosine((r * mu + t) / r_t);
    mu_s_t = clamp_cosine((r * mu_s + t * nu) / r_t);
}

// Length of the ray (r, mu) inside the atmosphere: to the ground or to the top.
float ray_length(float r, float mu, bool hits_ground) {
    return hits_ground ? distance_to_bottom(r, mu) : distance_to_top(r, mu);
}
