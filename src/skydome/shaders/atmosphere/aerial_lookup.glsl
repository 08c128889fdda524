// The aerial perspective from the aerial-perspective tables (atmosphere/aerial_view_lut.glsl):
// the light one light scatters towards the camera from the air within `distance` (km) along a
// view direction with sky-view unit coordinates `unit` (atmosphere/sky_view_mapping.glsl) and
// phase-angle cosine nu, on a ray of `ray_length_km`; (R, G, B, scotopic) at unit scale.
// Needs atmosphere/sky_view_mapping.glsl and the phase functions (common/mie_phase.glsl).
// The tables of the Sun and, with HAS_LIGHT2, of the second light (render/sky_view.py):
uniform sampler3D u_sun_aerial_scattering;
uniform sampler3D u_sun_aerial_single_mie;
#ifdef HAS_LIGHT2
uniform sampler3D u_light2_aerial_scattering;
uniform sampler3D u_light2_aerial_single_mie;
#endif
vec4 aerial_from_table(sampler3D scattering, sampler3D single_mie, vec3 unit, float nu,
                       float distance, float ray_length_km) {
    vec3 uvw = vec3(sky_view_texcoords(unit, u_aerial_size.xy), aerial_w(distance, ray_length_km));
    return texture(scattering, uvw) * rayleigh_phase(nu)
         + texture(single_mie, uvw) * mie_phase_channels(nu);
}
