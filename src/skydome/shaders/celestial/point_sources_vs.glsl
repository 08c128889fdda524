// Point sources (stars, planets), vertex stage: one instanced quad per source (or per copy
// of a source: the equirect seam, a cubemap face's extended plane), aligned to whole frame
// pixels: a point sprite (SPRITE 1) where its square lies inside the tile, else two
// triangles (GL drops a point whose centre leaves the viewport, which would lose light at
// tile and frame edges; a quad is clipped to the pixels it covers).
// The CPU (skydome.celestial.point_sources, float64) has placed every quad and kept only
// those that touch this tile. Per instance, in tile pixels: the quad's corners (whole
// pixels); the source's position and 1 / the PSF's sigma along x and y; the only cubemap
// face the copy may write (-1: any); the illuminance in the 4 output channels.
// For a quad of at most 8 pixels a side (WEIGHT_TABLE 1) the CPU also gives the PSF's share
// of each of its columns and rows (each set summing to 1): no per-pixel erf at all. For a
// larger one, the PSF's integral over the whole quad, whose inverse normalises the pixels'
// weights, is computed here once per vertex, not per pixel.
#define POINT_SOURCES_VERTEX_STAGE  // the PSF functions of the file below, not its main
#include "celestial/point_sources.glsl"

in vec4 in_rect;              // xy: the quad's lower-left corner, zw: its upper-right one
in vec4 in_centre_inv_sigma;  // xy: the source's position, zw: 1 / sigma (1 / pixels)
in vec4 in_wx0;  // the columns' weights, left to right (0 past the quad)
in vec4 in_wx1;
in vec4 in_wy0;  // the rows' weights, bottom to top
in vec4 in_wy1;
in float in_face;
in vec4 in_channels;

uniform vec2 u_tile_size;  // pixels of the tile drawn (the viewport)

void main() {
#if SPRITE
    // A point sprite at the centre of the source's pixel (the quad's centre), glPointSize
    // set by the CPU to the quad's larger side (odd): it covers that many whole pixels.
    gl_Position = vec4((in_rect.xy + in_rect.zw) * 0.5 / u_tile_size * 2.0 - 1.0, 0.0, 1.0);
#else
    int corner = gl_VertexID % 6;
    vec2 offsets[6] = vec2[6](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
    vec2 corner_px = mix(in_rect.xy, in_rect.zw, offsets[corner]);
    gl_Position = vec4(corner_px / u_tile_size * 2.0 - 1.0, 0.0, 1.0);
#endif
    vec2 c = in_centre_inv_sigma.xy, inv_sigma = in_centre_inv_sigma.zw;
#if WEIGHT_TABLE
    v_wx0 = in_wx0;
    v_wx1 = in_wx1;
    v_wy0 = in_wy0;
    v_wy1 = in_wy1;
    v_channels = in_channels;
    v_lo = in_rect.xy;
#else
    // The same arithmetic as the fragment stage's pixel edges, so that the pixels' weights
    // telescope to this integral exactly.
    vec2 a0 = (in_rect.xy - c) * inv_sigma;
    vec2 b0 = (in_rect.zw - c) * inv_sigma;
    v_channels = in_channels / (normal_between(a0.x, b0.x) * normal_between(a0.y, b0.y));
    v_centre = c;
    v_inv_sigma = inv_sigma;
#endif
    v_face = int(in_face);
}
