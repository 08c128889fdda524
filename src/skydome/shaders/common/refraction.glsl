// Astronomical refraction: the airless (true) direction of an apparent one, for the disks
// and points drawn beyond the atmosphere (the Sun, the Moon, later the stars). Matches
// skydome.physics.refraction: Saemundsson 1986 (Meeus eq. 16.4) is the astronomy's true ->
// apparent law; its inverse here starts from Bennett 1982 (Meeus eq. 16.3, apparent -> true,
// consistent with it to 4") and takes two fixed-point steps of h_t = h_a - R_S(h_t), which
// converge because dR/dh < 0.25 everywhere the law is defined.
#include "common/constants.glsl"

uniform float u_refraction_scale;  // (P / 1010 hPa) (283 K / T): 0 switches refraction off

// Refraction (rad) to add to a true elevation (rad): Saemundsson, 0 below -1.9 deg and near
// the zenith (where the law's argument passes 90 deg and its cotangent turns negative) as in
// skydome.physics.refraction.refraction_saemundsson.
// twin: skydome.physics.refraction.refraction_saemundsson(np.degrees(h_true)) h_true=-0.05..1.58 u_refraction_scale=0.9
float refraction_saemundsson(float h_true) {
    float h = degrees(h_true);
    if (h < -1.9) return 0.0;
    return u_refraction_scale * max(radians(1.02 / 60.0) / tan(radians(h + 10.3 / (h + 5.11))), 0.0);
}

// Refraction (rad) to subtract from an apparent elevation (rad): Bennett, 0 below -1 deg and
// near the zenith.
// twin: skydome.physics.refraction.refraction_bennett(np.degrees(h_apparent)) h_apparent=-0.05..1.58 u_refraction_scale=0.9
float refraction_bennett(float h_apparent) {
    float h = degrees(h_apparent);
    if (h < -1.0) return 0.0;
    return u_refraction_scale * max(radians(1.0 / 60.0) / tan(radians(h + 7.31 / (h + 4.4))), 0.0);
}

// The airless direction whose refracted image is `dir` (unit, ENU): the same azimuth, the
// elevation lowered by the refraction R. `dir` is turned down by R in its vertical plane
// (dir cos R - up sin R, `up` the unit vector normal to dir towards the zenith), so that with
// no refraction it comes back unchanged. The elevation is atan(z, |xy|), not asin(z): Mesa's
// asin is a polynomial off by up to 3.9e-4 rad (81", measured on llvmpipe 22.3), which
// displaced a disk by a whole pixel of a zoomed frame; its atan is good to 3e-6 rad.
// twin: skydome.physics.refraction.airless_offset(dir[:, 2], u_refraction_scale) dir=unit u_refraction_scale=1.1
vec3 airless_direction(vec3 dir) {
    float horizontal = length(dir.xy);
    if (horizontal <= 0.0) return dir;  // the zenith or the nadir: no refraction there
    float h_a = atan(dir.z, horizontal);
    float r = refraction_bennett(h_a);
    r = refraction_saemundsson(h_a - r);
    r = refraction_saemundsson(h_a - r);
    vec3 up = (vec3(0.0, 0.0, 1.0) - dir.z * dir) / horizontal;
    return normalize(cos(r) * dir - sin(r) * up);
}
