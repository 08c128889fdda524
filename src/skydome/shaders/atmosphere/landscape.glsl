// Landscape layer (volume stage, the last): a panorama of the horizon (hills, trees,
// buildings) in front of the sky. Its pixels are Lambertian reflectances (the texture is
// sRGB: sampling gives linear values) lit as the level ground at the camera is, by the Sun
// (or the second light) and the sky (common/ground_shading.glsl, per wavelength group), at
// u_landscape_km from the camera and seen through the air between (aerial perspective from
// the 4D tables): frag = mix(behind, in-scattered + T x landscape, coverage).
// The panorama is equirect: u = azimuth / 2 pi from north through east (north at the left
// edge, as skydome's own equirect maps), v = 0.5 + elevation / pi (the horizon the middle).
#include "common/camera.glsl"
#include "common/behind.glsl"
#include "atmosphere/surface_radiance.glsl"

uniform vec3 u_camera_position;   // km, planet centred, ENU axes of the observer
uniform vec3 u_sun_direction;     // unit, ENU
uniform float u_sun_scale;
uniform vec3 u_light2_direction;
uniform vec4 u_light2_scale;
uniform sampler2D u_landscape;    // RGB: linear reflectance, A: coverage (0: the sky shows)
uniform float u_landscape_km;     // how far the landscape stands
uniform float u_landscape_lod;    // mip level: log2 of the texels a frame pixel spans
out vec4 frag;

// The light a level Lambertian surface at the camera's ground reflects per unit albedo
// (cd/m^2 per output channel): (E_light + E_sky) / pi for each light, at its scale.
vec4 landscape_light(vec3 ground) {
    vec3 up = normalize(ground);
    vec4 sky;
    vec4 e = u_sun_scale * sun_and_sky_irradiance(ground, up, u_sun_direction, sky);
    e += u_sun_scale * sky;
    vec4 sky2;
    vec4 e2 = sun_and_sky_irradiance(ground, up, u_light2_direction, sky2);
    e += u_light2_scale * (e2 + sky2);
    return e * INV_PI;
}

void main() {
    vec4 behind = light_behind(gl_FragCoord.xy);
    frag = behind;
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) return;
    float azimuth = atan(dir.x, dir.y);  // from north through east
    vec2 uv = vec2(fract(azimuth / (2.0 * PI)), 0.5 + asin(clamp(dir.z, -1.0, 1.0)) / PI);
    // an explicit level (the camera's pixel over the texel): the seam of the azimuth and a
    // direction map's unrelated neighbours would fool the derivatives
    vec4 land = textureLod(u_landscape, uv, u_landscape_lod);
    if (land.a <= 0.0) return;
    float r = length(u_camera_position);
    vec3 ground = u_camera_position * (u_bottom_radius / r);
    vec4 reflectance = vec4(land.rgb, dot(land.rgb, vec3(0.2126, 0.7152, 0.0722)));
    vec4 radiance = reflectance * landscape_light(ground);
    // Through the air: what it scatters in front, and what it lets through, along the ray
    // to the panorama's cylinder. Below the camera's horizon the panorama is the ground in
    // front: as far as the ray meets it (up to the cylinder), but through air looked up
    // along the horizon's direction of that azimuth (the tables' two halves, the rays that
    // leave the air and those that meet the ground, do not join seamlessly at the horizon:
    // a seam would show across the panorama).
    float mu_min = -safe_sqrt(1.0 - (u_bottom_radius / r) * (u_bottom_radius / r)) + 1e-3;
    float mu_ray = clamp_cosine(dot(u_camera_position, dir) / r);
    vec3 air_dir = dir;
    float reach = u_landscape_km;
    if (mu_ray < mu_min && length(dir.xy) > 0.0) {
        air_dir = vec3(normalize(dir.xy) * sqrt(1.0 - mu_min * mu_min), mu_min);
        reach = min(reach, distance_to_bottom(r, mu_ray));
    }
    vec3 point = u_camera_position + air_dir * reach;
    vec4 air = u_sun_scale * sky_radiance_to_point(u_camera_position, point, 0.0, u_sun_direction)
             + u_light2_scale * sky_radiance_to_point(u_camera_position, point, 0.0, u_light2_direction);
    float mu = clamp_cosine(dot(u_camera_position, air_dir) / r);
    bool hits_ground = ray_hits_ground(r, mu);
    float d = min(reach, ray_length(r, mu, hits_ground));
    vec3 t = transmittance_rgb(column_along_ray(r, mu, d, hits_ground));
    vec4 seen = air + vec4(t, t.g) * radiance;
    frag = mix(behind, seen, clamp(land.a, 0.0, 1.0));
}
