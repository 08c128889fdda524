// Astronomical refraction: the airless (true) direction of an apparent one, for the disks
// and points drawn beyond the atmosphere (the Sun, the Moon, later the stars). Matches
// skydome.astro.frames: Saemundsson 1986 (Meeus eq. 16.4) is the astronomy's true ->
// apparent law; its inverse here starts from Bennett 1982 (Meeus eq. 16.3, apparent -> true,
// consistent with it to 4") and takes two fixed-point steps of h_t = h_a - R_S(h_t), which
// converge because dR/dh < 0.25 everywhere the law is defined.
#include "common/constants.glsl"

uniform float u_refraction_scale;  // (P / 1010 hPa) (283 K / T): 0 switches refraction off

// Refraction (rad) to add to a true elevation (rad): Saemundsson, 0 below -1.9 deg as in
// frames.refraction_saemundsson.
float refraction_saemundsson(float h_true) {
    float h = degrees(h_true);
    if (h < -1.9) return 0.0;
    return u_refraction_scale * radians(1.02 / 60.0) / tan(radians(h + 10.3 / (h + 5.11)));
}

// Refraction (rad) to subtract from an apparent elevation (rad): Bennett, 0 below -1 deg.
float refraction_bennett(float h_apparent) {
    float h = degrees(h_apparent);
    if (h < -1.0) return 0.0;
    return u_refraction_scale * radians(1.0 / 60.0) / tan(radians(h + 7.31 / (h + 4.4)));
}

// The airless direction whose refracted image is `dir` (unit, ENU): the same azimuth, the
// elevation lowered by the refraction.
vec3 airless_direction(vec3 dir) {
    float h_a = asin(clamp(dir.z, -1.0, 1.0));
    float h_t = h_a - refraction_bennett(h_a);
    h_t = h_a - refraction_saemundsson(h_t);
    h_t = h_a - refraction_saemundsson(h_t);
    float horizontal = length(dir.xy);
    vec2 azimuth = horizontal > 0.0 ? dir.xy / horizontal : vec2(0.0, 1.0);
    return vec3(azimuth * cos(h_t), sin(h_t));
}
