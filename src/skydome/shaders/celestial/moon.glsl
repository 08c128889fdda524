// Moon layer (space stage): the Moon's disk beyond the atmosphere, a sphere lit by the Sun
// from its true direction (so the terminator and the bright limb fall where they are) and by
// the Earth (earthshine on the night side), with the albedo map of maria and highlands
// turned by the libration and the axis position angle. Photometric law: Lommel-Seeliger,
// L = k A mu0 / (mu0 + mu), with k set per phase so the disk integrates to the Moon's
// illuminance of the astronomy (Allen's phase law; skydome.celestial.moon). The earthlit
// side is seen at opposition (the Earth lights it from the observer's side): mu0 = mu.
// Output: the output channels of the Moon's colour (solar spectrum x lunar spectral albedo),
// drawn added; the atmosphere layer applies the transmittance.
#include "celestial/disk_pixel.glsl"
#include "celestial/surface_laws.glsl"

uniform vec3 u_moon_direction_true;   // airless, unit ENU, observer -> Moon centre
uniform float u_sin_angular_radius;
uniform vec3 u_moon_to_sun;           // unit ENU
uniform mat3 u_enu_to_moon;           // ENU -> Moon-fixed (x lon 0, y lon 90 E, z north)
uniform sampler2D u_albedo_map;       // relative albedo: lon -180..180 in s, lat +90..-90 in t
uniform float u_sunlit_scale;         // luminance (cd/m^2) per unit albedo x mu0 / (mu0 + mu)
uniform float u_earthlit_scale;       // luminance (cd/m^2) per unit albedo on the earthlit side
uniform vec4 u_colour;                // output channels per cd/m^2 of the Moon's light
#ifdef LUNAR_ECLIPSE
// A lunar eclipse (skydome.scene.eclipses): each point of the Moon sees the Sun partly or
// wholly behind the Earth (the penumbra and umbra, uniform disks: common/eclipse.glsl), plus
// the sunlight the Earth's atmosphere refracts into the shadow, tabulated against the
// distance from the shadow's axis in output channels per cd/m^2 of uneclipsed moonlight.
#include "common/eclipse.glsl"
uniform vec3 u_ecl_sun_km;            // the Sun's centre from the observer, km, ENU
uniform vec3 u_ecl_earth_km;          // the Earth's centre from the observer, km, ENU
uniform vec3 u_ecl_moon_km;           // the Moon's centre from the observer, km, ENU
uniform vec3 u_ecl_radii_km;          // the Moon's, the Earth's (shadow) and the Sun's radii
uniform float u_ecl_umbra_step_km;    // spacing of the table's distances (from 0)
uniform vec4 u_ecl_umbra[UMBRA_SAMPLES];

// The refracted light's channels at distance d (km) from the shadow's axis.
vec4 umbra_light(float d) {
    float x = d / u_ecl_umbra_step_km;
    int i = int(floor(x));
    if (i >= UMBRA_SAMPLES - 1) return u_ecl_umbra[UMBRA_SAMPLES - 1];
    return mix(u_ecl_umbra[i], u_ecl_umbra[i + 1], x - float(i));
}
#endif
out vec4 frag;

// The Moon seen through the point xy of the frame.
vec4 moon_radiance(vec2 xy) {
    vec3 true_dir;
    if (!pixel_sees_sphere(xy, u_moon_direction_true, u_sin_angular_radius, true_dir)) return vec4(0.0);
    vec3 n = sphere_normal(true_dir, u_moon_direction_true, u_sin_angular_radius);
    float mu = max(dot(n, -true_dir), 0.0);
    float mu0 = dot(n, u_moon_to_sun);
    vec3 m = u_enu_to_moon * n;
    vec2 st = vec2(atan(m.y, m.x) / (2.0 * PI) + 0.5, 0.5 - atan(m.z, length(m.xy)) / PI);
    float albedo = texture(u_albedo_map, st).r;
#ifdef LUNAR_ECLIPSE
    vec3 p = u_ecl_moon_km + u_ecl_radii_km.x * n;   // the point on the Moon, km
    vec3 to_earth = u_ecl_earth_km - p, to_sun = u_ecl_sun_km - p;
    float earth_r = asin(min(u_ecl_radii_km.y / length(to_earth), 1.0));
    float sun_r = asin(min(u_ecl_radii_km.z / length(to_sun), 1.0));
    float sep = small_angle(normalize(to_earth), normalize(to_sun));
    float visible = 1.0 - disk_overlap_fraction(sep, sun_r, earth_r);
    vec3 axis = normalize(u_ecl_earth_km - u_ecl_sun_km);
    vec3 rel = p - u_ecl_earth_km;
    float d = length(rel - dot(rel, axis) * axis);
    vec4 lit = u_colour * visible + umbra_light(d);
    return albedo * (u_sunlit_scale * lommel_seeliger_law(mu0, mu) * lit + u_earthlit_scale * u_colour);
#else
    return u_colour * (albedo * (u_sunlit_scale * lommel_seeliger_law(mu0, mu) + u_earthlit_scale));
#endif
}

void main() {
    int n = int(u_disk_samples + 0.5);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < n * n; ++i) sum += moon_radiance(disk_sample_xy(gl_FragCoord.xy, i, n));
    frag = sum / float(n * n);
}
