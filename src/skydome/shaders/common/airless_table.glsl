// The airless (unrefracted) direction of a view ray from a table by the sine of its apparent
// elevation (skydome.core.refraction_table): d + k(z) (z d - up), unnormalised. The same law as
// common/refraction.glsl's airless_direction (within 2.3"), for one linear fetch instead of
// its trigonometry: for full-screen passes (the smooth layers).
uniform sampler2D u_airless_offset;   // R: k(z) at z = -1 + 2 i / (n - 1)
uniform vec2 u_offset_map;            // z -> the table's texture coordinate: z * x + y

// twin: skydome.physics.refraction.airless_offset_lookup(dir[:, 2], 1.0) dir=unit
vec3 airless_from_table(vec3 dir) {
    float k = textureLod(u_airless_offset, vec2(dir.z * u_offset_map.x + u_offset_map.y, 0.5),
                         0.0).r;
    return dir + k * (dir.z * dir - vec3(0.0, 0.0, 1.0));
}
