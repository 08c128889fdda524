"""Float64 oracles the tests check the GPU against: slow, obvious, never the production path.

- :mod:`skydome.reference.single`: transmittance and single scattering by quadrature;
- :mod:`skydome.reference.ms`: multiple scattering by Monte Carlo path tracing;
- :mod:`skydome.reference.disks`: the Sun's and the Moon's disks by ray tracing, and the
  solid angles of camera pixels.
"""
