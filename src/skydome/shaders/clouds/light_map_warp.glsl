// The clouds' light map (skydome.clouds.light_map): the key light's transmittance through
// the clouds' shells along the rays that leave the sphere of their lowest base, radius r
// (km), towards it. Rays from any point below that base cross the same shells as from where
// they leave the sphere, so one value per point of the sphere serves every point under the
// clouds. The sphere's points are held by their horizontal offsets (km, planet-centred, the
// camera on the z axis) from the map's centre, where the light's ray from the ground under
// the camera leaves the sphere (the points near the camera look up the texels near it),
// warped into the unit disk m = xy / (|xy| + a): a texel of N spans 2a/N km at the centre
// and (|xy| + a)^2 / a 2/N km at |xy| (far shadows fill few pixels), and the disk reaches
// every distance. Texture coordinates uv = (m + 1) / 2.

// twin: skydome.clouds.light_map.light_map_uv(xy_km, a_km) xy_km=-300..300 a_km=3
vec2 light_map_uv(vec2 xy_km, float a_km) {
    return 0.5 + 0.5 * xy_km / (length(xy_km) + a_km);
}

// The inverse: the offsets (km, from the centre) of texture coordinates uv inside the disk.
// twin: skydome.clouds.light_map.light_map_xy(uv, a_km) uv=0.2..0.8 a_km=3
vec2 light_map_xy(vec2 uv, float a_km) {
    vec2 m = 2.0 * uv - 1.0;
    return a_km * m / max(1.0 - length(m), 1e-6);
}
