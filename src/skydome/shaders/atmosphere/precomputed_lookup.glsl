// Lookups into the precomputed atmosphere (atmosphere/precompute.py): sky radiance, aerial
// perspective and irradiance with every scattering order, mirroring Bruneton 2017's rendering
// API (GetSkyRadiance, GetSkyRadianceToPoint, GetSunAndSkyIrradiance).
//
// Units: positions in km, planet centred; directions unit vectors. Radiance results are
// (R, G, B, scotopic) in cd/m^2 (linear sRGB, Y = luminance) and irradiance results
// (R, G, B, scotopic) in lx, both for the solar spectrum the tables were made for at unit
// scale (multiply by the ratio of the actual to that irradiance: e.g. the Sun's distance, or a
// second source such as the Moon: call the same functions with its direction and scale).
// With output="spectral" tables (a debugging mode) the same functions return the 4 raw
// transfer values per unit solar irradiance (sr^-1 for radiance, 1 for irradiance).
//
// Needs the defines of PrecomputedAtmosphere.defines() (NUM_GROUPS) and its uniforms() and
// textures(). The direct Sun (its disk) and the ground itself are not included: the renderer
// adds them (transmittance from the returned column densities, the ground and the irradiance
// on surfaces from common/ground_shading.glsl).
#include "atmosphere/precomputed_params.glsl"
#include "atmosphere/single_scattering.glsl"

// Single scattering: (R, G, B, scotopic) without phase functions, divided by the normalization
// F of lit_density (atmosphere/precomputed_params.glsl) and multiplied by 1 / u_scattering_scale.
uniform sampler3D u_scattering_texture;  // single Rayleigh / F_R
uniform sampler3D u_single_mie_texture;  // single Mie / F_M
uniform vec4 u_scattering_size;          // (NU, MU_S, MU, R)
uniform float u_scattering_scale;        // stored x this = value / F
// Orders >= 2 (radiance) and the sky irradiance: logarithms of (X, Y, Z, scotopic),
// converted to (R, G, B, scotopic) by u_table_to_output (identity for output="spectral").
uniform sampler3D u_multiple_scattering_texture;
uniform vec4 u_multiple_scattering_size;
// ln v = lo + span * stored (16-bit normalized storage; lo = 0, span = 1 for float32).
uniform vec2 u_multiple_scattering_log_range;
uniform sampler2D u_irradiance_spectral; // sky irradiance on a horizontal surface per wavelength
                                         // (ln E / E_sun), NUM_GROUPS bands in y
uniform vec2 u_irradiance_size;          // (MU_S, R)
uniform mat4 u_table_to_output;
// Per-group weights giving each output channel an effective transmittance
// (precompute.transmittance_weights): T_c = sum_g u_transmittance_to_output[g] * T_g.
uniform mat4 u_transmittance_to_output[NUM_GROUPS];

// ---------------------------------------------------------------- helpers
// Column densities (km) from the start of the ray (r, mu) to the point at distance d on it
// (Bruneton 2017 GetTransmittance, in column densities).
vec3 column_along_ray(float r, float mu, float d, bool hits_ground) {
    float r_d = clamp(sqrt(d * d + 2.0 * r * mu * d + r * r), u_bottom_radius, u_top_radius);
    float mu_d = clamp_cosine((r * mu + d) / r_d);
    vec3 c0 = column_to_top(r, hits_ground ? -mu : mu);
    return column_between(c0, r_d, mu_d, hits_ground);
}

// Transmittance of column densities c per output channel (R, G, B, scotopic).
vec4 output_transmittance(vec3 c) {
    vec4 t = vec4(0.0);
    for (int g = 0; g < NUM_GROUPS; ++g) t += u_transmittance_to_output[g] * exp(-optical_depth(g, c));
    return t;
}

#ifdef COMPOSITE_BEHIND
// Transmittance per output channel of light with the solar spectrum's shape (what the space
// layers draw: the Sun, and closely the Moon and the stars): T_c = sum_l M[c, l] T(l) /
// sum_l M[c, l], exact for that shape because each channel is a linear functional of the
// spectrum (skydome.atmosphere.layer.behind_transmittance_weights).
uniform mat4 u_behind_transmittance[NUM_GROUPS];
vec4 behind_transmittance(vec3 c) {
    vec4 t = vec4(0.0);
    for (int g = 0; g < NUM_GROUPS; ++g) t += u_behind_transmittance[g] * exp(-optical_depth(g, c));
    return t;
}
#endif

// Fraction of the Sun's disk above the horizon seen from radius r (Bruneton 2017
// GetTransmittanceToSun: linear in the sine of the disk's height above the horizon).
float sun_visible_fraction(float r, float mu_s) {
    float sin_h = u_bottom_radius / r;
    float cos_h = -safe_sqrt(1.0 - sin_h * sin_h);
    float a = sin_h * u_sun_angular_radius;
    return smoothstep(-a, a, mu_s - cos_h);
}

// Orders >= 2 from the log-stored table at table coordinates uvwz (interpolated in the log).
vec4 multiple_scattering_at(vec4 uvwz) {
    return exp(u_multiple_scattering_log_range.x + u_multiple_scattering_log_range.y
               * sample_scattering(u_multiple_scattering_texture, uvwz, u_multiple_scattering_size, 0, 1));
}

// The same for a ray that hits the ground, interpolated linearly (not in the log) between its
// two nearest r layers. The bottom layer's ground rays have zero length and hold no light, so
// a log interpolation from it darkens every ground ray of a camera near the ground by orders
// of magnitude: at dusk, when the ground-level air is lit by the sky alone, the air in front
// of the ground went black and the ground below the horizon showed a dark band.
vec4 multiple_scattering_linear_in_r(vec4 uvwz) {
    float n = u_multiple_scattering_size.w;
    if (n < 2.0) return multiple_scattering_at(uvwz);
    float layer = uvwz.w * n - 0.5;
    float l0 = clamp(floor(layer), 0.0, n - 2.0);
    float f = clamp(layer - l0, 0.0, 1.0);
    vec4 a = multiple_scattering_at(vec4(uvwz.xyz, (l0 + 0.5) / n));
    vec4 b = multiple_scattering_at(vec4(uvwz.xyz, (l0 + 1.5) / n));
    return mix(a, b, f);
}

// Rayleigh + orders >= 2 (both / P_R) and single Mie scattering (/ P_M) at (r, mu, mu_s, nu)
// (Bruneton 2017 GetCombinedScattering), (R, G, B, scotopic).
vec4 combined_scattering(float r, float mu, float mu_s, float nu, bool hits_ground,
                         out vec4 single_mie) {
    vec4 uvwz = scattering_uvwz(r, mu, mu_s, nu, hits_ground, u_scattering_size, false);
    float k = sun_cutoff_fade(mu_s);
    vec2 F = lit_density(r, mu, mu_s, nu, ray_length(r, mu, hits_ground)) * (u_scattering_scale * k);
    single_mie = sample_scattering(u_single_mie_texture, uvwz, u_scattering_size, 0, 1) * F.y;
    vec4 rayleigh = sample_scattering(u_scattering_texture, uvwz, u_scattering_size, 0, 1) * F.x;
    vec4 uvwz_ms = scattering_uvwz(r, mu, mu_s, nu, hits_ground, u_multiple_scattering_size, true);
    vec4 ms = hits_ground ? multiple_scattering_linear_in_r(uvwz_ms)
                          : multiple_scattering_at(uvwz_ms);
    return rayleigh + u_table_to_output * ms * (k / rayleigh_phase(nu));
}

// Moves a camera outside the atmosphere to where the ray enters it. False if the ray misses.
bool enter_atmosphere(inout vec3 camera, vec3 view_ray, out float r, out float rmu) {
    r = length(camera);
    rmu = dot(camera, view_ray);
    float disc = rmu * rmu - r * r + u_top_radius * u_top_radius;
    if (r <= u_top_radius) return true;
    if (disc < 0.0) return false;
    float d = -rmu - sqrt(disc);
    if (d < 0.0) return false;
    camera += view_ray * d;
    r = u_top_radius;
    rmu += d;
    return true;
}

// ---------------------------------------------------------------- the API
// Radiance (luminance, cd/m^2) scattered towards a camera at `camera` (km, anywhere, also
// outside the atmosphere) looking along `view_ray`, by the air between the camera and the
// ground or space, with the Sun towards `sun_direction` (Bruneton 2017 GetSkyRadiance).
// `shadow_length` (km) is the length of the part of the ray next to the camera that lies in
// the shadow of an occluder (light shafts, 0 = none): that part scatters no light; the rest is
// seen through it. `column` receives the column densities (km, wavelength independent) along
// the ray to where it hits the ground or leaves the atmosphere (0 if it misses it): the
// transmittance of group g is exp(-optical_depth(g, column)).
vec4 sky_radiance(vec3 camera, vec3 view_ray, float shadow_length, vec3 sun_direction,
                  out vec3 column) {
    float r, rmu;
    column = vec3(0.0);
    if (!enter_atmosphere(camera, view_ray, r, rmu)) return vec4(0.0);
    float mu = clamp_cosine(rmu / r);
    float mu_s = clamp_cosine(dot(camera, sun_direction) / r);
    float nu = clamp_cosine(dot(view_ray, sun_direction));
    bool hits_ground = ray_hits_ground(r, mu);
    column = hits_ground ? column_along_ray(r, mu, distance_to_bottom(r, mu), true)
                         : column_to_top(r, mu);
    // The light scattered beyond the shadow, seen through the shadowed part: one lookup at
    // the end of the shadowed part, which is the camera itself when there is no shadow (one
    // call, not two branches: a CPU rasterizer would run both).
    float d = clamp(shadow_length, 0.0, ray_length(r, mu, hits_ground));
    float r_p = r, mu_p = mu, mu_s_p = mu_s;
    if (d > 0.0) {
        r_p = clamp(sqrt(d * d + 2.0 * r * mu * d + r * r), u_bottom_radius, u_top_radius);
        mu_p = clamp_cosine((r * mu + d) / r_p);
        mu_s_p = clamp_cosine((r * mu_s + d * nu) / r_p);
    }
    vec4 single_mie;
    vec4 scattering = combined_scattering(r_p, mu_p, mu_s_p, nu, hits_ground, single_mie);
    if (d > 0.0) {
        vec4 T = output_transmittance(column_along_ray(r, mu, d, hits_ground));
        scattering *= T;
        single_mie *= T;
    }
    return scattering * rayleigh_phase(nu) + single_mie * mie_phase_channels(nu);
}

// The phase-free parts of sky_radiance_to_point: Rayleigh + orders >= 2 (/ P_R) and single
// Mie (/ P_M), (R, G, B, scotopic), for the air between `camera` and the point at `distance`
// (km) along `view_ray` (Bruneton 2017 GetSkyRadianceToPoint), S(camera) - T S(point), with
// `shadow_length` (km) as in sky_radiance. The transmittance to the point is not included (the
// renderer computes it per wavelength: column_along_ray).
void scattering_to_point(vec3 camera, vec3 view_ray, float distance, float shadow_length,
                         vec3 sun_direction, out vec4 scattering, out vec4 single_mie) {
    float r, rmu;
    scattering = vec4(0.0);
    single_mie = vec4(0.0);
    vec3 start = camera;
    if (!enter_atmosphere(start, view_ray, r, rmu)) return;
    float mu = clamp_cosine(rmu / r);
    float mu_s = clamp_cosine(dot(start, sun_direction) / r);
    float nu = clamp_cosine(dot(view_ray, sun_direction));
    bool hits_ground = ray_hits_ground(r, mu);
    scattering = combined_scattering(r, mu, mu_s, nu, hits_ground, single_mie);
    // From where the ray enters the atmosphere (the camera itself when it is inside).
    float d = min(distance - length(start - camera), ray_length(r, mu, hits_ground));
    float dp = max(d - max(shadow_length, 0.0), 0.0);
    float r_p = clamp(sqrt(dp * dp + 2.0 * r * mu * dp + r * r), u_bottom_radius, u_top_radius);
    float mu_p = clamp_cosine((r * mu + dp) / r_p);
    float mu_s_p = clamp_cosine((r * mu_s + dp * nu) / r_p);
    vec4 single_mie_p;
    vec4 scattering_p = combined_scattering(r_p, mu_p, mu_s_p, nu, hits_ground, single_mie_p);
    vec4 T = output_transmittance(column_along_ray(r, mu, dp, hits_ground));
    scattering = max(scattering - T * scattering_p, vec4(0.0));
    single_mie = max(single_mie - T * single_mie_p, vec4(0.0));
    // Bruneton 2017: the difference of two nearly equal Mie values is noise once the Sun has set.
    single_mie *= smoothstep(0.0, 0.01, mu_s);
}

// Radiance (luminance, cd/m^2) scattered towards the camera by the air between `camera` and
// `point` (km): aerial perspective, scattering_to_point with the phase functions applied.
vec4 sky_radiance_to_point(vec3 camera, vec3 point, float shadow_length, vec3 sun_direction) {
    vec3 view_ray = normalize(point - camera);
    float nu = clamp_cosine(dot(view_ray, sun_direction));
    vec4 scattering, single_mie;
    scattering_to_point(camera, view_ray, length(point - camera), shadow_length, sun_direction,
                        scattering, single_mie);
    return scattering * rayleigh_phase(nu) + single_mie * mie_phase_channels(nu);
}
