// Scattering density J_{n+1} on the coarse grid (layered: one layer per r), every wavelength
// group at once (location g = group g):
//   J(y, v, s) = integral_{4 pi} [beta_R rho_R(y) P_R(v.w) + beta_M rho_M(y) P_M(v.w)] L_n(y, w) dw
// (seed 004 5.2.2.1; Bruneton 2017 ComputeScatteringDensity), summed over the directions of the
// field pass (atmosphere/precompute_field.glsl), which holds L_n(w) dw for this texel's (r, mu_s).
// The Mie sum is self-normalized, sum P_M(v.w) L dw / sum P_M(v.w) dw: P_M integrates to 1,
// and with g ~ 0.8 its lobe is narrower than the spacing of the directions, so the plain sum
// would depend on where v falls between them; normalized, it is a P_M-weighted mean of L around
// v, exact for smooth L. The Rayleigh phase function is smooth and needs no such care.
// A spectral phase function's lobes (MIE_LOBES) come broadened to g <= MS_MIE_LOBE_G_MAX
// (precompute.py; inputs.broadened_lobe_uniforms merges those that then coincide): the
// directions are ~20 deg apart, and a lobe a few degrees wide (Martian dust's diffraction peak,
// g ~ 0.97) made the weighted mean jump from one direction to the next as v moved (bands in
// the orders >= 2); self-normalized, the broadening keeps the energy.
// The field is mirror-symmetric about the Sun's vertical plane (precompute_field.glsl: azimuth
// N_PHI - 1 - j is azimuth j's mirror image, w' = (w.x, -w.y, w.z)): each of its values is
// fetched once for both directions (PHI_PAIRS pairs; an odd N_PHI's middle azimuth, pi, is its
// own mirror image and counted once).
// With NO_MIE (the layers above the aerosols, where their scattering is negligible beside the
// air's: precompute.py draws those layers apart) J is the Rayleigh sum alone, and that from
// the field's moments: sum (1 + (v.w)^2) L dw = S + v^T M v with S = sum L dw and
// M = sum w w^T L dw: 7 sums per fetched value (those odd in w.y cancel over a mirrored pair)
// for all the views of the fragment, instead of a phase function per view.
// Stored as a logarithm (atmosphere/precomputed_params.glsl).
#include "atmosphere/precompute_common.glsl"

uniform vec4 u_density_size;  // the grid of J (NU, MU_S, MU, R)
uniform sampler2D u_field;  // L dw, x = group * N_DIR + direction, y = r_index * MU_S + mu_s_index

flat in int v_layer;
// NU_PER_FRAGMENT views (nu) per fragment: the field's values of a (r, mu_s) are fetched once
// for all of them (the fetch cost 3/4 of this pass on llvmpipe). This pass draws
// (MU_S * NU / NU_PER_FRAGMENT, MU) texels per layer; output g * NU_PER_FRAGMENT + t holds group
// g at the nu index b * NU_PER_FRAGMENT + t of the fragment's block b (precompute.py reorders).
#ifndef NU_PER_FRAGMENT
#define NU_PER_FRAGMENT 1
#endif
#define NV NU_PER_FRAGMENT
layout(location = 0) out vec4 out_density[NUM_GROUPS * NV];
#define PHI_PAIRS ((N_PHI + 1) / 2)

// 1 where azimuth j has a mirror image of its own, 0 for an odd N_PHI's middle one.
float mirrored(int j) {
#if (N_PHI & 1) == 1
    return 2 * j + 1 == N_PHI ? 0.0 : 1.0;
#else
    return 1.0;
#endif
}

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    int n_mu_s = int(u_density_size.y);
    int block = texel.x / n_mu_s;
    int i_mu_s = texel.x - block * n_mu_s;
    int row = v_layer * n_mu_s + i_mu_s;
    float r, mu, mu_s;
    vec3 v[NV];
    for (int t = 0; t < NV; ++t) {
        float nu;
        bool hits_ground;
        ivec2 full = ivec2((block * NV + t) * n_mu_s + i_mu_s, texel.y);
        scattering_texel_params(full, v_layer, u_density_size, true, r, mu, mu_s, nu, hits_ground);
        v[t] = view_in_frame(mu, mu_s, nu);
    }

#ifdef NO_MIE
    // the field's moments per group: S, then M's xx, yy, zz, xy, xz, yz
    vec4 moment[NUM_GROUPS * 7];
    for (int k = 0; k < NUM_GROUPS * 7; ++k) moment[k] = vec4(0.0);
    for (int a = 0; a < N_MU; ++a) {
        vec2 m = mu_node(a, r);
        float sin_a = safe_sqrt(1.0 - m.x * m.x);
        for (int j = 0; j < PHI_PAIRS; ++j) {
            vec3 w = vec3(sin_a * u_phi_cs[j], m.x);
            int x = a * N_PHI + j;
            // w and its mirror image: the terms odd in w.y cancel, the others double
            float even = 1.0 + mirrored(j), odd = 1.0 - mirrored(j);
            for (int k = 0; k < NUM_GROUPS; ++k) {
                vec4 Lw = texelFetch(u_field, ivec2(k * N_DIR + x, row), 0);
                int o = 7 * k;
                moment[o] += even * Lw;
                moment[o + 1] += (even * w.x * w.x) * Lw;
                moment[o + 2] += (even * w.y * w.y) * Lw;
                moment[o + 3] += (even * w.z * w.z) * Lw;
                moment[o + 4] += (odd * w.x * w.y) * Lw;
                moment[o + 5] += (even * w.x * w.z) * Lw;
                moment[o + 6] += (odd * w.y * w.z) * Lw;
            }
        }
    }
    vec3 d = densities(r - u_bottom_radius);
    for (int k = 0; k < NUM_GROUPS; ++k) {
        int o = 7 * k;
        for (int t = 0; t < NV; ++t) {
            vec3 u = v[t];
            vec4 sum_r = moment[o] + (u.x * u.x) * moment[o + 1] + (u.y * u.y) * moment[o + 2]
                       + (u.z * u.z) * moment[o + 3]
                       + 2.0 * ((u.x * u.y) * moment[o + 4] + (u.x * u.z) * moment[o + 5]
                                + (u.y * u.z) * moment[o + 6]);
            out_density[k * NV + t] =
                to_log(u_rayleigh_scattering[k] * (d.x * 3.0 / (16.0 * PI)) * sum_r);
        }
    }
#else
#ifndef MIE_LOBES
    float g = u_mie_g;
    float gg = 1.0 + g * g;
    float norm_m[NV];
    for (int t = 0; t < NV; ++t) norm_m[t] = 0.0;
#else
    vec4 norm_m[NUM_GROUPS * NV];  // a spectral phase function: one normalization per wavelength
    for (int k = 0; k < NUM_GROUPS * NV; ++k) norm_m[k] = vec4(0.0);
#endif
    vec4 sum_r[NUM_GROUPS * NV];
    vec4 sum_m[NUM_GROUPS * NV];
    for (int k = 0; k < NUM_GROUPS * NV; ++k) {
        sum_r[k] = vec4(0.0);
        sum_m[k] = vec4(0.0);
    }
    for (int a = 0; a < N_MU; ++a) {
        vec2 m = mu_node(a, r);
        float sin_a = safe_sqrt(1.0 - m.x * m.x);
        float w_a = m.y * (2.0 * PI / float(N_PHI));
        for (int j = 0; j < PHI_PAIRS; ++j) {
            vec3 w = vec3(sin_a * u_phi_cs[j], m.x);
            int x = a * N_PHI + j;
            float twin = mirrored(j);
            vec4 Lw[NUM_GROUPS];
            for (int k = 0; k < NUM_GROUPS; ++k)
                Lw[k] = texelFetch(u_field, ivec2(k * N_DIR + x, row), 0);
            for (int t = 0; t < NV; ++t) {
                // the cosines with w and with its mirror image (w.y negated)
                float c = dot(v[t], w);
                float c2 = c - 2.0 * v[t].y * w.y;
                float pr = 1.0 + c * c + twin * (1.0 + c2 * c2);
#ifndef MIE_LOBES
                // Cornette-Shanks without its constant factor (it cancels in the normalization).
                float ix = inversesqrt(max(gg - 2.0 * g * c, 1e-8));
                float ix2 = inversesqrt(max(gg - 2.0 * g * c2, 1e-8));
                float pm = (1.0 + c * c) * ix * ix * ix + twin * (1.0 + c2 * c2) * ix2 * ix2 * ix2;
                norm_m[t] += pm * w_a;
#endif
                for (int k = 0; k < NUM_GROUPS; ++k) {
                    int o = k * NV + t;
                    sum_r[o] += pr * Lw[k];
#ifdef MIE_LOBES
                    vec4 pm = mie_phase_group(c, k) + twin * mie_phase_group(c2, k);
                    norm_m[o] += pm * w_a;
#endif
                    sum_m[o] += pm * Lw[k];
                }
            }
        }
    }
    vec3 d = densities(r - u_bottom_radius);
    for (int k = 0; k < NUM_GROUPS; ++k) {
        for (int t = 0; t < NV; ++t) {
            int o = k * NV + t;
            out_density[o] = to_log(u_rayleigh_scattering[k] * (d.x * 3.0 / (16.0 * PI)) * sum_r[o]
#ifndef MIE_LOBES
                                    + u_mie_scattering[k] * (d.y / max(norm_m[t], 1e-30)) * sum_m[o]);
#else
                                    + u_mie_scattering[k] * (d.y / max(norm_m[o], vec4(1e-30))) * sum_m[o]);
#endif
        }
    }
#endif
}
