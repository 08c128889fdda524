// What the celestial layers' passes share: whether this pixel sees a sphere beyond the air
// (the Sun, the Moon, later the planets), through refraction.
#include "common/camera.glsl"
#include "common/refraction.glsl"
#include "common/sphere_disk.glsl"

// Points per pixel side a disk's pixel averages (skydome.core.cameras.disk_samples): 1 (the
// pixel's centre) while the disk spans a few pixels; more where a pixel is wide against the
// disk (a reduced frame of the viewer, a wide field), so that a pixel holds the disk's light
// over its area and the disk keeps its energy at any resolution.
uniform float u_disk_samples;

// The i-th of the n x n points spread over the pixel at frag_xy: its centre when n = 1, else
// Roberts' R2 low-discrepancy sequence (the plastic number's powers; no lattice for a disk
// centred on a pixel's corner to line up with, whose count of points would err by R^(2/3)).
vec2 disk_sample_xy(vec2 frag_xy, int i, int n) {
    if (n == 1) return frag_xy;
    return frag_xy - 0.5 + fract(vec2(0.5) + float(i) * vec2(0.7548776662466927, 0.5698402909980532));
}

// True when the pixel at frag_xy sees the sphere towards `centre_true` (airless, unit ENU) of
// angular radius asin(sin_radius); `true_dir` receives the pixel's airless direction.
bool pixel_sees_sphere(vec2 frag_xy, vec3 centre_true, float sin_radius, out vec3 true_dir) {
    vec3 dir;
    true_dir = vec3(0.0, 0.0, 1.0);
    if (!camera_ray(frag_xy, dir)) return false;
    true_dir = airless_direction(dir);
    return ray_meets_sphere(true_dir, centre_true, sin_radius);
}
