// The sky-view table: the sky seen from one camera position, for one light, by view direction
// (Hillaire 2020's sky-view LUT, here holding Bruneton's phase-free values so that the phase
// functions stay exact per pixel). The camera sits on the z axis at radius u_view_radius (km);
// a direction is (phi, e): phi in [0, pi] the azimuth from the light's (the sky is symmetric
// about the light's vertical plane), e the elevation.
//  x: linear in phi, texel centres at 0 and pi.
//  y: split at the horizon elevation e_h = -acos(Rb / r) like Bruneton's mu mapping, so that
//     sky and ground never interpolate into each other: the upper half holds rays that leave
//     the atmosphere, the lower half rays that hit the ground, each with x = sqrt of the
//     elevation's distance from the horizon (texels crowd at the horizon, where the sky
//     brightens and the ground fades fastest).
uniform vec2 u_sky_view_size;  // texels (phi, elevation)
uniform float u_view_radius;   // km

float horizon_elevation(float r) { return -acos(clamp(u_bottom_radius / r, 0.0, 1.0)); }

// Unit coordinates of a view direction (mu = its z) for a light at azimuth difference phi:
// (phi / pi, x, side) with x the warped distance from the horizon and side +1 above it, -1
// below. Independent of the table size, so a pixel computes them once for all its tables.
vec3 sky_view_unit(float phi, float mu, bool hits_ground) {
    float e = asin(clamp(mu, -1.0, 1.0));
    float e_h = horizon_elevation(u_view_radius);
    float x = hits_ground ? (e_h - e) / (e_h + 0.5 * PI) : (e - e_h) / (0.5 * PI - e_h);
    return vec3(phi / PI, sqrt(clamp(x, 0.0, 1.0)), hits_ground ? -1.0 : 1.0);
}

// Texture coordinates of unit coordinates in a table of `size` (phi, elevation) texels.
vec2 sky_view_texcoords(vec3 unit, vec2 size) {
    return vec2(texcoord_from_unit(unit.x, size.x),
                0.5 + 0.5 * unit.z * texcoord_from_unit(unit.y, 0.5 * size.y));
}

// Azimuth difference phi in [0, pi] between the horizontal parts of dir and light (0 where
// either is vertical: the sky is symmetric about the zenith there).
float azimuth_from_light(vec3 dir, vec3 light) {
    float c = dir.x * light.x + dir.y * light.y;
    float s = abs(dir.x * light.y - dir.y * light.x);
    return atan(s, c + 1e-30);
}

// The view direction of texel (i, j) (integer indices) of a table of `size` texels for a light
// towards `light` (unit, ENU); hits_ground tells which half it is in.
vec3 sky_view_texel_direction(ivec2 texel, vec3 light, vec2 size, out bool hits_ground) {
    float light_az = atan(light.y, light.x + 1e-30);
    float phi = PI * float(texel.x) / (size.x - 1.0);
    float e_h = horizon_elevation(u_view_radius);
    float half_h = 0.5 * size.y;
    float e;
    hits_ground = float(texel.y) < half_h;
    if (hits_ground) {
        float x = (half_h - 1.0 - float(texel.y)) / (half_h - 1.0);
        e = e_h - x * x * (e_h + 0.5 * PI);
    } else {
        float x = (float(texel.y) - half_h) / (half_h - 1.0);
        e = e_h + x * x * (0.5 * PI - e_h);
    }
    float az = light_az + phi;
    return vec3(cos(e) * cos(az), cos(e) * sin(az), sin(e));
}

// ---------------------------------------------------------------- aerial-perspective tables
// The same directions with a third coordinate, the distance d (km) from the camera along the
// ray, as a warped fraction of the ray's own length L in the atmosphere (to the ground or the
// top): x = ln(1 + d / AERIAL_D0) / ln(1 + L / AERIAL_D0). Slices are ~13% apart in distance
// at 64 of them (linear within the first km, where scenes are), so that the in-scattered
// light, ~ 1 - exp(-d / l), interpolates to ~1e-3; and a point on the ground is at x = 1 in
// every direction, so neighbouring directions, whose rays end at different distances, are
// never mixed at different fractions of their rays.
const float AERIAL_D0 = 0.5;  // km
uniform vec3 u_aerial_size;   // texels (phi, elevation, distance)

float aerial_w(float d_km, float ray_length_km) {
    float x = log(1.0 + max(d_km, 0.0) / AERIAL_D0) / log(1.0 + ray_length_km / AERIAL_D0);
    return texcoord_from_unit(clamp(x, 0.0, 1.0), u_aerial_size.z);
}

float aerial_slice_distance(int slice, float ray_length_km) {
    float x = float(slice) / (u_aerial_size.z - 1.0);
    return AERIAL_D0 * (pow(1.0 + ray_length_km / AERIAL_D0, x) - 1.0);
}
