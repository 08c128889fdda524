// Photometric laws of the sunlit spheres (the Moon, the planets): mu0 and mu the cosines of
// the incidence and emission angles at a point of the surface (mu >= 0: it faces the
// observer); 0 where the Sun does not light it (skydome.celestial.surface_laws).

// Lambert: mu0 (many scatterings: cloud decks).
// twin: skydome.celestial.surface_laws.lambert_law(mu0) mu0=-1..1
float lambert_law(float mu0) { return max(mu0, 0.0); }

// Lommel-Seeliger: mu0 / (mu0 + mu) (single scattering in a dark regolith; Hapke 2012,
// "Theory of reflectance and emittance spectroscopy", eq. 9.4).
// twin: skydome.celestial.surface_laws.lommel_seeliger_law(mu0, mu) mu0=-1..1 mu=0..1
float lommel_seeliger_law(float mu0, float mu) { return mu0 > 0.0 ? mu0 / (mu0 + mu) : 0.0; }
