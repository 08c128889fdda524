// Night vision: the eye's adaptation state, shared by the passes of skydome.display.night_vision
// (float64 twin: skydome/reference/night_vision.py; constants there, passed in as defines).
//
//   photopic adaptation L_p: the uniform u_adaptation (cd/m^2), or with ADAPTATION_FROM_TEXTURE
//     the log-average luminance of skydome.display.gpu_exposure read from its 1 x 1 mip level
//     (as post/tonemap.glsl does with AUTO_EXPOSURE: no read-back);
//   scotopic adaptation L_s = L_p * (S/P), the S/P ratio of the frame from the 1 x 1 level of
//     post/night_log_luminance.glsl's grid;
//   m: CIE 191:2010 MES2, fixed-point iteration from m0 = 0.5 (see mesopic_coefficient).
#ifndef NV_DELTA
#error "define the NV_* constants (skydome.display.night_vision)"
#endif

uniform sampler2D u_nv_log_luminance;   // post/night_log_luminance.glsl grid, mipmapped
uniform float u_nv_log_luminance_level; // its 1 x 1 level
#ifdef ADAPTATION_FROM_TEXTURE
uniform sampler2D u_log_luminance;      // GpuExposure.texture
uniform float u_log_luminance_level;
uniform float u_delta;
float photopic_adaptation() {
    vec2 s = textureLod(u_log_luminance, vec2(0.5), u_log_luminance_level).rg;
    return s.g > 0.0 ? max(exp(s.r / s.g) - u_delta, u_delta) : u_delta;
}
#else
uniform float u_adaptation;             // photopic adaptation luminance, cd/m^2
float photopic_adaptation() { return u_adaptation; }
#endif

// S/P ratio of the frame: log-average scotopic over log-average photopic luminance, each
// exp(mean ln(delta + L)) - delta as Reinhard et al. 2002 eq. 1 with its bias removed
// (skydome.display.exposure), so a flat field gives its own S/P exactly.
float frame_sp_ratio() {
    vec3 s = textureLod(u_nv_log_luminance, vec2(0.5), u_nv_log_luminance_level).rgb;
    if (!(s.b > 0.0)) return 1.0;
    float lp = max(exp(s.r / s.b) - NV_DELTA, NV_DELTA);
    float ls = max(exp(s.g / s.b) - NV_DELTA, NV_DELTA);
    return ls / lp;
}

// CIE 191:2010 MES2: L_mes = (m L_p + (1 - m) L_s V'(555)) / (m + (1 - m) V'(555)),
// m = a + b log10(L_mes) clamped to [0, 1], iterated from m = 0.5 until it settles (the map
// contracts for S/P < 18, Li et al. 2018, Opt. Express 26, 31351).
float mesopic_coefficient(float lp, float ls) {
    float m = 0.5;
    for (int i = 0; i < NV_MES2_ITERATIONS; ++i) {
        float lmes = (m * lp + (1.0 - m) * ls * NV_V_PRIME_555) / (m + (1.0 - m) * NV_V_PRIME_555);
        float next = clamp(NV_MES2_A + NV_MES2_B * log(max(lmes, 1e-30)) * 0.434294481903252,
                           0.0, 1.0);
        if (abs(next - m) < 1e-7) { m = next; break; }
        m = next;
    }
    return m;
}

struct Adaptation { float lp; float ls; float m; };

Adaptation adaptation_state() {
    Adaptation a;
    a.lp = photopic_adaptation();
    a.ls = a.lp * frame_sp_ratio();
    a.m = mesopic_coefficient(a.lp, a.ls);
    return a;
}
