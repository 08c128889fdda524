// One mip level of the prefiltered specular cube map (skydome.lighting_ibl): the split sum's
// first factor (Karis 2013) with n = v = r, drawn as a strip of the 6 faces (face f covers
// x in [f n, (f + 1) n) of the 6n x n target; GL row 0 = the face's t = 0 row,
// lighting/cube_faces.glsl). Per texel: SAMPLES half vectors drawn from the GGX lobe of
// alpha = u_alpha (Hammersley points), l = 2 (n.h) h - n, and
//     L(n) = sum L_env(l) (n.l) / sum (n.l)    over n.l > 0,
// each sample read from the equirect map's mip chain at the level whose texel covers the
// sample's solid angle 1 / (SAMPLES pdf), pdf = D(n.h) / 4 (n = v), plus one level, at most
// MAX_LOD (the level of 16 rows: lighting_ibl.MIN_ROWS) (filtered importance sampling:
// Colbert & Krivanek 2007, GPU Gems 3 ch. 20), so that a
// small bright feature is spread over the lobe instead of hit or missed; the levels average
// by solid angle, env_radiance). u_alpha = 0 (the mirror) reads the map at the texel's
// direction (bilinear, level 0).
// A point light (the Sun, u_sun_rgb its illuminance in lx on a surface facing it; 0: none)
// adds E D(n.h_s) (n.s) / 4 divided by the sum's mean weight (sum (n.l) / SAMPLES): the
// same estimator's limit for a delta of light; at u_alpha = 0 it is put into the texel it
// falls in, E / the texel's solid angle.
// Float64 twin: tests/test_lighting_ibl.py (prefilter_twin).
#include "lighting/ggx.glsl"
#include "lighting/cube_faces.glsl"

uniform sampler2D u_env;        // equirect map, (L w, w), rows top first, mipmapped
uniform float u_face_size;      // this level's face size, texels
uniform float u_alpha;          // GGX alpha = roughness^2
uniform float u_env_texel_sr;   // solid angle of a level-0 texel of the map at the equator, sr
uniform vec3 u_sun_dir;         // ENU, unit
uniform vec3 u_sun_rgb;         // lx on a surface facing it (0: no Sun)
out vec4 frag;

// The map's radiance (cd/m^2) at `uv`, level `lod`: the texture holds (L w, w) with w the
// texel's cos(latitude), so that its mip levels average by solid angle.
vec3 env_radiance(vec2 uv, float lod) {
    vec4 c = textureLod(u_env, uv, lod);
    return c.rgb / c.a;
}

// Where a unit ENU direction lands on the equirect map: u = azimuth / 2 pi (north = 0,
// east = 0.25), v = zenith angle / pi (row 0 at the zenith).
vec2 equirect_uv(vec3 d) {
    float az = atan(d.x, d.y);
    return vec2(az * (0.5 * INV_PI) + (az < 0.0 ? 1.0 : 0.0),
                atan(length(d.xy), d.z) * INV_PI);
}

// Exact solid angle of the face rectangle [x0, x1] x [y0, y1] (face coordinates in [-1, 1]).
float face_area(vec2 p) { return atan(p.x * p.y, sqrt(dot(p, p) + 1.0)); }
float texel_sr(vec2 lo, vec2 hi) {
    return face_area(lo) - face_area(vec2(lo.x, hi.y)) - face_area(vec2(hi.x, lo.y))
           + face_area(hi);
}

void main() {
    int face = int(floor(gl_FragCoord.x / u_face_size));
    vec2 texel = vec2(gl_FragCoord.x - float(face) * u_face_size, gl_FragCoord.y);
    vec2 st = texel / u_face_size;
    vec3 n = normalize(enu_from_cube(cube_direction(face, st)));
    vec3 rgb = vec3(0.0);
    if (u_alpha <= 0.0) {
        rgb = env_radiance(equirect_uv(n), 0.0);
        if (dot(u_sun_rgb, vec3(1.0)) > 0.0) {
            vec2 sun_st;
            int sun_face = cube_face_st(cube_from_enu(u_sun_dir), sun_st);
            vec2 cell = floor(texel);
            if (sun_face == face
                && all(equal(min(floor(sun_st * u_face_size), u_face_size - 1.0), cell))) {
                vec2 lo = 2.0 * cell / u_face_size - 1.0;
                vec2 hi = 2.0 * (cell + 1.0) / u_face_size - 1.0;
                rgb += u_sun_rgb / texel_sr(lo, hi);
            }
        }
        frag = vec4(rgb, 1.0);
        return;
    }
    float weight = 0.0;
    for (uint i = 0u; i < uint(SAMPLES); ++i) {
        vec3 h = importance_sample_ggx(hammersley(i, uint(SAMPLES)), u_alpha, n);
        float noh = dot(n, h);
        vec3 l = 2.0 * noh * h - n;
        float nol = dot(n, l);
        if (nol > 0.0) {
            float pdf = 0.25 * d_ggx(noh, u_alpha);
            float sample_sr = 1.0 / (float(SAMPLES) * pdf);
            float lod = clamp(0.5 * log2(sample_sr / u_env_texel_sr) + 1.0, 0.0, MAX_LOD);
            rgb += env_radiance(equirect_uv(l), lod) * nol;
            weight += nol;
        }
    }
    rgb /= weight;
    float sun_nol = dot(n, u_sun_dir);
    if (sun_nol > 0.0 && dot(u_sun_rgb, vec3(1.0)) > 0.0) {
        float noh = dot(n, normalize(n + u_sun_dir));
        rgb += u_sun_rgb * (0.25 * d_ggx(noh, u_alpha) * sun_nol / (weight / float(SAMPLES)));
    }
    frag = vec4(rgb, 1.0);
}
