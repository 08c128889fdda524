// The clouds' ray march (skydome.clouds.layer): for each pixel, the light the clouds scatter
// towards the camera and their transmittance, marched through the spherical shells of the
// main layer and of the cirrus sheet (clouds/cloud_density.glsl) from any altitude (below,
// inside, above, from space). Each sample is lit by the key light (the Sun, or the Moon at
// night) through a light march towards it and a march across its local slab
// (clouds/cloud_lighting.glsl), and by the sky's irradiance from the atmosphere's tables.
// Energy-conserving integration of each step (Hillaire 2016): J (1 - exp(-sigma dt)).
//   location 0: what the clouds add to the light from behind them, seen through the air:
//               (1 - T_c) S(0 -> d) + T(0 -> d) L_c, less the ground's direct light lost in
//               their shadow where the ray ends on the ground (R, G, B, scotopic; cd/m^2:
//               may be negative there), with L_c and T_c the clouds' radiance and
//               transmittance, d their light-weighted distance, S(0 -> d) the air's light in
//               front of them and T(0 -> d) its transmittance (the atmosphere's tables:
//               the aerial-perspective tables with AERIAL_TABLES, else the 4D tables). The
//               light behind (the atmosphere and space: S(0 -> d) + T(0 -> d) X) becomes
//               S + T (L_c + T_c X) by clouds/clouds_composite.glsl's behind T_c + this;
//   location 1: (T_c, d km, the cloud shadow on the ground (1 = lit), 1).
// With CLOUDS_ALONE (the tests' probe) location 0 is the clouds' own radiance L_c.
// With CLOUDS_ALONE (tests) the key light has the irradiance u_test_irradiance at every point
// and there is no sky light. NO_JITTER starts every ray's samples at the steps' middles
// (tests); otherwise the 4x4 ordered offsets of seed 000 eq. 5.14, turned each frame by
// u_frame_jitter (the interactive mode's temporal accumulation).
#include "common/camera.glsl"
#include "atmosphere/surface_radiance.glsl"
#ifdef AERIAL_TABLES
#include "atmosphere/sky_view_mapping.glsl"
#include "atmosphere/aerial_lookup.glsl"
#endif
#include "clouds/cloud_lighting.glsl"
#include "clouds/cloud_paths.glsl"

uniform vec3 u_camera_position;   // km, planet-centred
uniform vec3 u_light_direction;   // the key light (unit, ENU)
uniform vec4 u_light_scale;       // its scale per output channel relative to the tables' Sun
uniform vec3 u_march;             // (view steps per km, most view steps, shortest step km)
uniform vec2 u_light_march_km;    // lengths of the march towards the light and across the slab
uniform float u_cloud_albedo_below; // the ground's albedo seen by the clouds' two-stream slab
uniform float u_frame_jitter;     // added to the ordered offset (0 for still frames)
uniform float u_peak_scale;       // 1 - the droplets' forward peak's share of their extinction
#ifdef HAS_DEPTH_MAP
uniform sampler2D u_depth_map;    // distance to the user's scene along each ray, km (<= 0: none)
#endif
uniform vec4 u_ambient_radiance;  // the mean radiance of the cloudy sky and ground around
                                  // the air in the clouds' shadow (CloudLayer.sky_probe)
uniform vec4 u_sky_light_ratio;   // the sky's irradiance on the ground with the clouds over
                                  // the clear sky's (CloudLayer.sky_probe; 1 without it)
uniform vec4 u_under_sky_ratio;   // the same with the clouds alone (not the fog and rain under
                                  // them): the sky light on the fog and rain
uniform float u_rain_share;       // the rain's share of the precipitation's extinction (the
                                  // rest is snow)
uniform vec3 u_sun_direction;     // the air's lights (aerial perspective)
uniform float u_sun_scale;
#ifdef HAS_LIGHT2
uniform vec3 u_light2_direction;
uniform vec4 u_light2_scale;
#endif
#ifdef CLOUDS_ALONE
uniform vec4 u_test_irradiance;
#endif
#ifdef LIGHT_MAP
#include "clouds/light_map_warp.glsl"
uniform sampler2D u_light_map;    // the clouds' light map (clouds/cloud_light_map.glsl)
uniform vec4 u_light_map_warp;    // (its warp's a, the clouds' lowest base's radius, its
                                  // centre's offsets x, y; km)
#endif

// The clouds' transmittance towards the key light L at p (LIGHT_PATH_STEPS samples per shell
// crossing): with LIGHT_MAP, below the clouds' lowest base, the light map's at the point where
// the ray towards L leaves that base's sphere (the same crossings); elsewhere marched.
float clouds_transmittance_at(vec3 p, vec3 L) {
#ifdef LIGHT_MAP
    float r = u_light_map_warp.y;
    if (dot(p, p) < r * r) {
        vec3 q = p + L * ray_sphere(p, L, r).y;
        vec2 uv = light_map_uv(q.xy - u_light_map_warp.zw, u_light_map_warp.x);
        return textureLod(u_light_map, uv, 0.0).r;
    }
#endif
    return clouds_transmittance(p, L, LIGHT_PATH_STEPS);
}

// The same through the fog and the precipitation under the clouds as well.
float key_light_transmittance(vec3 p) {
    return clouds_transmittance_at(p, u_light_direction)
         * ground_layer_transmittance(p, u_light_direction, LIGHT_PATH_STEPS);
}

layout(location = 0) out vec4 frag_radiance;
layout(location = 1) out vec4 frag_cloud;

// Samples of the march towards the light, and how often (in steps of the view march) a
// sample's light is computed afresh (the layer's quality sets both).
#ifndef LIGHT_STEPS
#define LIGHT_STEPS 6
#endif
#ifndef FAR_STEPS
#define FAR_STEPS 4
#endif
#ifndef LIGHT_EVERY
#define LIGHT_EVERY 2
#endif

// Seed 000 eq. 5.14 (its 0.22 read as the Bayer matrix's 0.25).
float ordered_offset(ivec2 xy) {
    const float M[16] = float[16](0.0, 0.5, 0.125, 0.625, 0.75, 0.25, 0.875, 0.375,
                                  0.1875, 0.6875, 0.0625, 0.5625, 0.9375, 0.4375, 0.8125, 0.3125);
    return M[(xy.y & 3) * 4 + (xy.x & 3)];
}

// The key light's irradiance normal to its beam and the sky's on a horizontal surface at p
// (R, G, B, scotopic; lx).
void irradiance_at(vec3 p, out vec4 light, out vec4 sky) {
#ifdef CLOUDS_ALONE
    light = u_test_irradiance;
    sky = vec4(0.0);
#else
    vec3 up = normalize(p);
    vec3 q = up * max(length(p), u_bottom_radius + 1e-3);
    SurfaceLight beam = surface_light(q, u_light_direction, u_light_direction);
    SurfaceLight level = surface_light(q, up, u_light_direction);
    light = vec4(0.0);
    sky = vec4(0.0);
    for (int g = 0; g < NUM_GROUPS; ++g) {
        light += u_spectral_to_rgbs[g] * sun_irradiance_group(g, beam);
        sky += u_spectral_to_rgbs[g] * sky_irradiance_group(g, level);
    }
    light *= u_light_scale;
    sky *= u_light_scale;
#endif
}

// March one shell's segment, accumulating radiance, transmittance and the light-weighted
// distance. Steps grow with the distance (a fraction u_march.x of it, at least u_march.z
// km: a pixel's footprint grows so); through empty air they are COARSE times longer, and on
// meeting a cloud the march steps back and goes on finely until it has seen EMPTY_STEPS
// empty samples in a row.
#ifndef COARSE
#define COARSE 4.0
#endif
const int EMPTY_STEPS = 3;
const float STEP_TAU = 1.0;
const float UNDER_STEP_KM = 0.5;
const int UNDER_LIGHT_EVERY = 2;
const float UNDER_LIGHT_TAU = 0.1;
const float UNDER_STEP_TAU = 0.5;
#ifndef STEP_SPLIT
#define STEP_SPLIT 1.0
#endif
// `under`: the shell of the fog and the precipitation under the clouds, lit through them
// (the key light in their shadow; the sky's light as the clouds' probe measured it); `ice`:
// the cirrus's, whose crystals scatter by the halo table (with HALOS).
void march_shell(vec3 o, vec3 d, vec2 seg, float r_lo, float r_hi, float offset, bool under,
                 bool ice, inout vec4 radiance, inout float transmittance, inout vec2 depth) {
    float len = seg.y - seg.x;
    vec4 light0, sky0, light1, sky1;
    bool lit = false;  // the irradiances at the segment's ends, on its first cloud
    bool have_j = false;
    vec2 j = vec2(0.0);
    vec4 j_colour = vec4(0.0);  // single scattering per channel, over j's grey one
    float j_radius = 0.0;  // where (km from the centre) j was computed
    vec3 L = u_light_direction;
    float nu = dot(d, L);
    bool fine = under;  // the sheet under the clouds: no skipping (it has no empty air to skip)
    float under_sigma = u_ground_extinction.x + u_ground_extinction.y;  // its densest (1/km)
    float sigma_near = 0.0;  // the extinction last met (a bound of it on a coarse hit)
    float skipped = -1.0;    // where the last coarse step through empty air began
    int empty = 0;
    float stay_fine = 0.0;
    // Each step is the interval [edge, edge + dt] (dt grows with the distance), sampled at
    // edge + offset dt and weighted by its whole length: the intervals tile the segment
    // exactly whatever the offset and however the steps grow.
    // The steps that meet no cloud (coarse through empty air, fine past a cloud's edge) run
    // in tight loops of their own inside the loop, counting the same steps i: llvmpipe runs
    // the whole body of a loop on every pass, masked, even when all its pixels have left the
    // pass by a `continue` (it skips only `if` blocks they all skip), and the lighting below
    // is most of this shader (the fair-weather still frame:
    // 2.5 s -> 1.1 s, bit-identical). The inner loops test a flag, not `while (true)` with
    // breaks: Mesa 22.3 miscompiled that form here (frames 2 % off).
    float edge = seg.x;
    int most_steps = int(u_march.y);
    int i = 0;
    while (i < most_steps) {
        if (edge >= seg.y) break;
        float dt = max(u_march.x * edge, u_march.z);
        if (!fine) {
            float coarse = min(COARSE * dt, seg.y - edge);
            sigma_near = cloud_extinction_bound(o + d * (edge + offset * coarse));
            bool more = sigma_near <= 0.0;
            while (more) {
                skipped = edge;
                edge += coarse;
                ++i;
                more = i < most_steps && edge < seg.y;
                if (more) {
                    dt = max(u_march.x * edge, u_march.z);
                    coarse = min(COARSE * dt, seg.y - edge);
                    sigma_near = cloud_extinction_bound(o + d * (edge + offset * coarse));
                    more = sigma_near <= 0.0;
                }
            }
            if (sigma_near <= 0.0) break;  // the segment or the steps ran out in empty air
            // a cloud: this coarse step again, finely, at least to its end, and the skipped
            // one before it (its sample may have fallen short of the cloud's edge: without
            // it the march would enter a jittered distance deep, seen as speckle)
            fine = true;
            empty = 0;
            stay_fine = edge + coarse;
            if (skipped >= 0.0) edge = skipped;
            skipped = -1.0;
        }
        // fine steps until one meets cloud (or leaves fine marching: back to the coarse)
        float step, t, sigma;
        vec3 p;
        bool again = true;
        while (again) {
            // in dense cloud a step spans at most STEP_TAU of optical depth (down to an
            // eighth of dt): the light is taken where the scattering happens, not up to a
            // step deep
            step = min(min(dt, seg.y - edge), max(STEP_TAU / max(sigma_near, 1e-6), dt / STEP_SPLIT));
            // the sheet under the clouds is smooth (a uniform fog, rain varying over
            // kilometres): its steps may span an optical depth of UNDER_STEP_TAU at its
            // densest, up to UNDER_STEP_KM
            if (under)
                step = min(seg.y - edge, max(dt, min(UNDER_STEP_TAU / max(under_sigma, 1e-6), UNDER_STEP_KM)));
            // (the smooth sheet under the clouds at the steps' middles: offsets there would
            // print their pattern on it, having no edges to hide)
            t = edge + (under ? 0.5 : offset) * step;
            p = o + d * t;
            sigma = cloud_extinction(p);
            edge += step;
            again = false;
            if (sigma > 0.0) {
                sigma_near = sigma;
            } else if (sigma <= 0.0) {
                if (++empty >= EMPTY_STEPS && edge >= stay_fine) fine = under;
                if (fine) {
                    ++i;
                    if (i < most_steps && edge < seg.y) {
                        dt = max(u_march.x * edge, u_march.z);
                        again = true;
                    }
                }
            }
        }
        if (sigma <= 0.0) {
            if (fine) break;  // the segment or the steps ran out
            ++i;
            continue;         // back to coarse steps
        }
        empty = 0;
        if (!lit) {
            // the segment's ends; for a sheet at the ground, whose rays run far through it,
            // its bottom and top above the segment's start (its light varies with the height)
            // (one call per end whatever the branch: irradiance_at inlined twice more cost
            // llvmpipe 15 % of a cloud frame)
            vec3 p0 = o + d * seg.x, p1 = o + d * seg.y;
            if (under) {
                vec3 up = normalize(p0);
                p0 = up * r_lo;
                p1 = up * r_hi;
            }
            irradiance_at(p0, light0, sky0);
            irradiance_at(p1, light1, sky1);
            if (under) {
                sky0 *= u_under_sky_ratio;
                sky1 *= u_under_sky_ratio;
            }
            lit = true;
        }
        // The light of this sample: recomputed on every LIGHT_EVERY-th step of the loop (the
        // same steps for every pixel: neighbouring pixels run in lockstep on a CPU
        // rasterizer, so a pixel's own schedule would not save them the work) and where a
        // pixel has none yet; between, the last one (the light varies slowly along a ray).
        // In the rain under the clouds every UNDER_LIGHT_EVERY-th, or where the height has
        // changed by an optical depth of UNDER_LIGHT_TAU since: its light varies with the
        // height, and across it over kilometres only (the clouds' shadow; its steps are up to
        // UNDER_STEP_KM).
        // (in the fog: every step, as in the clouds: its light falls off within a step)
        bool rain_only = under && length(p) >= u_ground_layer.y;
        bool fresh = i % (rain_only ? max(LIGHT_EVERY, UNDER_LIGHT_EVERY) : LIGHT_EVERY) == 0;
        if (rain_only) fresh = fresh || abs(length(p) - j_radius) * sigma > UNDER_LIGHT_TAU;
        if (!have_j || fresh) {
            j_radius = length(p);
            vec3 up = normalize(p);
            float mu_l = dot(up, L);
            // the local slab faces the light: its top is towards the light
            vec3 n_slab = mu_l >= 0.0 ? up : -up;
            float mu0 = max(abs(mu_l), 0.03);
            float to_light = min(distance_in_shell(p, L, r_lo, r_hi), u_light_march_km.x);
            float tau_s = optical_depth_along(p, L, to_light, LIGHT_STEPS, true);
            // across the slab to its far face (equal steps: exact in a uniform layer)
            float far_km = min(distance_in_shell(p, -n_slab, r_lo, r_hi), u_light_march_km.y);
            float tau_far = optical_depth_along(p, -n_slab, far_km, FAR_STEPS, false);
            // the azimuth of the scattered light (travelling along -d) from the light's, about
            // the slab's normal
            vec3 across_out = -d - dot(-d, n_slab) * n_slab, across_light = L - mu_l * up;
            float norms = length(across_out) * length(across_light);
            float cos_phi = norms > 1e-6 ? dot(across_out, across_light) / norms : 1.0;
            j = cloud_source(tau_s, tau_far, mu0, dot(-d, n_slab), nu, cos_phi,
                             u_cloud_albedo_below);
            // single scattering per channel: the droplets' colours, and under the clouds
            // the rain's share of the extinction with its own phase function (the rainbows)
            float rain = 0.0, shadow = 1.0;
            vec2 parts = vec2(0.0);  // the fog's and the precipitation's extinctions here
            if (under) {
                parts = ground_layer_parts(p, length(p));
                rain = u_rain_share * parts.y / max(parts.x + parts.y, 1e-9);
                shadow = clouds_transmittance_at(p, L);
                j *= vec2(shadow, 1.0);
            }
#ifdef HALOS
            vec4 single = ice ? halo_phase(d, L, up) : (1.0 - rain) * droplet_phase(nu);
#else
            vec4 single = (1.0 - rain) * droplet_phase(nu);
#endif
#if defined(FOG_ICE) || defined(FOG_PHASE)
            // the fog's share under the clouds by its own phase function: diamond dust's
            // crystals by the halo table, or droplets of the fog's own size (the snow's
            // share, if any, stays the clouds' droplets')
            if (under) {
                float fog = parts.x / max(parts.x + parts.y, 1e-9);
#ifdef FOG_ICE
                vec4 fog_single = halo_phase(d, L, up);
#else
                vec4 fog_single = fog_phase(nu);
#endif
                single = fog * fog_single + max(1.0 - rain - fog, 0.0) * droplet_phase(nu);
            }
#endif
            if (rain > 0.0) single += rain * rain_phase(nu);
            j_colour = (single - cloud_phase(nu)) * (exp(-tau_s) * shadow);
            have_j = true;
        }
        float w = under ? clamp((length(p) - r_lo) / max(r_hi - r_lo, 1e-9), 0.0, 1.0)
                        : clamp((t - seg.x) / max(len, 1e-6), 0.0, 1.0);
        vec4 light = mix(light0, light1, w);
        vec4 source = light * (j.x + j_colour) + mix(sky0, sky1, w) * j.y;
        float a = 1.0 - exp(-sigma * step);
        radiance += transmittance * a * source;
        depth += vec2(transmittance * a * t, transmittance * a);
        transmittance *= 1.0 - a;
        // nearly opaque: the rest of the ray as deep as it is, of this step's source
        if (transmittance < 0.01) { radiance += transmittance * source; transmittance = 0.0; break; }
        ++i;
    }
}

// The fraction of the key light that reaches the air along the ray from o over `length_km`
// (the mean of the clouds' transmittance towards it at PATH_SAMPLES points). A cloud's
// shadow is nearly 0 or 1, so the fraction takes about PATH_SAMPLES + 1 values: at a low
// Sun, where the air in front of the clouds is most of their light, 4 points drew them in
// flat terraces; 12 leave steps too small to see (+5 % on a cloud frame; the pixels'
// ordered offsets would dither them, but print their pattern at the march's resolution).
const int PATH_SAMPLES = 12;
float path_lit_fraction(vec3 o, vec3 d, float length_km) {
    float lit = 0.0;
    for (int k = 0; k < PATH_SAMPLES; ++k)
        lit += key_light_transmittance(o + d * ((float(k) + 0.5) / float(PATH_SAMPLES) * length_km));
    return lit / float(PATH_SAMPLES);
}

// The clouds' shadow on the ground over the pixel's footprint: the key light's transmittance
// at four points, where rays through a rotated grid of sub-pixel offsets meet the ground (the
// centre's point where one misses it), averaged: an edge drawn at the march's resolution is
// antialiased to a quarter of its pixel, not stair-stepped.
const vec2 FOOTPRINT[4] = vec2[4](vec2(0.125, 0.375), vec2(0.375, -0.125),
                                  vec2(-0.125, -0.375), vec2(-0.375, 0.125));
float ground_shadow(vec3 o, vec3 d, float t_ground) {
    float lit = 0.0;
    for (int k = 0; k < 4; ++k) {
        vec3 dk;
        vec3 p = o + d * t_ground;
        if (camera_ray(gl_FragCoord.xy + FOOTPRINT[k], dk)) {
            vec2 hit = ray_sphere(o, dk, u_bottom_radius);
            if (hit.x > 0.0) p = o + dk * hit.x;
        }
        lit += key_light_transmittance(p);
    }
    return 0.25 * lit;
}

// What the clouds add to the light behind them, seen through the air in front of them, for a
// march that reached transmittance T and radiance R (their own) at the light-weighted
// distance mean_km (location 0 above, before the ground's corrections).
vec4 through_air(vec3 o, vec3 d, vec3 entry, float r, float mu, bool hits_ground, float T,
                 vec4 R, float mean_km) {
    if (T >= 1.0) return vec4(0.0);
    float along = max(mean_km - length(entry - o), 0.0);
    vec4 t_air = output_transmittance(column_along_ray(r, mu, along, hits_ground));
#ifdef AERIAL_TABLES
    float ray_km = ray_length(r, mu, hits_ground);
    vec3 sun_unit = sky_view_unit(azimuth_from_light(d, u_sun_direction), d.z, hits_ground);
    vec4 air = u_sun_scale * aerial_from_table(u_sun_aerial_scattering, u_sun_aerial_single_mie,
                                               sun_unit, dot(d, u_sun_direction), along, ray_km);
#ifdef HAS_LIGHT2
    vec3 l2_unit = sky_view_unit(azimuth_from_light(d, u_light2_direction), d.z, hits_ground);
    air += u_light2_scale * aerial_from_table(u_light2_aerial_scattering,
                                              u_light2_aerial_single_mie, l2_unit,
                                              dot(d, u_light2_direction), along, ray_km);
#endif
#else
    vec3 point = o + d * max(mean_km, 1e-3);
    vec4 air = u_sun_scale * sky_radiance_to_point(o, point, 0.0, u_sun_direction);
#ifdef HAS_LIGHT2
    air += u_light2_scale * sky_radiance_to_point(o, point, 0.0, u_light2_direction);
#endif
#endif
    // the air in front of the clouds: lit by the key light where the clouds let it
    // through; in their shadow by the cloudy sky alone, a nearly isotropic field of
    // radiance u_ambient_radiance, which a column of conservatively scattering air
    // of transmittance t_air passes on as (1 - t_air) of it, whatever its phase
    float lit = path_lit_fraction(o, d, max(mean_km, 1e-3));
    air = lit * air + (1.0 - lit) * (vec4(1.0) - t_air) * u_ambient_radiance;
    return (1.0 - T) * air + t_air * R;
}

// The clear sky along the ray without the Sun's and the Moon's disks (and the ground where it
// ends there): the smooth light behind the clouds, as the probe sees it.
vec4 smooth_behind(vec3 o, vec3 d, vec3 entry, float r, float mu, bool hits_ground) {
    vec3 column;
    vec4 behind = u_sun_scale * sky_radiance(o, d, 0.0, u_sun_direction, column);
    if (hits_ground) behind += u_sun_scale * ground_radiance(entry, d, r, mu, u_sun_direction);
#ifdef HAS_LIGHT2
    behind += u_light2_scale * sky_radiance(o, d, 0.0, u_light2_direction, column);
#endif
    return behind;
}

void main() {
    frag_radiance = vec4(0.0);
    frag_cloud = vec4(1.0, 0.0, 1.0, 1.0);
    vec3 d;
    if (!camera_ray(gl_FragCoord.xy, d)) return;
    vec3 o = u_camera_position;
    vec2 ground = ray_sphere(o, d, u_bottom_radius);
    float t_ground = ground.x > 0.0 ? ground.x : 1e30;
    // a user's scene along the ray (a depth map, km): the march notes what it has met there
    // and goes on to the end of the ray (the droplets' forward peak, below)
    float t_scene = 1e30;
#ifdef HAS_DEPTH_MAP
    float scene_km = texelFetch(u_depth_map, ivec2(gl_FragCoord.xy), 0).r;
    if (scene_km > 0.0 && scene_km < t_ground) t_scene = scene_km;
#endif
    bool scene_hit = t_scene < 1e29;
#ifdef NO_JITTER
    float offset = 0.5;
#else
    float offset = fract(ordered_offset(ivec2(gl_FragCoord.xy + u_tile_offset)) + u_frame_jitter);
#endif
    vec4 radiance = vec4(0.0);
    float transmittance = 1.0;
    vec2 depth = vec2(0.0);
    // the shells near to far: the fog and precipitation under the clouds (0), the main
    // layer (1), the cirrus (2)
    vec2 segs[3];
    vec2 radii[3] = vec2[3](vec2(u_ground_layer.x, max(u_ground_layer.y, u_ground_layer.z)),
                            u_cloud_shell.xy, u_cloud_shell.zw);
    int order[3];
    int n = 0;
#ifdef NO_ALOFT
    const int SHELLS = 1;  // the sheet under the clouds alone: no clouds over it
#else
    const int SHELLS = 3;
#endif
    for (int s = 0; s < SHELLS; ++s) {
        vec2 seg;
        if (radii[s].y <= radii[s].x || !shell_segment(o, d, radii[s].x, radii[s].y, t_ground, seg))
            continue;
        int k = n++;
        for (; k > 0 && segs[order[k - 1]].x > seg.x; --k) order[k] = order[k - 1];
        segs[s] = seg;
        order[k] = s;
    }
    // before the scene, then (with one) beyond it
    vec4 radiance_scene = vec4(0.0);
    float transmittance_scene = 1.0;
    vec2 depth_scene = vec2(0.0);
    float fog_scene = 1.0;  // the transmittance of the fog and precipitation before the scene
    for (int part = 0; part < (scene_hit ? 2 : 1); ++part) {
        for (int k = 0; k < n; ++k) {
            if (transmittance <= 0.0) break;
            int s = order[k];
            vec2 seg = part == 0 ? vec2(segs[s].x, min(segs[s].y, t_scene))
                                 : vec2(max(segs[s].x, t_scene), segs[s].y);
            if (seg.y <= seg.x) continue;
            float before = transmittance;
            march_shell(o, d, seg, radii[s].x, radii[s].y, offset, s == 0, s == 2, radiance,
                        transmittance, depth);
            if (s == 0 && part == 0) fog_scene *= transmittance / before;
        }
        if (part == 0) {
            radiance_scene = radiance;
            transmittance_scene = transmittance;
            depth_scene = depth;
        }
    }
    float mean_km = depth_scene.y > 0.0 ? depth_scene.x / depth_scene.y : 0.0;
    float shadow = t_ground < 1e29 && !scene_hit ? ground_shadow(o, d, t_ground) : 1.0;
    // w: whether the ray misses the ground (the composite upsamples within each kind)
    frag_cloud = vec4(transmittance_scene, mean_km, shadow, t_ground < 1e29 ? 0.0 : 1.0);
#ifdef CLOUDS_ALONE
    frag_radiance = radiance_scene;
#else
    frag_radiance = vec4(0.0);
    vec3 entry = o;
    float r, rmu;
    if (enter_atmosphere(entry, d, r, rmu)) {
        float mu = clamp_cosine(rmu / r);
        bool hits_ground = ray_hits_ground(r, mu) && !scene_hit;
        frag_radiance = through_air(o, d, entry, r, mu, hits_ground, transmittance_scene,
                                    radiance_scene, mean_km);
        if (shadow < 1.0 && hits_ground) {
            // the ground's direct light only (common/ground_shading.glsl), seen through the air
            float d_ground = distance_to_bottom(r, mu);
            vec3 n = normalize(entry + d * d_ground);
            vec4 direct = u_light_scale * lambertian_ground(n * u_bottom_radius, n, u_light_direction,
                                                            column_along_ray(r, mu, d_ground, true), false);
            frag_radiance -= transmittance_scene * (1.0 - shadow) * direct;
        }
        if (hits_ground && u_sky_light_ratio != vec4(1.0)) {
            // the ground lit by the sky that is drawn (the clouds' probe), not the clear one
            float d_ground = distance_to_bottom(r, mu);
            vec3 n = normalize(entry + d * d_ground);
            vec3 column = column_along_ray(r, mu, d_ground, true);
            vec4 sky_lit = lambertian_ground(n * u_bottom_radius, n, u_light_direction, column, true)
                         - lambertian_ground(n * u_bottom_radius, n, u_light_direction, column, false);
            frag_radiance += transmittance_scene * (u_sky_light_ratio - 1.0) * u_light_scale * sky_lit;
        }
#ifdef SKY_PROBE
        // the probe: the whole sky, the clear one behind the clouds (no Sun's disk: its light
        // is the direct light, counted apart); the clear sky alone in frag_cloud.yzw
        vec4 behind = smooth_behind(o, d, entry, r, mu, hits_ground);
        frag_radiance += transmittance * behind;
        frag_cloud.yzw = behind.rgb;
#else
        // The drops' forward peak (skydome.clouds.phase: the part of their scattering within
        // TRUNCATION_DEG of the forward direction) is marched as unscattered light:
        // right for a smooth background, whose peak-scattered light is the light it lost.
        // A sharp source (the Sun's disk, a star, a user's scene of small details: the
        // visibility's 2 % contrast is of such a target) keeps only the truly unscattered
        // part, T_full = T^(1 / u_peak_scale), and the rest of the peak's light is the smooth
        // light behind it: the continuation of the ray beyond the scene (its clouds and the
        // sky behind them).
        // (Of the fog and the precipitation only: their sheets are smooth, while at the
        // march's resolution the clouds' ragged edges would print its texels on a bright sky.)
        float t_full = transmittance_scene * pow(fog_scene, 1.0 / u_peak_scale - 1.0);
        if (transmittance_scene > 0.0 && t_full < transmittance_scene) {
            vec4 beyond = smooth_behind(o, d, entry, r, mu, ray_hits_ground(r, mu)) * transmittance;
            if (scene_hit)
                beyond += through_air(o, d, entry, r, mu, false, transmittance, radiance, 
                                      depth.y > 0.0 ? depth.x / depth.y : 0.0)
                        - frag_radiance;
            frag_radiance += (1.0 - t_full / transmittance_scene) * beyond;
            frag_cloud.x = t_full;
        }
#endif
    }
#endif
}
