// The clouds' extinction coefficient (1/km) at a point: a weather map over a repeating tile
// (coverage, cloud type, precipitation, cirrus: skydome.clouds.weather), a height profile
// per cloud type, and the shape and detail noises eroding it (the approach of seed 000 eqs.
// 5.1-5.5, in the form of Schneider 2015/2017: the coverage remaps the base shape, the detail
// erodes its edges). With UNIFORM_CLOUD (tests: the Monte Carlo slab) the main layer has the
// constant extinction u_uniform_extinction and no cirrus.
uniform vec4 u_cloud_shell;   // radii (km) from the planet's centre: layer bottom, top; cirrus bottom, top
uniform vec4 u_ground_layer;  // under the clouds: radii (km) of the ground, the fog's top, the
                              // precipitation's top (the layer's base); the fog top's fade (km)
uniform vec3 u_ground_extinction;  // 1/km: the fog's, the precipitation's at the map's full
                                   // precipitation; 1 / the layer's precipitation (0: none)
#ifdef UNIFORM_CLOUD
uniform float u_uniform_extinction;  // 1/km
#else
uniform sampler2D u_weather;       // RGBA: coverage, type, precipitation, cirrus coverage
uniform sampler3D u_shape_noise;   // RGBA: Perlin-Worley, Worley fBm x 3 frequencies
uniform sampler3D u_detail_noise;  // RGB(A): Worley fBm x 3 frequencies
uniform sampler2D u_curl_noise;    // RG: a divergence-free 2D field in [-1, 1]
uniform vec3 u_noise_tiles_km;     // repeat lengths: weather map, shape noise, detail noise
uniform vec3 u_cloud_offset_km;    // how far the wind has carried the clouds (east, north, up):
                                   // the weather texture is moved already, the noise here
uniform vec4 u_type_extinction;    // 1/km at density 1: stratus, stratocumulus, cumulus, cumulonimbus
uniform float u_cirrus_extinction; // 1/km at density 1
uniform float u_detail_erosion;    // how much the detail noise eats into the edges (0-1)
uniform float u_water_norm[16];    // skydome.clouds.params.WATER_NORMALIZATION: per cloud type
                                   // (rows) and map coverage 0.25, 0.5, 0.75, 1 (columns)
#endif

const float CELL_FILL = 0.75;
// The least density (of the peak's) left in a closed sheet (stratus at coverage 1).
const float SHEET_FLOOR = 0.3;

float remap(float v, float lo, float hi, float new_lo, float new_hi) {
    return new_lo + (v - lo) / max(hi - lo, 1e-6) * (new_hi - new_lo);
}

// Where (km) on the weather tile a planet-centred point lies: the camera is above the tile's
// origin (the x, y of the local tangent plane; the tile is small beside the planet).
vec2 tile_position(vec3 p) { return p.xy; }

#ifndef UNIFORM_CLOUD
// The density of a cloud type (0 stratus, 1/3 stratocumulus, 2/3 cumulus, 1 cumulonimbus)
// at height fraction h of the layer: a rise from the base and a fall towards the top,
// the four types' edges (fractions) interpolated.
float height_profile(float h, float type) {
    // rise start, rise end, fall start, fall end
    const vec4 STRATUS = vec4(0.0, 0.08, 0.70, 1.0);
    const vec4 STRATOCUMULUS = vec4(0.0, 0.12, 0.40, 0.80);
    const vec4 CUMULUS = vec4(0.0, 0.08, 0.35, 0.95);
    const vec4 CUMULONIMBUS = vec4(0.0, 0.05, 0.75, 1.0);
    float t = clamp(type, 0.0, 1.0) * 3.0;
    vec4 e = t < 1.0 ? mix(STRATUS, STRATOCUMULUS, t)
           : t < 2.0 ? mix(STRATOCUMULUS, CUMULUS, t - 1.0) : mix(CUMULUS, CUMULONIMBUS, t - 2.0);
    return smoothstep(e.x, e.y, h) * (1.0 - smoothstep(e.z, e.w, h));
}

float type_extinction(float type) {
    float t = clamp(type, 0.0, 1.0) * 3.0;
    return t < 1.0 ? mix(u_type_extinction.x, u_type_extinction.y, t)
         : t < 2.0 ? mix(u_type_extinction.y, u_type_extinction.z, t - 1.0)
                   : mix(u_type_extinction.z, u_type_extinction.w, t - 2.0);
}

// The factor that makes a column's water what the type asks for (skydome.clouds.params:
// the mean column of a closed deck is the nominal optical depth, and a cloud's column at a
// lower coverage holds as much), bilinear in type and coverage (held below 0.25).
float water_norm(float type, float coverage) {
    float t = clamp(type, 0.0, 1.0) * 3.0;
    int i = min(int(t), 2);
    float c = clamp(coverage * 4.0 - 1.0, 0.0, 3.0);
    int j = min(int(c), 2);
    float fc = c - float(j);
    float lo = mix(u_water_norm[i * 4 + j], u_water_norm[i * 4 + j + 1], fc);
    float hi = mix(u_water_norm[i * 4 + 4 + j], u_water_norm[i * 4 + 5 + j], fc);
    return mix(lo, hi, t - float(i));
}
#endif

// Extinction (1/km) of the main layer at planet-centred p (km), radius r. `detail` false
// skips the detail noise: an upper bound of the extinction (the detail only takes away),
// for the march's test of empty air; every optical depth (the view's, the light's, the
// shadows', the census's) is of the detailed field.
float layer_extinction(vec3 p, float r, bool detail) {
    float h = (r - u_cloud_shell.x) / (u_cloud_shell.y - u_cloud_shell.x);
    if (h <= 0.0 || h >= 1.0) return 0.0;
#ifdef UNIFORM_CLOUD
    return u_uniform_extinction;
#else
    vec2 xy = tile_position(p);
    vec4 weather = texture(u_weather, xy / u_noise_tiles_km.x);
    float coverage = weather.r;
    if (coverage <= 0.0) return 0.0;
    float profile = height_profile(h, weather.g);
    if (profile <= 0.0) return 0.0;
    // how much of a sheet the type is: 1 for stratus, 0 from stratocumulus on
    float sheet = clamp(1.0 - 3.0 * weather.g, 0.0, 1.0);
    vec3 q = vec3(xy - u_cloud_offset_km.xy, r - u_cloud_shell.x - u_cloud_offset_km.z);
    vec4 shape = textureLod(u_shape_noise, q / u_noise_tiles_km.y, 0.0);
    // the base shape: the Perlin-Worley channel and the Worley fBm, each stretched from its
    // 1st to 99th percentile (skydome.clouds.noise at the defaults: 0.45-0.97 and
    // 0.25-0.72) to [0, 1], so that the coverage threshold below meets the whole range
    float low = shape.g * 0.625 + shape.b * 0.25 + shape.a * 0.125;
    float base = clamp(0.65 * remap(shape.r, 0.45, 0.97, 0.0, 1.0)
                       + 0.35 * remap(low, 0.25, 0.72, 0.0, 1.0), 0.0, 1.0);
    // Heaped clouds take their height profile into the shape before the threshold (rounded
    // tops, flat bases); a sheet is thresholded alone and follows the profile after.
    base *= mix(profile, 1.0, sheet);
    // The coverage keeps the top of the shape's range: 0 leaves nothing. A fully covered
    // texel of the map leaves the shape's lowest part clear in heaped clouds (cumulus cells,
    // the breaks of a stratocumulus deck); a sheet closes as the coverage nears 1 (the
    // threshold falls below the shape's least value: SHEET_FLOOR of the density remains).
    // The coverage sets where the cloud is, not how dense: the water per column is set by
    // u_type_extinction (skydome.clouds.params.WATER_NORMALIZATION).
    float fill = mix(1.0, CELL_FILL, clamp(1.5 * weather.g, 0.0, 1.0)) * coverage;
    float closing = sheet * pow(coverage, 8.0) * SHEET_FLOOR / (1.0 - SHEET_FLOOR);
    float density = clamp(remap(base, 1.0 - fill - closing, 1.0, 0.0, 1.0), 0.0, 1.0);
    density *= mix(1.0, profile, sheet);
    if (density <= 0.0) return 0.0;
    if (detail) {
        // the detail's own fBm (its alpha), stretched as the shape's (0.3-0.66)
        float high = clamp(remap(textureLod(u_detail_noise, q / u_noise_tiles_km.z, 0.0).a,
                                 0.3, 0.66, 0.0, 1.0), 0.0, 1.0);
        // wispy at the base, billowy above (Schneider 2015)
        high = mix(high, 1.0 - high, clamp(h * 5.0, 0.0, 1.0));
        // it erodes a heaped cloud's edges; in a sheet it only thins (never to a hole)
        float eroded = clamp(remap(density, high * u_detail_erosion, 1.0, 0.0, 1.0), 0.0, 1.0);
        density = mix(eroded, density * (1.0 - u_detail_erosion * high), sheet);
    }
    // rain-bearing cloud holds more water
    return density * type_extinction(weather.g) * water_norm(weather.g, coverage)
         * (1.0 + 2.0 * weather.b);
#endif
}

// Extinction (1/km) of the cirrus sheet: streaks of the shape noise drawn out by the curl
// field over the weather map's cirrus coverage.
float cirrus_extinction(vec3 p, float r) {
#ifdef UNIFORM_CLOUD
    return 0.0;
#else
    float h = (r - u_cloud_shell.z) / max(u_cloud_shell.w - u_cloud_shell.z, 1e-6);
    if (h <= 0.0 || h >= 1.0) return 0.0;
    vec2 xy = tile_position(p);
    float cover = texture(u_weather, xy / u_noise_tiles_km.x).a;
    xy -= u_cloud_offset_km.xy;
    if (cover <= 0.0) return 0.0;
    vec2 curl = texture(u_curl_noise, xy / (0.5 * u_noise_tiles_km.x)).rg;
    vec2 warped = xy + curl * 3.0;
    vec4 shape = textureLod(u_shape_noise, vec3(warped.x * 0.25, warped.y, h * 2.0) / u_noise_tiles_km.y, 0.0);
    float fbm = shape.g * 0.5 + shape.b * 0.3 + shape.a * 0.2;
    float density = clamp(remap(fbm, 1.0 - cover, 1.0, 0.0, 1.0), 0.0, 1.0) * cover;
    return density * 4.0 * h * (1.0 - h) * u_cirrus_extinction;
#endif
}

// Extinction (1/km) under the clouds (the weather: skydome.weather), as (the fog's, the rain
// and snow's): the fog, thinning over its top's fade, and the rain or snow falling from the
// layer's base where the weather map has precipitation (its coverage where the layer has
// none: rain where the clouds are).
vec2 ground_layer_parts(vec3 p, float r) {
    vec2 sigma = vec2(0.0);
    if (r < u_ground_layer.y)
        sigma.x = u_ground_extinction.x * clamp((u_ground_layer.y - r) / max(u_ground_layer.w, 1e-6), 0.0, 1.0);
    if (r < u_ground_layer.z) {
#ifdef UNIFORM_CLOUD
        sigma.y = u_ground_extinction.y;
#else
        vec4 weather = texture(u_weather, tile_position(p) / u_noise_tiles_km.x);
        float rain = u_ground_extinction.z > 0.0 ? weather.b * u_ground_extinction.z : weather.r;
        sigma.y = u_ground_extinction.y * clamp(rain, 0.0, 1.0);
#endif
    }
    return sigma;
}

float ground_layer_extinction(vec3 p, float r) {
    vec2 parts = ground_layer_parts(p, r);
    return parts.x + parts.y;
}

// Extinction (1/km) of the clouds at planet-centred p (km).
float cloud_extinction(vec3 p) {
    float r = length(p);
    if (r < u_ground_layer.y || r < u_ground_layer.z) return ground_layer_extinction(p, r);
    if (r < u_cloud_shell.y + 1e-4) return layer_extinction(p, r, true);
    return cirrus_extinction(p, r);
}

// An upper bound of cloud_extinction (no detail noise): zero only where the clouds are.
float cloud_extinction_bound(vec3 p) {
    float r = length(p);
    if (r < u_ground_layer.y || r < u_ground_layer.z) return ground_layer_extinction(p, r);
    if (r < u_cloud_shell.y + 1e-4) return layer_extinction(p, r, false);
    return cirrus_extinction(p, r);
}
