// Paths through the clouds' shells (clouds/cloud_density.glsl): the part of a ray inside a
// shell, optical depths along a path, the transmittance towards a light. Shared by the march
// (clouds/clouds_march.glsl), the light shafts (clouds/cloud_shafts.glsl) and the shadow query
// (clouds/cloud_shadow_query.glsl). Needs ray_sphere (common/atmosphere_common.glsl).
#include "clouds/cloud_density.glsl"

// The part [t0, t1] of the ray from o along unit d inside the shell between radii r_lo and
// r_hi (km), before the ground at t_ground; false if none.
bool shell_segment(vec3 o, vec3 d, float r_lo, float r_hi, float t_ground, out vec2 seg) {
    vec2 outer = ray_sphere(o, d, r_hi);
    if (outer.y <= 0.0) return false;
    float t0 = max(outer.x, 0.0), t1 = outer.y;
    vec2 inner = ray_sphere(o, d, r_lo);
    if (inner.y > 0.0) {
        if (length(o) < r_lo) t0 = max(t0, inner.y);  // below: from where it leaves the inner sphere
        else t1 = min(t1, inner.x);                   // above or inside: until it meets it
    }
    t1 = min(t1, t_ground);
    seg = vec2(t0, t1);
    return t1 > t0;
}

// Optical depth from p along unit d over `length_km`, `n` steps growing geometrically
// (samples at each step's middle; exact for a uniform medium).
float optical_depth_along(vec3 p, vec3 d, float length_km, int n, bool geometric) {
    float tau = 0.0, t = 0.0;
    float total = geometric ? float((1 << n) - 1) : float(n);
    for (int i = 0; i < n; ++i) {
        float dt = length_km * (geometric ? float(1 << i) : 1.0) / total;
        tau += cloud_extinction(p + d * (t + 0.5 * dt)) * dt;
        t += dt;
    }
    return tau;
}

// The distance from p (inside the shell r_lo..r_hi) along unit d to the shell's boundary.
float distance_in_shell(vec3 p, vec3 d, float r_lo, float r_hi) {
    float t = ray_sphere(p, d, r_hi).y;
    vec2 inner = ray_sphere(p, d, r_lo);
    if (inner.x > 0.0) t = min(t, inner.x);
    return max(t, 0.0);
}

// The transmittance from p along L through the shell r_lo..r_hi: `steps` samples of its
// crossing.
float shell_transmittance(vec3 p, vec3 L, float r_lo, float r_hi, int steps) {
    vec2 seg;
    if (r_hi <= r_lo || !shell_segment(p, L, r_lo, r_hi, 1e30, seg)) return 1.0;
    return exp(-optical_depth_along(p + L * seg.x, L, seg.y - seg.x, steps, false));
}

// Transmittance towards the light L from a point p through the clouds' two shells (its cloud
// shadow): `steps` samples of the shapes (no detail) along each crossing (seed 000 ch.
// 5.4.3's soft shadows, from the whole crossing rather than one sample).
float clouds_transmittance(vec3 p, vec3 L, int steps) {
#ifdef NO_ALOFT
    return 1.0;  // no clouds over the sheet under them
#else
    return shell_transmittance(p, L, u_cloud_shell.x, u_cloud_shell.y, steps)
         * shell_transmittance(p, L, u_cloud_shell.z, u_cloud_shell.w, steps);
#endif
}

// Transmittance towards L from p through the fog and the precipitation under the clouds.
float ground_layer_transmittance(vec3 p, vec3 L, int steps) {
    return shell_transmittance(p, L, u_ground_layer.x, max(u_ground_layer.y, u_ground_layer.z), steps);
}

// The same through the clouds and through the fog and the precipitation under them.
float light_transmittance(vec3 p, vec3 L, int steps) {
    return clouds_transmittance(p, L, steps) * ground_layer_transmittance(p, L, steps);
}
