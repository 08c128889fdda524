// Where a view direction falls in the fog's direction table (skydome.clouds.direction_table,
// whose table_texcoords is this function's float64 twin). Both its angles are "diamond
// angles" (a ratio of a direction's components, monotonic in the true angle and within a
// factor 2 of proportional to it): a pixel finds its texel with a few divisions and a square
// root, no trigonometry (which a CPU rasterizer pays dearly for, per pixel).
//  x: the azimuth from the key light's, a quarter turn per quarter of the table (the light's
//     on texel 0's centre; the texture repeats);
//  y: the elevation's q = z / (h + |z|) (h the horizontal part), split at the ground's
//     horizon q_h: the upper half the rays that miss the ground, the lower half those that
//     meet it, each with the square root of q's distance from q_h linear in the texels
//     (they crowd at the horizon).
uniform vec3 u_table_frame;  // (cos, sin) of the key light's azimuth (from east towards
                             // north), the horizon's q_h
uniform vec2 u_table_size;   // texels (azimuth, elevation)

// The diamond angle of (x, y) in (-1, 3]: 0 along +x, 1 along +y, 2 along -x, -1 (or 3)
// along -y (one division and a choice: a CPU rasterizer runs every branch of a pixel block).
float diamond_angle(float x, float y) {
    float r = y / (abs(x) + abs(y) + 1e-30);
    return x < 0.0 ? 2.0 - r : r;
}

// Its half: the rays below the ground's horizon (q < q_h) are the ground's, as sky_class
// (clouds_composite.glsl) finds them, without a second ray.
// twin: skydome.clouds.direction_table.table_texcoords(d, size, frame) d=unit
vec2 direction_table_uv(vec3 d) {
    // the horizontal direction in the light's frame: +x towards the light
    float a = d.x * u_table_frame.x + d.y * u_table_frame.y;
    float b = d.y * u_table_frame.x - d.x * u_table_frame.y;
    float u = fract(0.25 * diamond_angle(a, b) + 0.5 / u_table_size.x);
    float h = length(d.xy);
    float q = d.z / (h + abs(d.z) + 1e-30);
    float q_h = u_table_frame.z;
    bool hits_ground = q < q_h;
    float x = hits_ground ? (q_h - q) / (q_h + 1.0) : (q - q_h) / (1.0 - q_h);
    x = sqrt(clamp(x, 0.0, 1.0));
    float half_n = 0.5 * u_table_size.y;
    float v_half = (0.5 + x * (half_n - 1.0)) / half_n;
    return vec2(u, 0.5 + 0.5 * (hits_ground ? -v_half : v_half));
}
