// Camera models: the view direction (ENU world frame: x east, y north, z up) of a pixel.
// CAMERA_MODEL: 0 perspective, 1 fisheye (equidistant, 180 deg, zenith at the centre,
// north up, east left as seen looking up), 2 equirectangular (azimuth 0 = north at the left
// edge increasing eastward, zenith at the top), 3 cubemap strip of six square faces
// (+X east, -X west, +Y north, -Y south, +Z up, -Z down), 4 a direction per pixel given
// by a texture (u_direction_map).
// frag_xy is gl_FragCoord.xy (origin bottom-left; images are flipped to top-first on read)
// of a frame drawn whole or tile by tile: u_tile_offset places the tile in the frame.
#include "common/constants.glsl"

uniform vec2 u_resolution;       // pixels of the whole frame
uniform vec2 u_tile_offset;      // pixels: the drawn tile's lower-left corner in the frame
uniform mat3 u_camera_basis;     // columns: right, up, forward (perspective)
uniform float u_tan_half_fov;    // tan(horizontal fov / 2) (perspective)
uniform sampler2D u_direction_map;  // unit directions, one texel per pixel (model 4)

vec3 cube_face_direction(int face, vec2 p) {
    // p in [-1, 1]^2, x right and y up on the face image.
    // Each face seen from inside: right = forward x up, up = +z (zenith/nadir: top = north).
    if (face == 0) return vec3(1.0, -p.x, p.y);    // +X east: right = south
    if (face == 1) return vec3(-1.0, p.x, p.y);    // -X west: right = north
    if (face == 2) return vec3(p.x, 1.0, p.y);     // +Y north: right = east
    if (face == 3) return vec3(-p.x, -1.0, p.y);   // -Y south: right = west
    if (face == 4) return vec3(-p.x, p.y, 1.0);    // +Z up: right = west
    return vec3(p.x, p.y, -1.0);                   // -Z down: right = east
}

// twin: skydome.core.cameras.Camera.directions(x, y, width, height) tile_xy=0..64
bool camera_ray(vec2 tile_xy, out vec3 dir) {
    vec2 frag_xy = tile_xy + u_tile_offset;
    vec2 uv = frag_xy / u_resolution;
#if CAMERA_MODEL == 0
    vec2 ndc = uv * 2.0 - 1.0;
    float aspect = u_resolution.x / u_resolution.y;
    dir = normalize(u_camera_basis * vec3(ndc.x * u_tan_half_fov, ndc.y * u_tan_half_fov / aspect, 1.0));
    return true;
#elif CAMERA_MODEL == 1
    float side = min(u_resolution.x, u_resolution.y);
    vec2 p = (frag_xy - 0.5 * u_resolution) / (0.5 * side);  // unit disk = horizon
    float rho = length(p);
    if (rho > 1.0) { dir = vec3(0.0, 0.0, 1.0); return false; }
    float zenith = rho * 0.5 * PI;
    // North up (+y), east left (-x): azimuth measured from north towards the left.
    float az = atan(-p.x, p.y);
    dir = vec3(sin(zenith) * sin(az), sin(zenith) * cos(az), cos(zenith));
    return true;
#elif CAMERA_MODEL == 2
    float az = uv.x * 2.0 * PI;
    float el = (uv.y - 0.5) * PI;
    dir = vec3(sin(az) * cos(el), cos(az) * cos(el), sin(el));
    return true;
#elif CAMERA_MODEL == 4
    dir = normalize(texelFetch(u_direction_map, ivec2(tile_xy), 0).xyz);  // the tile's own map
    return true;
#else
    float face_size = u_resolution.y;
    int face = int(floor(frag_xy.x / face_size));
    vec2 p = vec2(mod(frag_xy.x, face_size), frag_xy.y) / face_size * 2.0 - 1.0;
    dir = normalize(cube_face_direction(clamp(face, 0, 5), p));
    return true;
#endif
}
