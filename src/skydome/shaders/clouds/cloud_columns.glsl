// The clouds' column census (skydome.clouds.layer.CloudLayer.column_optical_depths): for each
// texel of a grid over the weather tile, the optical depth of the vertical column through the
// main layer and through the cirrus sheet: the integral of the same extinction the march and
// the light see (clouds/cloud_density.glsl), COLUMN_STEPS equal steps per shell sampled at
// their middles. Optical depths are of the delta-M scaled extinction (the layer divides).
#include "atmosphere/precomputed_lookup.glsl"
#include "clouds/cloud_density.glsl"

uniform vec2 u_grid_km;  // the grid's spacing (km) in x (east) and y (north)

layout(location = 0) out vec4 frag;

const int COLUMN_STEPS = 160;

// The optical depth of the vertical column at (x, y) km of the tile between radii r_lo and
// r_hi: points p with p.xy = (x, y) (the tile's coordinates) and |p| = r.
float column_depth(vec2 xy, float r_lo, float r_hi) {
    float dr = (r_hi - r_lo) / float(COLUMN_STEPS);
    float tau = 0.0;
    for (int i = 0; i < COLUMN_STEPS; ++i) {
        float r = r_lo + (float(i) + 0.5) * dr;
        vec3 p = vec3(xy, sqrt(r * r - dot(xy, xy)));
        tau += cloud_extinction(p) * dr;
    }
    return tau;
}

void main() {
    vec2 xy = (gl_FragCoord.xy - 0.5) * u_grid_km;
    float main_layer = column_depth(xy, u_cloud_shell.x, u_cloud_shell.y);
    float cirrus = u_cloud_shell.w > u_cloud_shell.z ? column_depth(xy, u_cloud_shell.z, u_cloud_shell.w) : 0.0;
    frag = vec4(main_layer, cirrus, 0.0, 1.0);
}
