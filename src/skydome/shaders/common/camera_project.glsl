// The forward mapping of common/camera.glsl: where a view direction lands in the frame, and
// the solid angle of a pixel there. For point sources and overlays drawn by vertex shaders.
// Frame positions are GL pixels of the whole frame (x right, y up, pixel i covering
// [i, i + 1]); subtract u_tile_offset for a tile. Models 0-3 (a direction map, model 4, has
// no forward mapping). Float64 twins: the camera classes of skydome.core.cameras.
#include "common/camera.glsl"

// The face (camera.glsl's order) and face coordinates in [-1, 1]^2 of a direction.
int cube_face_of(vec3 d, out vec2 p) {
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z) {
        p = d.x > 0.0 ? vec2(-d.y, d.z) / a.x : vec2(d.y, d.z) / a.x;
        return d.x > 0.0 ? 0 : 1;
    }
    if (a.y >= a.z) {
        p = d.y > 0.0 ? vec2(d.x, d.z) / a.y : vec2(-d.x, d.z) / a.y;
        return d.y > 0.0 ? 2 : 3;
    }
    p = d.z > 0.0 ? vec2(-d.x, d.y) / a.z : vec2(d.x, d.y) / a.z;
    return d.z > 0.0 ? 4 : 5;
}

// False where the camera does not see `dir` (behind a perspective camera, below the
// fisheye's horizon); `frag_xy` is its frame position.
// twin: skydome.core.cameras.Camera.project(dir, width, height) dir=unit
bool camera_project(vec3 dir, out vec2 frag_xy) {
    frag_xy = vec2(-1e9);
#if CAMERA_MODEL == 0
    vec3 local = transpose(u_camera_basis) * dir;  // (right, up, forward)
    if (local.z <= 1e-9) return false;
    float aspect = u_resolution.x / u_resolution.y;
    vec2 ndc = vec2(local.x / (local.z * u_tan_half_fov), local.y / (local.z * u_tan_half_fov / aspect));
    frag_xy = (ndc + 1.0) * 0.5 * u_resolution;
    return true;
#elif CAMERA_MODEL == 1
    float zenith = atan(length(dir.xy), dir.z);  // acos loses digits near the zenith
    float az = atan(dir.x, dir.y);
    float rho = zenith / (0.5 * PI) * 0.5 * min(u_resolution.x, u_resolution.y);
    frag_xy = 0.5 * u_resolution + rho * vec2(-sin(az), cos(az));
    return zenith <= 0.5 * PI;
#elif CAMERA_MODEL == 2
    float az = atan(dir.x, dir.y);
    if (az < 0.0) az += 2.0 * PI;
    float el = atan(dir.z, length(dir.xy));
    frag_xy = vec2(az / (2.0 * PI), el / PI + 0.5) * u_resolution;
    return true;
#elif CAMERA_MODEL == 3
    vec2 p;
    int face = cube_face_of(dir, p);
    float side = u_resolution.y;
    frag_xy = vec2(float(face) * side, 0.0) + (p + 1.0) * 0.5 * side;
    return true;
#else
    return false;
#endif
}

// Solid angle (sr) of one pixel where the frame sees `dir`.
// twin: skydome.core.cameras.Camera.solid_angle(dir, width, height) dir=unit
float camera_pixel_solid_angle(vec3 dir) {
#if CAMERA_MODEL == 0
    float f = max(dot(u_camera_basis[2], dir), 1e-12);
    float step_ = 2.0 * u_tan_half_fov / u_resolution.x;  // pixel on the unit-distance plane
    return step_ * step_ * f * f * f;                     // dA cos^3(theta)
#elif CAMERA_MODEL == 1
    float k = PI / min(u_resolution.x, u_resolution.y);  // rad per pixel
    float z = atan(length(dir.xy), dir.z);
    return k * k * (z > 1e-4 ? sin(z) / z : 1.0);
#elif CAMERA_MODEL == 2
    float cos_el = length(dir.xy);  // not sqrt(1 - z^2): float32 loses it near the poles
    return (2.0 * PI / u_resolution.x) * (PI / u_resolution.y) * cos_el;
#elif CAMERA_MODEL == 3
    float m = max(abs(dir.x), max(abs(dir.y), abs(dir.z)));
    float step_ = 2.0 / u_resolution.y;
    return step_ * step_ * m * m * m;
#else
    return 0.0;
#endif
}
