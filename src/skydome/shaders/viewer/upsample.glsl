// Viewer: a moving view's frame, drawn and tone-mapped at a reduced size (RGBA8, GL rows),
// brought up to the window's size (skydome.viewer.dynamic_resolution). EDGE 0: one bilinear
// fetch (the whole window). EDGE 1 (drawn over the band of rows and columns around the
// ground's edge): bilinear over the four reduced pixels around the window pixel, guided by
// the horizon: a reduced pixel whose centre lies on the other side of the ground's edge
// than this pixel's direction is left out, so the ground/sky edge does not smear; where all
// four lie across, plain bilinear.
#include "common/camera.glsl"

uniform sampler2D u_reduced;   // the reduced image, tone-mapped (bilinear filter)
uniform vec2 u_reduced_size;   // its pixels (w, h)
uniform float u_dip_sin;       // sin of the ground horizon's dip below the horizontal
out vec4 frag;

// 0: sky, 1: ground, 2: no ray (outside a fisheye's circle). frag_xy: window pixels.
int side(vec2 frag_xy) {
    vec3 dir;
    if (!camera_ray(frag_xy, dir)) return 2;
    return dir.z < -u_dip_sin ? 1 : 0;
}

void main() {
#if EDGE == 0
    frag = texture(u_reduced, gl_FragCoord.xy / u_resolution);
#else
    vec2 ratio = u_resolution / u_reduced_size;  // window pixels per reduced pixel
    vec2 q = gl_FragCoord.xy / ratio - 0.5;      // in reduced pixels, centres at integers
    vec2 base = floor(q);
    vec2 f = q - base;
    ivec2 b = ivec2(base);
    ivec2 hi = ivec2(u_reduced_size) - 1;
    int here = side(gl_FragCoord.xy);
    vec4 plain = vec4(0.0);
    vec4 sum = vec4(0.0);
    float wsum = 0.0;
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 2; ++i) {
            ivec2 t = clamp(b + ivec2(i, j), ivec2(0), hi);
            vec4 c = texelFetch(u_reduced, t, 0);
            float w = (i == 1 ? f.x : 1.0 - f.x) * (j == 1 ? f.y : 1.0 - f.y);
            plain += w * c;
            if (side((vec2(t) + 0.5) * ratio) == here) {
                sum += w * c;
                wsum += w;
            }
        }
    }
    frag = wsum > 1e-4 ? sum / wsum : plain;
#endif
}
