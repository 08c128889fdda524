// Spectral coefficients, NUM_GROUPS groups of 4 wavelengths (per km), and the conversion of a
// spectrum (per unit solar irradiance) to linear sRGB luminance and scotopic luminance.
uniform vec4 u_rayleigh_scattering[NUM_GROUPS];
uniform vec4 u_mie_scattering[NUM_GROUPS];
uniform vec4 u_mie_extinction[NUM_GROUPS];
uniform vec4 u_absorption_extinction[NUM_GROUPS];
uniform vec4 u_ground_albedo[NUM_GROUPS];
uniform float u_mie_g;
// Column g of the matrix maps the 4 samples of group g to (R, G, B, scotopic) in cd/m^2.
uniform mat4 u_spectral_to_rgbs[NUM_GROUPS];

// Optical depth of column densities c = (Rayleigh, Mie, absorption) km, for group g.
// twin: skydome.atmosphere.columns.optical_depth(coefficients, c * 1000) g=0..1 c=0..200 NUM_GROUPS=2
vec4 optical_depth(int g, vec3 c) {
    return u_rayleigh_scattering[g] * c.x + u_mie_extinction[g] * c.y + u_absorption_extinction[g] * c.z;
}
