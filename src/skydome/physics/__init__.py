"""Physics: float64 formulas and constants with one home each.

Host code and the tests use them; where a shader needs the same formula, its GLSL function
names the twin here (a ``// twin:`` line) and ``tests/test_glsl_twins.py`` holds the two
together.

- :mod:`~skydome.physics.constants`: J2000, the astronomical unit, the Earth's radii, angle
  and length units, the standard weather;
- :mod:`~skydome.physics.phase`: Rayleigh, Henyey-Greenstein and Cornette-Shanks phase
  functions, HG sampling;
- :mod:`~skydome.physics.refraction`: the refraction laws (Bennett, Saemundsson), the weather's
  factor on them, their per-pixel form, refracted ENU directions, the dip of the horizon;
- :mod:`~skydome.physics.airmass`: the relative air mass (Kasten & Young);
- :mod:`~skydome.physics.geometry`: ENU directions, rays in a spherical shell (distances to
  its spheres, the dip of their horizon), spheres seen from outside (the disks' geometry);
- :mod:`~skydome.physics.packing`: spectral values packed 4 to a vec4 / mat4 for the shaders;
- :mod:`~skydome.physics.interfaces`: Fresnel's reflectance, tabulated refractive indices;
- :mod:`~skydome.physics.sphere_optics`: water drops' rays (the bows by geometric optics);
- :mod:`~skydome.physics.crystal_optics`: ice crystals' rays, traced (the halos).
"""
