// The GGX (Trowbridge-Reitz) microfacet lobe of the split-sum image-based lighting
// (skydome.lighting_ibl; Karis 2013, "Real Shading in Unreal Engine 4"): its normal
// distribution, Karis' Schlick-GGX visibility for image lighting, the Hammersley points and
// the lobe's importance sampling. alpha = roughness^2 (Burley's perceptual roughness).
// Float64 twins: skydome.physics.ggx.
#include "common/constants.glsl"

// GGX normal distribution D(n.h) (sr^-1): alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2).
// twin: skydome.physics.ggx.d_ggx(noh, alpha) noh=0..1 alpha=0.05..1
float d_ggx(float noh, float alpha) {
    float a2 = alpha * alpha;
    float d = noh * noh * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// Smith's G with Schlick's G1 = x / (x (1 - k) + k), k = alpha / 2 (Karis' choice for image
// lighting), at n.v and n.l.
// twin: skydome.physics.ggx.g_smith_schlick(nov, nol, alpha) nov=0.01..1 nol=0.01..1 alpha=0.05..1
float g_smith_schlick(float nov, float nol, float alpha) {
    float k = 0.5 * alpha;
    return nov / (nov * (1.0 - k) + k) * (nol / (nol * (1.0 - k) + k));
}

// The i-th of n Hammersley points in [0, 1)^2: (i / n, the base-2 radical inverse of i).
vec2 hammersley(uint i, uint n) {
    uint b = i;
    b = (b << 16u) | (b >> 16u);
    b = ((b & 0x55555555u) << 1u) | ((b & 0xAAAAAAAAu) >> 1u);
    b = ((b & 0x33333333u) << 2u) | ((b & 0xCCCCCCCCu) >> 2u);
    b = ((b & 0x0F0F0F0Fu) << 4u) | ((b & 0xF0F0F0F0u) >> 4u);
    b = ((b & 0x00FF00FFu) << 8u) | ((b & 0xFF00FF00u) >> 8u);
    return vec2(float(i) / float(n), float(b) * 2.3283064365386963e-10);
}

// A half vector drawn from D(n.h) (n.h) around the unit normal n (Karis' ImportanceSampleGGX,
// his tangent frame: up = +z unless n is within 2.6 deg of it, then +x).
vec3 importance_sample_ggx(vec2 xi, float alpha, vec3 n) {
    float phi = 2.0 * PI * xi.x;
    float cos_t = sqrt((1.0 - xi.y) / (1.0 + (alpha * alpha - 1.0) * xi.y));
    float sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    vec3 up = abs(n.z) < 0.999 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
    vec3 tx = normalize(cross(up, n));
    vec3 ty = cross(n, tx);
    return tx * (sin_t * cos(phi)) + ty * (sin_t * sin(phi)) + n * cos_t;
}
