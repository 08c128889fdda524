"""Float64 oracles the tests check the GPU against: slow, obvious, never the production path.

- :mod:`skydome.reference.single`: transmittance and single scattering by quadrature;
- :mod:`skydome.reference.ms`: multiple scattering by Monte Carlo path tracing;
"""
