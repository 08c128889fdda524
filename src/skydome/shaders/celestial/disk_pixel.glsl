// What the celestial layers' passes share: whether this pixel sees a sphere beyond the air
// (the Sun, the Moon, later the planets), through refraction.
#include "common/camera.glsl"
#include "common/refraction.glsl"
#include "common/sphere_disk.glsl"

// True when the pixel at frag_xy sees the sphere towards `centre_true` (airless, unit ENU) of
// angular radius asin(sin_radius); `true_dir` receives the pixel's airless direction.
bool pixel_sees_sphere(vec2 frag_xy, vec3 centre_true, float sin_radius, out vec3 true_dir) {
    vec3 dir;
    true_dir = vec3(0.0, 0.0, 1.0);
    if (!camera_ray(frag_xy, dir)) return false;
    true_dir = airless_direction(dir);
    return ray_meets_sphere(true_dir, centre_true, sin_radius);
}
