// Light pollution layer (volume stage, after the atmosphere): the artificial sky glow an
// observer on the ground sees (skydome.night.light_pollution), already including the air's
// extinction, added to what lies behind: frag = behind + glow, exactly behind where the ray
// meets the ground. The uniform glow rises towards the horizon as a homogeneous slab,
// (1 - exp(-tau X(z))) / (1 - exp(-tau X(0))) with X the Kasten-Young air mass; each city adds a
// dome calibrated by Walker's law at 45 deg elevation towards it.
#include "common/camera.glsl"

#define MAX_CITIES 8
uniform sampler2D u_behind;        // light arriving from behind this layer, cd/m^2
uniform vec4 u_lp_zenith;          // channels of the uniform glow at the zenith
uniform float u_tau;               // zenith optical depth of the glow's slab
uniform float u_dip_sin;           // sin of the ground horizon's dip
uniform int u_num_cities;
uniform vec4 u_city[MAX_CITIES];   // (sin az, cos az, luminance at 45 deg, 0)
uniform vec4 u_lp_colour;          // channels per cd/m^2 of the lamp spectrum
uniform float u_kappa;             // azimuthal concentration of a city's dome
uniform float u_eta;               // its fall-off with elevation
out vec4 frag;

// Kasten & Young's (1989) relative air mass at the cosine of the zenith angle.
// twin: skydome.physics.airmass.kasten_young_airmass(np.arccos(cos_z)) cos_z=0..1 CAMERA_MODEL=0
float airmass(float cos_z) {
    float z = acos(clamp(cos_z, 0.0, 1.0));
    return 1.0 / (max(cos_z, 0.0) + 0.50572 * pow(96.07995 - degrees(z), -1.6364));
}

// The glow of a homogeneous slab of zenith optical depth u_tau relative to the zenith.
// twin: skydome.night.light_pollution.slab_profile(np.arccos(cos_z), extinction_mag) cos_z=0..1 CAMERA_MODEL=0
float slab(float cos_z) {
    return (1.0 - exp(-u_tau * airmass(cos_z))) / (1.0 - exp(-u_tau * airmass(1.0)));
}

void main() {
    vec4 behind = texelFetch(u_behind, ivec2(gl_FragCoord.xy), 0);
    frag = behind;
    vec3 dir;
    if (!camera_ray(gl_FragCoord.xy, dir)) return;
    if (dir.z < -u_dip_sin) return;  // the ground: nothing added
    float s = slab(dir.z);
    vec4 glow = u_lp_zenith * s;
    float horiz = length(dir.xy);
    float s45 = slab(0.70710678);
    for (int k = 0; k < MAX_CITIES; ++k) {
        if (k >= u_num_cities) break;
        // cos of the azimuth difference from the horizontal components.
        float cos_da = horiz > 0.0 ? (dir.x * u_city[k].x + dir.y * u_city[k].y) / horiz : 1.0;
        float lobe = exp(u_kappa * (cos_da - 1.0) * horiz);
        float fall = exp(-u_eta * (dir.z - 0.70710678));
        glow += u_lp_colour * (u_city[k].z * s / s45 * lobe * fall);
    }
    frag = behind + glow;
}
