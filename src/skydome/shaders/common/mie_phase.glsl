// The aerosol's phase function (sr^-1), nu = cosine of the scattering angle: Cornette-Shanks of
// u_mie_g at every wavelength, or with MIE_LOBES (atmosphere/uniforms.py, phase_defines) a
// spectral one, sum_j w_j(lambda) HG(nu, g_j) (atmosphere/phase.py, MiePhaseLobes).
//   mie_phase_group(nu, g):   per wavelength of group g (the precomputation, spectral passes);
//   mie_phase_channels(nu):   per output channel (R, G, B, scotopic) of the single-Mie tables:
//     the lobes' weights averaged over each channel's response to the Mie scattering spectrum,
//     sum_g M_g (beta_M,g w_j,g) / sum_g M_g beta_M,g with M_g = u_spectral_to_rgbs[g] (the sum
//     is linear in the weights, so this is the channel's own phase function for light of the
//     solar spectrum scattered once; the tables' transmittance colours it slightly).
#include "common/phase_functions.glsl"
#include "common/spectral.glsl"

#ifdef MIE_LOBES
uniform float u_mie_lobe_g[MIE_LOBES];
uniform vec4 u_mie_lobe_weight[NUM_GROUPS * MIE_LOBES];  // group-major: [g * MIE_LOBES + j]

// MIE_LOBE_G_VALUES (the caller's literals) makes the lobes' g compile-time constants (a g of 0
// folds to a constant lobe; Mars's density pass of the orders >= 2 -8 % on llvmpipe).
#ifdef MIE_LOBE_G_VALUES
const float MIE_LOBE_G[MIE_LOBES] = float[MIE_LOBES](MIE_LOBE_G_VALUES);
#else
#define MIE_LOBE_G u_mie_lobe_g
#endif

// twin: skydome.atmosphere.phase.MiePhaseLobes.phase(nu, wavelengths_nm) nu=-1..1 g=0..1 NUM_GROUPS=2
vec4 mie_phase_group(float nu, int g) {
    vec4 p = vec4(0.0);
    for (int j = 0; j < MIE_LOBES; ++j)
        p += u_mie_lobe_weight[g * MIE_LOBES + j] * henyey_greenstein_phase(nu, MIE_LOBE_G[j]);
    return p;
}

vec4 mie_phase_channels(float nu) {
    vec4 num = vec4(0.0);
    vec4 den = vec4(0.0);
    for (int g = 0; g < NUM_GROUPS; ++g) {
        num += u_spectral_to_rgbs[g] * (u_mie_scattering[g] * mie_phase_group(nu, g));
        den += u_spectral_to_rgbs[g] * u_mie_scattering[g];
    }
    return num / max(den, vec4(1e-30));
}
#else
vec4 mie_phase_group(float nu, int g) { return vec4(cornette_shanks_phase(nu, u_mie_g)); }
vec4 mie_phase_channels(float nu) { return vec4(cornette_shanks_phase(nu, u_mie_g)); }
#endif
