// Light shafts' input (HAS_SHADOW_MAP): per pixel, R the length (km) of the view ray in an
// occluder's shadow and G its first moment, the integral of the shadowed distance (km^2): the
// clouds' shafts (clouds/cloud_shafts.glsl) give both; a user's shadow_length_m image gives
// R alone (G = 0: the shadow next to the camera, Bruneton's light shafts). The shadowed parts
// are taken as one segment of that length centred on their mean distance.
uniform sampler2D u_shadow_map;

// The shadowed `length` (km) and where its segment starts (km from the camera; 0: at it).
void shadow_map_at(ivec2 pixel, out float length_km, out float start_km) {
    vec2 shadow = texelFetch(u_shadow_map, pixel, 0).rg;
    length_km = shadow.x;
    start_km = shadow.x > 0.0 ? max(shadow.y / shadow.x - 0.5 * shadow.x, 0.0) : 0.0;
}
