"""Volumetric clouds: the cloud droplets' phase function (:mod:`skydome.clouds.phase`), and, as
the package grows, the cloud layer (noise, weather maps, cloud types, shadows).

The float64 Monte Carlo reference the renderer's clouds are checked against lives in
:mod:`skydome.reference.clouds_mc`.
"""
