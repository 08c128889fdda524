// The clouds' light model (float64 twin: skydome.reference.cloud_slab, which derives it):
// single scattering of the unscattered beam, the beam's forward peak scattered again, and the
// delta-Eddington two-stream diffuse field of a conservative local slab (Joseph, Wiscombe &
// Weinman 1976; Meador & Weaver 1980 Eddington coefficients at albedo 1, closed form).
// Optical depths are dimensionless; results are per unit irradiance (1/sr).
#include "common/phase_functions.glsl"

// The cloud phase function (1/sr; skydome.clouds.phase.RENDER_PHASE: the droplets' Mie phase
// function, its diffraction peak cut), tabulated at CLOUD_PHASE_TEXELS angles uniform from 0
// to 180 deg, linear in the angle (the texture's filtering; its twin TabulatedPhase.value).
uniform sampler2D u_cloud_phase_table;
uniform vec3 u_cloud_moments;  // (g, f = second moment, g' = (g - f) / (1 - f))

float cloud_phase(float nu) {
    float x = acos(clamp(nu, -1.0, 1.0)) / PI * float(CLOUD_PHASE_TEXELS - 1);
    return texture(u_cloud_phase_table, vec2((x + 0.5) / float(CLOUD_PHASE_TEXELS), 0.5)).r;
}

// Rain's phase function per output channel, the same way (skydome.clouds.phase.
// rain_channel_phases: its drops' rays by geometric optics at each wavelength, weighted as
// sunlight's share of each channel: the rainbows' colours); snow scatters as cloud_phase.
uniform sampler2D u_rain_phase_table;

vec4 rain_phase(float nu) {
    float x = acos(clamp(nu, -1.0, 1.0)) / PI * float(CLOUD_PHASE_TEXELS - 1);
    return texture(u_rain_phase_table, vec2((x + 0.5) / float(CLOUD_PHASE_TEXELS), 0.5));
}

// The droplets' per output channel (skydome.clouds.phase.droplet_channel_phases: their Mie
// phase function by wavelength, each channel normalised as cloud_phase): single scattering
// takes its colours from it (the cloudbow's and fogbow's rims, the glory's rings), the
// orders >= 2 stay grey.
uniform sampler2D u_droplet_phase_table;

vec4 droplet_phase(float nu) {
    float x = acos(clamp(nu, -1.0, 1.0)) / PI * float(CLOUD_PHASE_TEXELS - 1);
    return texture(u_droplet_phase_table, vec2((x + 0.5) / float(CLOUD_PHASE_TEXELS), 0.5));
}

#ifdef FOG_PHASE
// The fog's droplets' own per output channel (droplet_channel_phases for their effective
// radius, not the clouds'): the fogbow's width and radius follow their size.
uniform sampler2D u_fog_phase_table;

vec4 fog_phase(float nu) {
    float x = acos(clamp(nu, -1.0, 1.0)) / PI * float(CLOUD_PHASE_TEXELS - 1);
    return texture(u_fog_phase_table, vec2((x + 0.5) / float(CLOUD_PHASE_TEXELS), 0.5));
}
#else
vec4 fog_phase(float nu) { return droplet_phase(nu); }
#endif

#ifdef HALOS
// The cirrus crystals' phase function per output channel (1/sr; skydome.clouds.halos.
// halo_table, for the key light's elevation): over the direction seen `d`, by its elevation
// (y: -90 to 90 deg) and its azimuth from the light's (x: 0 to 180 deg) about the local
// vertical `up` (the crystals float level with it): halos, sun dogs, arcs.
uniform sampler2D u_halo_table;

vec4 halo_phase(vec3 d, vec3 light, vec3 up) {
    float sin_el = clamp(dot(d, up), -1.0, 1.0);
    vec3 across = d - sin_el * up, light_across = light - dot(light, up) * up;
    float sine = length(cross(across, light_across)), cosine = dot(across, light_across);
    float azimuth = sine + abs(cosine) > 1e-12 ? atan(sine, cosine) : 0.0;
    return texture(u_halo_table, vec2(azimuth / PI, asin(sin_el) / PI + 0.5));
}
#endif

// (I0, I1) of the diffuse field at scaled depth tau below the top of a slab of scaled
// thickness tau_total lit at its top by a beam of cosine mu0 (unit irradiance normal to it),
// over a ground of albedo A: the net flux F_up - F_down = mu0 exp(-tau/mu0) + c1 is constant
// but for the beam, F_up + F_down = a exp(-tau/mu0) + 2 gamma c1 tau + c2.
vec2 direct_field(float tau, float tau_total, float mu0, float g_scaled, float albedo) {
    float gamma = 0.75 * (1.0 - g_scaled);
    float gamma3 = (2.0 - 3.0 * g_scaled * mu0) * 0.25;
    float a = -mu0 * (2.0 * gamma * mu0 + 1.0 - 2.0 * gamma3);
    float e_total = exp(-tau_total / mu0);
    float c1 = (1.0 - albedo) * (a * (1.0 - e_total) - mu0 * (1.0 + e_total))
             / (2.0 + 2.0 * gamma * tau_total * (1.0 - albedo));
    float c2 = mu0 + c1 - a;
    float e = exp(-tau / mu0);
    float net = mu0 * e + c1;
    float total = a * e + 2.0 * gamma * c1 * tau + c2;
    return vec2(total / (2.0 * PI), 3.0 * net / (4.0 * PI));
}

// The same per unit diffuse (isotropic) irradiance on the slab's top.
vec2 diffuse_field(float tau, float tau_total, float g_scaled, float albedo) {
    float gamma = 0.75 * (1.0 - g_scaled);
    float c1 = -2.0 * (1.0 - albedo) / (2.0 + 2.0 * gamma * tau_total * (1.0 - albedo));
    return vec2((2.0 * gamma * c1 * tau + 2.0 + c1) / (2.0 * PI), 3.0 * c1 / (4.0 * PI));
}

// The source of every order >= 2 from the Monte Carlo table (skydome.clouds.ms_table, built by
// tools/build_cloud_ms_table.py; its NumPy twin ms_source interpolates the same way): per
// (scattered direction's upward cosine: a block of 24 depth texels in x), (depth in the slab,
// optical thickness, light cosine) interpolated bilinearly in depth and light cosine at each
// thickness node, RGB = the cosine Fourier coefficients in the azimuth from the light's of
// J2 / h, h = HG(cos theta, u_ms_norm_g[node]) the orders' peak around the beam's direction;
// the two thickness nodes' J2 interpolated linearly.
uniform sampler3D u_cloud_ms_table;  // (12 x 24, 19, 12)
uniform float u_ms_norm_g[19];
const float MS_MU[12] = float[12](-1.0, -0.85, -0.65, -0.45, -0.25, -0.08, 0.08, 0.25, 0.45,
                                  0.65, 0.85, 1.0);

vec3 ms_coefficients(int mu_index, float x, int tau_index, float z) {
    return texture(u_cloud_ms_table, vec3((float(mu_index) * 24.0 + x + 0.5) / 288.0,
                                          (float(tau_index) + 0.5) / 19.0, (z + 0.5) / 12.0)).rgb;
}

float ms_source(float tau_top, float tau_total, float mu0, float mu_up, float cos_phi) {
    mu0 = clamp(mu0, 0.02, 1.0);  // the table's range (the peak shape's too)
    float u = clamp(tau_top / max(tau_total, 1e-6), 0.0, 1.0);
    float x = clamp(acos(1.0 - 2.0 * u) / PI * 24.0 - 0.5, 0.0, 23.0);
    // thickness: 2 nodes per doubling from 0.25; light: uniform in its zenith angle
    float y = clamp(2.0 * (log2(max(tau_total, 1e-6)) + 2.0), 0.0, 18.0);
    float z = clamp(11.0 * (1.0 - acos(mu0) / acos(0.02)), 0.0, 11.0);
    int iy = min(int(y), 17);
    float fy = y - float(iy);
    float m = clamp(mu_up, -1.0, 1.0);
    int i = 0;
    while (i < 10 && MS_MU[i + 1] < m) ++i;
    float w = clamp((m - MS_MU[i]) / (MS_MU[i + 1] - MS_MU[i]), 0.0, 1.0);
    // the scattering angle from the beam in the slab (the table's geometry)
    float cos_theta = -m * mu0 - sqrt(max(1.0 - m * m, 0.0)) * sqrt(max(1.0 - mu0 * mu0, 0.0)) * cos_phi;
    float j2 = 0.0;
    for (int k = 0; k < 2; ++k) {
        int node = iy + k;
        vec3 c = mix(ms_coefficients(i, x, node, z), ms_coefficients(i + 1, x, node, z), w);
        float series = c.x + c.y * cos_phi + c.z * (2.0 * cos_phi * cos_phi - 1.0);
        j2 += (k == 0 ? 1.0 - fy : fy) * henyey_greenstein_phase(cos_theta, u_ms_norm_g[node]) * series;
    }
    float thin = min(tau_total / 0.25, 1.0);  // orders >= 2 vanish linearly in thin slabs
    return max(j2, 0.0) * thin;
}

// The source J (1/sr) per unit of the light's irradiance and per unit of the sky's diffuse
// irradiance (returned as x and y) at a point with slant optical depth tau_s towards the
// light and tau_below across its local slab (the slab's top faces the light: tau_top =
// tau_s mu0), for light scattered towards upward cosine mu_up (to the slab's normal) at
// phase-angle cosine nu and azimuth cosine cos_phi from the light's, over a ground of
// `albedo`: the exact single scattering, the table's orders >= 2 (a black ground), the
// ground's reflected light as the two-stream field adds it, and the sky's two-stream field.
vec2 cloud_source(float tau_s, float tau_below, float mu0, float mu_up, float nu, float cos_phi,
                  float albedo) {
    float g = u_cloud_moments.x, f = u_cloud_moments.y, gs = u_cloud_moments.z;
    float k = 1.0 - f;
    float tau_top = tau_s * mu0;
    float tau_total = tau_top + tau_below;
    float j = cloud_phase(nu) * exp(-tau_s) + ms_source(tau_top, tau_total, mu0, mu_up, cos_phi);
    if (albedo > 0.0) {
        vec2 lit = direct_field(k * tau_top, k * tau_total, mu0, gs, albedo)
                 - direct_field(k * tau_top, k * tau_total, mu0, gs, 0.0);
        j += lit.x + g * mu_up * lit.y;
    }
    vec2 sky = diffuse_field(k * tau_top, k * tau_total, gs, albedo);
    return vec2(j, sky.x + g * mu_up * sky.y);
}
