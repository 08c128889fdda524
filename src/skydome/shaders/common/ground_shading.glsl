// The light on a surface from the precomputed tables, and the one Lambertian ground shading
// used wherever the ground is drawn or probed (atmosphere/surface_radiance.glsl, atmosphere/precompute_probe.glsl):
// albedo(λ) (E_sun + E_sky)(λ) / pi per wavelength group, seen through the air, then
// converted to (R, G, B, scotopic). sun_and_sky_irradiance (Bruneton 2017
// GetSunAndSkyIrradiance) sums the same per-group irradiances.
//
// Units: positions in km, planet centred; irradiance per unit solar irradiance per group
// (dimensionless), luminance results in lx and cd/m^2 as in atmosphere/precomputed_lookup.glsl.
#include "atmosphere/precomputed_lookup.glsl"

// What the irradiance of every group needs of a surface at `point` with unit `normal` lit from
// `light` (unit), computed once: the direct part's factor (visible fraction of the disk x
// cosine) and column densities to the top towards the light (km), and where to read the sky
// irradiance table with its factor, the view factor of the sky for a tilted surface
// (1 + n.z) / 2 times the cut-off fade (Bruneton 2017 GetSunAndSkyIrradiance).
struct SurfaceLight {
    float sun_factor;
    vec3 sun_column;
    IrradianceCoords sky_coords;
    float sky_factor;
};

SurfaceLight surface_light(vec3 point, vec3 normal, vec3 light) {
    float r = length(point);
    float mu_s = clamp_cosine(dot(point, light) / r);
    float f = sun_visible_fraction(r, mu_s) * max(dot(normal, light), 0.0);
    // no column where no direct light arrives (the ray towards the light may hit the ground)
    vec3 column = f > 0.0 ? column_to_top(r, mu_s) : vec3(0.0);
    return SurfaceLight(f, column, irradiance_coords(r, mu_s, u_irradiance_size),
                        sun_cutoff_fade(mu_s) * (0.5 + 0.5 * dot(normal, point) / r));
}

// Direct irradiance of wavelength group g: transmittance to the light x the factor.
vec4 sun_irradiance_group(int g, SurfaceLight s) {
    return s.sun_factor * exp(-optical_depth(g, s.sun_column));
}

// Sky irradiance of wavelength group g (every order, from the spectral irradiance table).
vec4 sky_irradiance_group(int g, SurfaceLight s) {
    return exp(irradiance_fetch(u_irradiance_spectral, s.sky_coords, g, NUM_GROUPS)) * s.sky_factor;
}

// Radiance (R, G, B, scotopic; cd/m^2 at unit scale) of the Lambertian ground at `point`
// (km, on the ground sphere) with unit `normal`, lit by `light` (and by the sky when
// `with_sky`), seen through column densities `column` (km) from the camera:
// sum over groups of u_spectral_to_rgbs x albedo / pi x (E_sun + E_sky) x T.
vec4 lambertian_ground(vec3 point, vec3 normal, vec3 light, vec3 column, bool with_sky) {
    SurfaceLight s = surface_light(point, normal, light);
    vec4 radiance = vec4(0.0);
    for (int g = 0; g < NUM_GROUPS; ++g) {
        vec4 e = sun_irradiance_group(g, s);
        if (with_sky) e += sky_irradiance_group(g, s);
        radiance += u_spectral_to_rgbs[g] * (u_ground_albedo[g] * INV_PI * e * exp(-optical_depth(g, column)));
    }
    return radiance;
}

// Direct Sun and sky irradiance (luminance: R, G, B with Y = illuminance in lx, scotopic lx)
// on a surface at `point` (km) with unit `normal`: the per-group irradiances of
// lambertian_ground, converted. Returns the Sun's, writes the sky's.
vec4 sun_and_sky_irradiance(vec3 point, vec3 normal, vec3 sun_direction, out vec4 sky_irradiance) {
    SurfaceLight s = surface_light(point, normal, sun_direction);
    vec4 sun = vec4(0.0);
    sky_irradiance = vec4(0.0);
    for (int g = 0; g < NUM_GROUPS; ++g) {
        sun += u_spectral_to_rgbs[g] * sun_irradiance_group(g, s);
        sky_irradiance += u_spectral_to_rgbs[g] * sky_irradiance_group(g, s);
    }
    return sun;
}
