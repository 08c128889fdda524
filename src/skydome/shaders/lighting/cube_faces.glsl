// The cube map's faces as OpenGL and Direct3D address them (the OpenGL 4.6 spec, table 8.19;
// D3D's cube faces are the same): face 0..5 = +X, -X, +Y, -Y, +Z, -Z, texel (s, t) in
// [0, 1]^2 with t = 0 the first row in memory (a DDS/KTX2 file's first row). The cube's
// axes are the file's: (x, y, z) = (east, up, north) of our ENU frame (a left-handed, y-up
// frame, D3D's and Unity's). Float64 twin: skydome.lighting_ibl.cube_directions.

// The cube-space direction (not normalised) of face `face` at (s, t).
vec3 cube_direction(int face, vec2 st) {
    float sc = 2.0 * st.x - 1.0;
    float tc = 2.0 * st.y - 1.0;
    if (face == 0) return vec3(1.0, -tc, -sc);
    if (face == 1) return vec3(-1.0, -tc, sc);
    if (face == 2) return vec3(sc, 1.0, tc);
    if (face == 3) return vec3(sc, -1.0, -tc);
    if (face == 4) return vec3(sc, -tc, 1.0);
    return vec3(-sc, -tc, -1.0);
}

// Cube space (east, up, north) to ENU (east, north, up), and back.
vec3 enu_from_cube(vec3 c) { return vec3(c.x, c.z, c.y); }
vec3 cube_from_enu(vec3 d) { return vec3(d.x, d.z, d.y); }

// The face and (s, t) of a cube-space direction (the inverse of cube_direction).
int cube_face_st(vec3 c, out vec2 st) {
    vec3 a = abs(c);
    int face;
    vec2 sc_tc;
    if (a.x >= a.y && a.x >= a.z) {
        face = c.x > 0.0 ? 0 : 1;
        sc_tc = c.x > 0.0 ? vec2(-c.z, -c.y) / a.x : vec2(c.z, -c.y) / a.x;
    } else if (a.y >= a.z) {
        face = c.y > 0.0 ? 2 : 3;
        sc_tc = c.y > 0.0 ? vec2(c.x, c.z) / a.y : vec2(c.x, -c.z) / a.y;
    } else {
        face = c.z > 0.0 ? 4 : 5;
        sc_tc = c.z > 0.0 ? vec2(c.x, -c.y) / a.z : vec2(-c.x, -c.y) / a.z;
    }
    st = 0.5 * (sc_tc + 1.0);
    return face;
}
