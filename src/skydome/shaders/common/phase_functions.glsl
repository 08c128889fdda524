// Phase functions (sr^-1), nu = cosine of the scattering angle.
#include "common/constants.glsl"

// Rayleigh: 3/(16 pi) (1 + nu^2).
// twin: skydome.physics.phase.rayleigh_phase(nu) nu=-1..1
float rayleigh_phase(float nu) { return 3.0 / (16.0 * PI) * (1.0 + nu * nu); }

// Cornette-Shanks (1992, Appl. Opt. 31, 3152, eq. 4) Mie approximation (seed 001 ch. 2):
// 3/(8 pi) (1 - g^2)(1 + nu^2) / ((2 + g^2)(1 + g^2 - 2 g nu)^(3/2)).
// twin: skydome.physics.phase.cornette_shanks(nu, g) nu=-1..1 g=-0.95..0.95
float cornette_shanks_phase(float nu, float g) {
    float k = 3.0 / (8.0 * PI) * (1.0 - g * g) / (2.0 + g * g);
    return k * (1.0 + nu * nu) / pow(max(1.0 + g * g - 2.0 * g * nu, 1e-8), 1.5);
}

// Henyey-Greenstein: (1 - g^2) / (4 pi (1 + g^2 - 2 g nu)^(3/2)).
// twin: skydome.physics.phase.henyey_greenstein(nu, g) nu=-1..1 g=-0.95..0.95
float henyey_greenstein_phase(float nu, float g) {
    float d = max(1.0 + g * g - 2.0 * g * nu, 1e-8);
    return (1.0 - g * g) / (4.0 * PI * d * sqrt(d));
}
