"""The core under every layer: what the layers, the scene and the front ends share.

- :mod:`~skydome.core.cameras`: cameras, their pixel mappings and the float64 twins;
- :mod:`~skydome.core.frame`: ``Frame``, a frame in cd/m^2;
- :mod:`~skydome.core.tiles`: frames drawn in tiles, per-pixel inputs;
- :mod:`~skydome.core.lights`: ``SkyState``, ``Light``, ``MoonView``: the lights of an instant;
- :mod:`~skydome.core.basis`: ``SpectralBasis``, spectral values to output channels;
- :mod:`~skydome.core.layer`: the ``Layer`` interface and its ``DrawContext``;
- :mod:`~skydome.core.services`: the typed services layers offer one another;
- :mod:`~skydome.core.refraction_table`: the per-pixel refraction as a texture;
- :mod:`~skydome.core.cache`: the on-disk cache of tables.

Nothing here knows a particular layer, the scene or a front end
(``docs/architecture.md``: the base knows no sky).
"""
