// Point sources (stars, planets), vertex stage: one instanced quad per source (or per copy
// of a source: the equirect seam, a cubemap face's extended plane), aligned to whole frame
// pixels: a point sprite (SPRITE 1) where its square lies inside the tile, else two
// triangles (GL drops a point whose centre leaves the viewport, which would lose light at
// tile and frame edges; a quad is clipped to the pixels it covers).
// The CPU (skydome.celestial.point_sources, float64) has placed every quad and kept only
// those that touch this tile. Per instance, in tile pixels: the quad's corners (whole
// pixels); the source's position and 1 / the PSF's sigma along x and y; the only cubemap
// face the copy may write (-1: any); the illuminance in the 4 output channels.
// What does not vary across a quad is computed here, once per vertex (one per sprite), not
// per pixel: for a quad of at most 8 pixels a side (WEIGHT_TABLE 1), the PSF's share of
// each of its columns and rows (each set summing to 1), so that its pixels need no erf; for
// a larger one, the PSF's integral over the whole quad, whose inverse normalises the
// pixels' weights.
#define POINT_SOURCES_VERTEX_STAGE  // the PSF functions of the file below, not its main
#include "celestial/point_sources.glsl"

in vec4 in_rect;              // xy: the quad's lower-left corner, zw: its upper-right one
in vec4 in_centre_inv_sigma;  // xy: the source's position from in_rect.xy, zw: 1 / sigma
in float in_face;
in vec4 in_channels;

uniform vec2 u_tile_size;  // pixels of the tile drawn (the viewport)
uniform float u_point_size;  // SPRITE: the sprite's side, pixels (odd)

void main() {
#if SPRITE
    // A point sprite at the centre of the source's pixel (the quad's centre), its size set
    // by the CPU to the quad's larger side (odd): it covers that many whole pixels.
    gl_Position = vec4((in_rect.xy + in_rect.zw) * 0.5 / u_tile_size * 2.0 - 1.0, 0.0, 1.0);
    gl_PointSize = u_point_size;  // used if GL_PROGRAM_POINT_SIZE is enabled
#else
    int corner = gl_VertexID % 6;
    vec2 offsets[6] = vec2[6](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
    vec2 corner_px = mix(in_rect.xy, in_rect.zw, offsets[corner]);
    gl_Position = vec4(corner_px / u_tile_size * 2.0 - 1.0, 0.0, 1.0);
#endif
    vec2 c = in_centre_inv_sigma.xy, inv_sigma = in_centre_inv_sigma.zw;
#if WEIGHT_TABLE
    // The PSF's share of each column and row: the tails at the 9 edges once each, each
    // pixel's integral from its two edges, normalised by their sum (0 beyond the quad).
    vec2 n = in_rect.zw - in_rect.xy;
    float wx[8], wy[8];
    vec2 u = -c * inv_sigma;
    vec2 q = vec2(normal_tail(u.x), normal_tail(u.y));
    vec2 sum = vec2(0.0);
    for (int k = 0; k < 8; ++k) {
        vec2 u1 = (float(k + 1) - c) * inv_sigma;
        vec2 q1 = vec2(normal_tail(u1.x), normal_tail(u1.y));
        wx[k] = float(k) < n.x ? between_tails(u.x, u1.x, q.x, q1.x) : 0.0;
        wy[k] = float(k) < n.y ? between_tails(u.y, u1.y, q.y, q1.y) : 0.0;
        sum += vec2(wx[k], wy[k]);
        u = u1;
        q = q1;
    }
    v_wx0 = vec4(wx[0], wx[1], wx[2], wx[3]) / sum.x;
    v_wx1 = vec4(wx[4], wx[5], wx[6], wx[7]) / sum.x;
    v_wy0 = vec4(wy[0], wy[1], wy[2], wy[3]) / sum.y;
    v_wy1 = vec4(wy[4], wy[5], wy[6], wy[7]) / sum.y;
    v_channels = in_channels;
#else
    // The same arithmetic as the fragment stage's pixel edges, so that the pixels' weights
    // telescope to this integral exactly.
    vec2 a0 = (vec2(0.0) - c) * inv_sigma;
    vec2 b0 = (in_rect.zw - in_rect.xy - c) * inv_sigma;
    v_channels = in_channels / (normal_between(a0.x, b0.x) * normal_between(a0.y, b0.y));
    v_centre = c;
    v_inv_sigma = inv_sigma;
#endif
    v_lo = in_rect.xy;
    v_face = int(in_face);
}
