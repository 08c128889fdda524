// The split sum's second factor (skydome.lighting_ibl; Karis 2013, IntegrateBRDF): for
// n.v = (x + 0.5) / width and roughness = (y + 0.5) / height (GL row y), the scale and the
// bias of F0 in the specular reflectance of a GGX surface lit by a uniform white sky,
//     int f(l, v) (n.l) dl = F0 scale + bias,
//     scale = mean (1 - Fc) G_vis,  bias = mean Fc G_vis,  Fc = (1 - v.h)^5,
//     G_vis = G (v.h) / ((n.h)(n.v)),
// over SAMPLES half vectors drawn from D(n.h)(n.h) (Hammersley), with Karis' Schlick-GGX
// visibility (k = alpha / 2, alpha = roughness^2; lighting/ggx.glsl).
// Float64 twin: an independent quadrature in tests/test_lighting_ibl.py.
#include "lighting/ggx.glsl"

uniform vec2 u_size;   // table size (n.v columns, roughness rows)
out vec4 frag;

void main() {
    float nov = gl_FragCoord.x / u_size.x;
    float roughness = gl_FragCoord.y / u_size.y;
    float alpha = roughness * roughness;
    vec3 v = vec3(sqrt(1.0 - nov * nov), 0.0, nov);
    vec3 n = vec3(0.0, 0.0, 1.0);
    float a = 0.0;
    float b = 0.0;
    for (uint i = 0u; i < uint(SAMPLES); ++i) {
        vec3 h = importance_sample_ggx(hammersley(i, uint(SAMPLES)), alpha, n);
        float voh = dot(v, h);
        vec3 l = 2.0 * voh * h - v;
        float nol = l.z;
        float noh = h.z;
        if (nol > 0.0 && voh > 0.0) {
            float g_vis = g_smith_schlick(nov, nol, alpha) * voh / (noh * nov);
            float fc = pow(1.0 - voh, 5.0);
            a += (1.0 - fc) * g_vis;
            b += fc * g_vis;
        }
    }
    frag = vec4(a / float(SAMPLES), b / float(SAMPLES), 0.0, 1.0);
}
