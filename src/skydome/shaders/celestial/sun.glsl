// Sun layer (space stage): the Sun's disk beyond the atmosphere, limb darkened per
// wavelength (Neckel 2005 fits of Neckel & Labs 1994, skydome.celestial.limb_darkening) and
// normalised so that it integrates to the Sun's irradiance; seen through refraction, so a
// low Sun is flattened. The atmosphere layer then multiplies each pixel by the transmittance
// of its own ray, so the lower limb of a setting Sun is redder and dimmer than the upper.
// Output (R, G, B, scotopic) cd/m^2, or the 4 wavelengths of a spectral basis; drawn added.
#include "celestial/disk_pixel.glsl"

uniform vec3 u_sun_direction_true;   // airless, unit ENU
uniform float u_sin_angular_radius;  // sin of the disk's angular radius
uniform float u_sun_scale;           // irradiance in units of the tabulated solar spectrum
uniform mat4 u_spectral_to_rgbs[NUM_GROUPS];
// I(mu)/I(1) = sum_k A_k mu^k; A_k of the 4 wavelengths of group g in u_limb[6 g + k].
uniform vec4 u_limb[6 * NUM_GROUPS];
uniform vec4 u_limb_norm[NUM_GROUPS];  // 1 / integral of I/I(1) over the disk, 1/sr
// A solar eclipse (skydome.astro.eclipses): the Moon's disk hides what lies behind it, and
// the corona shows around the Sun: the K+F corona's radial profile of Baumbach (1937; Allen's
// Astrophysical Quantities, 4th ed., sec. 14.4), in units of the disk's mean radiance
//     B(rho) = 1e-6 (0.0532 rho^-2.5 + 1.425 rho^-7 + 2.565 rho^-17),
// rho the distance from the Sun's centre in solar radii, white (Thomson scattering keeps the
// photosphere's spectrum). u_moon_sin_radius = 0: no Moon in front (then no corona).
uniform vec3 u_moon_direction_true;
uniform float u_moon_sin_radius;
uniform float u_corona_scale;        // 1 / the disk's solid angle (sr^-1), 0 without eclipse
out vec4 frag;

// twin: skydome.astro.eclipses.baumbach_corona(rho) rho=1..6 CAMERA_MODEL=0 NUM_GROUPS=2
float baumbach_corona(float rho) {
    return 1e-6 * (0.0532 * pow(rho, -2.5) + 1.425 * pow(rho, -7.0) + 2.565 * pow(rho, -17.0));
}

// sum_k A_k m_k of the 4 wavelengths of group g: the limb law's polynomial over the moments
// m = (lo, hi) = (mu^0, mu^1, mu^2; mu^3, mu^4, mu^5) of one point, or their sums over a
// pixel's points (the law is linear in them).
vec4 limb_polynomial(int g, vec3 lo, vec3 hi) {
    int k = 6 * g;
    return u_limb[k] * lo.x + u_limb[k + 1] * lo.y + u_limb[k + 2] * lo.z
         + u_limb[k + 3] * hi.x + u_limb[k + 4] * hi.y + u_limb[k + 5] * hi.z;
}

// I(mu)/I(1) of the 4 wavelengths of group g at mu, the cosine of the heliocentric angle.
// twin: skydome.celestial.limb_darkening.limb_darkening(mu, wavelength_nm) mu=0..1 g=0..1 CAMERA_MODEL=0 NUM_GROUPS=2
vec4 limb_darkening(int g, float mu) {
    vec3 lo = vec3(1.0, mu, mu * mu);
    return limb_polynomial(g, lo, mu * mu * mu * lo);
}

// What the point xy of the frame sees, summed over a pixel's points: the disk's powers of mu
// (mu^0..mu^2 in lo, mu^3..mu^5 in hi; mu the cosine of the heliocentric angle) and the
// corona's profile. The radiance is linear in them, so the spectral work (the limb law of
// every wavelength, the groups' matrices) is done once a pixel, not once a point.
void sun_sample(vec2 xy, inout vec3 lo, inout vec3 hi, inout float corona) {
    vec3 true_dir;
    if (!pixel_sees_sphere(xy, u_sun_direction_true, u_sin_angular_radius, true_dir)) {
        if (u_corona_scale <= 0.0 || dot(true_dir, u_sun_direction_true) <= 0.0) return;
        if (ray_meets_sphere(true_dir, u_moon_direction_true, u_moon_sin_radius)) return;
        float rho_c = sin_offset(true_dir, u_sun_direction_true) / u_sin_angular_radius;
        if (rho_c <= 6.0) corona += baumbach_corona(rho_c);
        return;
    }
    if (u_moon_sin_radius > 0.0 && ray_meets_sphere(true_dir, u_moon_direction_true, u_moon_sin_radius)) return;
    // Heliocentric angle: sin(psi) = sin(theta) / sin(alpha) (exact for a sphere).
    float rho = sin_offset(true_dir, u_sun_direction_true) / u_sin_angular_radius;
    float mu = sqrt(max(1.0 - rho * rho, 0.0));
    vec3 powers = vec3(1.0, mu, mu * mu);
    lo += powers;
    hi += mu * mu * mu * powers;
}

void main() {
    int n = int(u_disk_samples + 0.5);
    vec3 lo = vec3(0.0), hi = vec3(0.0);
    float corona = 0.0;
    for (int i = 0; i < n * n; ++i) sun_sample(disk_sample_xy(gl_FragCoord.xy, i, n), lo, hi, corona);
    vec4 radiance = vec4(0.0);
    for (int g = 0; g < NUM_GROUPS; ++g) {
        // the sum over the points of I(mu)/I(1), limb_darkening's polynomial
        vec4 limb = limb_polynomial(g, lo, hi);
        radiance += u_spectral_to_rgbs[g] * (limb * u_limb_norm[g] + vec4(corona * u_corona_scale));
    }
    frag = radiance * (u_sun_scale / float(n * n));
}
