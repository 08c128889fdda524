// A solar eclipse's sky: the sunlight a view ray's air scatters, weighted by how much of the
// Sun each point of the ray sees past the Moon (the sky passes multiply the Sun's sky light
// by it; compiled in with HAS_ECLIPSE only). The approximation: the tables' sky radiance
// (every order) times the weight
//     W = int e(s) T(s) v(s) ds / int e(s) T(s) ds
// along the ray from the camera to the top of the air or the ground, e the air's extinction
// coefficient (Rayleigh and aerosol, exponential in height; per output channel, the
// Rayleigh part scaled as lambda^-4 from 550 nm, the aerosol grey), T the transmittance
// back to the camera, v the fraction of the Sun's disk seen from the point (uniform disk,
// common/eclipse.glsl). In totality W is 0 where the ray stays in the umbra (the zenith) and
// grows towards the horizon, where rays reach the sunlit air of the penumbra: the twilight
// ring, reddened where its light crossed the dark air (blue is lost on the way). Multiply scattered light entering the umbra sideways is not modelled beyond what the
// weight gives the tables' own multiple scattering.
// float64 twins: skydome.astro.eclipses.sky_sunlit_weight and sun_visible_at (checked
// through rendered skies in tests/test_solar_eclipse.py)
#include "common/eclipse.glsl"

uniform vec3 u_eclipse_moon_km;         // the Moon's centre from the camera, km, ENU
uniform float u_eclipse_moon_radius_km;
uniform float u_eclipse_sun_radius;     // the Sun's angular radius, rad
uniform float u_eclipse_sky_scale;      // the uneclipsed Sun's scale (u_sun_scale's units)
uniform vec4 u_eclipse_air;             // Rayleigh 1/km, its scale height km, aerosol 1/km, km
uniform vec4 u_eclipse_channels;        // per output channel: Rayleigh extinction / 550 nm's

// Fraction of the Sun's disk (towards sun_dir) seen from x (km from the camera).
float sun_visible_at(vec3 x, vec3 sun_dir) {
    vec3 m = u_eclipse_moon_km - x;
    float d = length(m);
    float moon_radius = asin(min(u_eclipse_moon_radius_km / d, 1.0));
    return 1.0 - disk_overlap_fraction(small_angle(m / d, sun_dir), u_eclipse_sun_radius, moon_radius);
}

// W of the module's comment (per output channel) for the ray from radius r (km) along dir
// (unit ENU, dir.z the cosine of its zenith angle).
vec4 eclipse_sky_weight(float r, vec3 dir, vec3 sun_dir) {
    float mu = dir.z;
    bool ground = ray_hits_ground(r, mu);
    float len = ground ? distance_to_bottom(r, mu) : distance_to_top(r, mu);
    const int N = 32;
    vec4 tau = vec4(0.0), num = vec4(0.0), den = vec4(0.0);
    for (int i = 0; i < N; ++i) {
        float t = (float(i) + 0.5) / float(N);
        float s = len * t * t;                       // denser near the camera
        float ds = len * 2.0 * t / float(N);
        float h = sqrt(max(r * r + 2.0 * r * mu * s + s * s, 0.0)) - u_bottom_radius;
        vec4 e = u_eclipse_channels * (u_eclipse_air.x * exp(-h / u_eclipse_air.y))
               + u_eclipse_air.z * exp(-h / u_eclipse_air.w);
        vec4 w = e * exp(-(tau + 0.5 * e * ds)) * ds;
        tau += e * ds;
        num += w * sun_visible_at(s * dir, sun_dir);
        den += w;
    }
    vec4 v0 = vec4(sun_visible_at(vec3(0.0), sun_dir));
    return mix(v0, num / max(den, vec4(1e-30)), greaterThan(den, vec4(0.0)));
}
