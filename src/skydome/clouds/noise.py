"""Tileable noise textures for volumetric clouds (after Schneider 2015/2017, Nubis).

Three textures, each drawn by a fragment shader of ``shaders/clouds/`` (the per-texel math;
its float64 twin is :mod:`skydome.clouds.lattice_noise`), seeded and deterministic, and
tiling seamlessly with ``repeat`` wrapping:

- ``shape``: 3D, RGBA (8-bit normalised on the GPU), default 128^3. R = Perlin-Worley (Perlin fBm remapped by the
  Worley fBm of G), G, B, A = Worley fBm of base periods 4, 8, 16 cells per tile;
- ``detail``: 3D, RGBA (8-bit normalised on the GPU), default 32^3. R, G, B = Worley fBm of base periods 2, 4, 8
  cells per tile, A = 0.625 R + 0.25 G + 0.125 B;
- ``curl``: 2D, RG32F, default 128^2. The curl (d psi/dy, -d psi/dx) of a tileable Perlin
  fBm potential psi, divergence-free, divided by its largest |component| (so in [-1, 1]).

All values are dimensionless; one texture spans one tile (texture coordinates [0, 1) per
axis). Texel (i, j, k) of an N^3 texture samples u = ((i, j, k) + 0.5) / N; host arrays are
indexed [k, j, i, channel] (z, y, x), as OpenGL stores them. The 3D textures filter
trilinearly within their full-resolution level (the shaders sample no other).

:func:`cloud_noise` keeps one set per (context, arguments) in memory and the texel arrays in
the disk cache (:mod:`skydome.core.cache`, :data:`NOISE_CACHE`), keyed on the seed, the
sizes, the noise constants and the shader sources: a second process uploads instead of
drawing.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import moderngl
import numpy as np

from skydome.core.cache import CacheSpec, load_or_build
from skydome.errors import CacheError, ParameterError
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.textures import release_unbound

#: Shape texture: the Perlin fBm's first period (cells per tile), its octaves, and the gain
#: that maps it to [0, 1] before the Perlin-Worley remap (0.5 + gain * fBm: the 1st-99th
#: percentiles of the 5-octave fBm, about -0.37 and +0.34, become about 0.04 and 0.93).
SHAPE_PERLIN_PERIOD = 4
SHAPE_PERLIN_OCTAVES = 5
SHAPE_PERLIN_GAIN = 1.25
#: Shape texture: base periods (cells per tile) of the Worley fBm in G, B, A.
SHAPE_WORLEY_PERIODS = (4, 8, 16)
#: Detail texture: base periods of the Worley fBm in R, G, B.
DETAIL_WORLEY_PERIODS = (2, 4, 8)
#: Curl texture: the potential's first period (cells per tile) and octaves.
CURL_PERIOD = 4
CURL_OCTAVES = 3

#: Default sizes (texels per axis), as in Nubis: 128^3 shape, 32^3 detail, 128^2 curl.
DEFAULT_SHAPE_SIZE = 128
DEFAULT_DETAIL_SIZE = 32
DEFAULT_CURL_SIZE = 128

#: What the cached noise depends on besides its arguments: the GLSL of shaders/clouds/ (the
#: noise shaders and their include, noise_common.glsl, live there) and this module, which
#: holds every constant and the texel arrays' layout (the rest it imports is GL plumbing).
#: Bump ``version`` when an edit of it changes the texels (tests/test_cache.py checks).
NOISE_CACHE = CacheSpec(
    name="cloud-noise",
    version=1,
    shader_folders=("clouds",),
    builder_files=("clouds/noise.py",),
)

_MAX_SEED = 2**31 - 1


def check_seed(seed: int) -> int:
    """``seed`` as an int in [0, 2^31 - 1], or ParameterError."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise ParameterError(f"seed must be an integer, got {seed!r}")
    if not 0 <= int(seed) <= _MAX_SEED:
        raise ParameterError(f"seed = {seed} is outside the valid range [0, {_MAX_SEED}]")
    return int(seed)


def check_size(name: str, size: int, lo: int, hi: int) -> int:
    """A texture size (texels per axis): a power of two in [lo, hi], or ParameterError."""
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)):
        raise ParameterError(f"{name} must be an integer, got {size!r}")
    size = int(size)
    if not lo <= size <= hi or size & (size - 1):
        raise ParameterError(f"{name} = {size} must be a power of two in [{lo}, {hi}] texels")
    return size


@dataclass(frozen=True)
class NoiseInputs(ShaderInputs):
    """The noise passes (``clouds/noise_*.glsl``): the texture's size (texels), the seed, and
    each noise's own periods (in texels), octaves and gain (None where another noise's)."""

    u_size: int
    u_seed: int
    u_perlin_period: int | None = None
    u_perlin_octaves: int | None = None
    u_perlin_gain: float | None = None
    u_worley_period_1: int | None = None
    u_worley_period_2: int | None = None
    u_worley_period_3: int | None = None
    u_period: int | None = None
    u_octaves: int | None = None


def _periods(periods: tuple[int, int, int]) -> dict[str, int]:
    """The three Worley periods as the fields ``u_worley_period_1`` to ``_3``."""
    return {f"u_worley_period_{n}": int(p) for n, p in enumerate(periods, start=1)}


def _draw_volume(ctx, shader: str, inputs: NoiseInputs) -> np.ndarray:
    """Draw a layered pass into an RGBA32F texture array of size^3; the texels (k, j, i, 4)."""
    size = inputs.u_size
    fpass = FullscreenPass(ctx, shader, inputs=(NoiseInputs,), layered=True)
    array = ctx.texture_array((size, size, size), 4, dtype="f4")
    fbo = ctx.framebuffer(color_attachments=[array])
    try:
        fbo.viewport = (0, 0, size, size)
        fpass.draw(fbo, inputs, layers=(0, size))
        data = np.frombuffer(array.read(), dtype=np.float32)
    finally:
        for obj in (fbo, array, fpass):
            release_unbound(obj)
    return data.reshape(size, size, size, 4).copy()


def render_shape(ctx, seed: int = 1, size: int = DEFAULT_SHAPE_SIZE) -> np.ndarray:
    """Draw the shape noise: float32 texels (size, size, size, 4) indexed [k, j, i, RGBA]."""
    inputs = NoiseInputs(
        u_size=check_size("shape_size", size, 4, 512),
        u_seed=check_seed(seed),
        u_perlin_period=SHAPE_PERLIN_PERIOD,
        u_perlin_octaves=SHAPE_PERLIN_OCTAVES,
        u_perlin_gain=SHAPE_PERLIN_GAIN,
        **_periods(SHAPE_WORLEY_PERIODS),
    )
    return _draw_volume(ctx, "clouds/noise_shape.glsl", inputs)


def render_detail(ctx, seed: int = 1, size: int = DEFAULT_DETAIL_SIZE) -> np.ndarray:
    """Draw the detail noise: float32 texels (size, size, size, 4) indexed [k, j, i, RGBA]."""
    inputs = NoiseInputs(
        u_size=check_size("detail_size", size, 4, 512),
        u_seed=check_seed(seed),
        **_periods(DETAIL_WORLEY_PERIODS),
    )
    return _draw_volume(ctx, "clouds/noise_detail.glsl", inputs)


def render_curl_raw(ctx, seed: int = 1, size: int = DEFAULT_CURL_SIZE) -> np.ndarray:
    """Draw the unnormalised curl: float32 (size, size, 2) indexed [j, i, (x, y)], in units of
    the potential per tile."""
    size = check_size("curl_size", size, 4, 4096)
    fpass = FullscreenPass(ctx, "clouds/noise_curl.glsl", inputs=(NoiseInputs,))
    tex = ctx.texture((size, size), 2, dtype="f4")
    fbo = ctx.framebuffer(color_attachments=[tex])
    try:
        fbo.viewport = (0, 0, size, size)
        fpass.draw(
            fbo,
            NoiseInputs(size, check_seed(seed), u_period=CURL_PERIOD, u_octaves=CURL_OCTAVES),
        )
        data = np.frombuffer(tex.read(), dtype=np.float32)
    finally:
        for obj in (fbo, tex, fpass):
            release_unbound(obj)
    return data.reshape(size, size, 2).copy()


def render_curl(ctx, seed: int = 1, size: int = DEFAULT_CURL_SIZE) -> np.ndarray:
    """The curl noise divided by its largest |component|: float32 (size, size, 2) in [-1, 1],
    indexed [j, i, (x, y)]; x along the texture's s axis (east in a weather map)."""
    raw = render_curl_raw(ctx, seed, size)
    peak = float(np.max(np.abs(raw)))
    return (raw / peak).astype(np.float32) if peak > 0 else raw


def noise_key(seed: int, shape_size: int, detail_size: int, curl_size: int) -> str:
    """Cache key of a noise set: the arguments and the noise constants (``NOISE_CACHE`` adds
    the shader sources and the version of the code that draws them)."""
    return NOISE_CACHE.key(
        {
            "seed": seed,
            "sizes": [shape_size, detail_size, curl_size],
            "shape_perlin": [SHAPE_PERLIN_PERIOD, SHAPE_PERLIN_OCTAVES, SHAPE_PERLIN_GAIN],
            "shape_worley": SHAPE_WORLEY_PERIODS,
            "detail_worley": DETAIL_WORLEY_PERIODS,
            "curl": [CURL_PERIOD, CURL_OCTAVES],
        }
    )


def _volume_texture(ctx, texels: np.ndarray):
    # 8-bit normalised texels (the noise lies in [0, 1]; 1/255 steps, as Schneider 2015's
    # textures): a CPU rasterizer filters them several times faster than float32, and a GPU
    # holds a quarter of the memory.
    d, h, w, c = texels.shape
    unorm = np.round(np.clip(texels, 0.0, 1.0) * 255.0).astype(np.uint8)
    tex = ctx.texture3d((w, h, d), c, np.ascontiguousarray(unorm), dtype="f1")
    tex.repeat_x = tex.repeat_y = tex.repeat_z = True
    # No mipmaps: the shaders sample the volumes at their full resolution (textureLod 0), and
    # a mipmapped filter cost llvmpipe its level selection at every fetch (the fair-weather
    # still frame 13 % longer for the same pixels).
    tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
    return tex


def _plane_texture(ctx, texels: np.ndarray):
    h, w, c = texels.shape
    tex = ctx.texture((w, h), c, np.ascontiguousarray(texels, np.float32), dtype="f4")
    tex.repeat_x = tex.repeat_y = True
    tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    tex.build_mipmaps()
    return tex


@dataclass(eq=False)
class CloudNoise:
    """The cloud noise textures of one seed on one context (see the module docstring).

    Attributes:
        shape: 3D RGBA8 texture (shape_size^3), repeat wrap, trilinear, no mipmaps.
        detail: 3D RGBA8 texture (detail_size^3), repeat wrap, trilinear, no mipmaps.
        curl: 2D RG32F texture (curl_size^2), components in [-1, 1], repeat, mipmaps.
        seed: the seed they were drawn with.
        from_cache: True when the texels came from the disk cache (nothing was drawn).
    """

    ctx: object
    shape: moderngl.Texture3D
    detail: moderngl.Texture3D
    curl: moderngl.Texture
    seed: int
    from_cache: bool = False
    _key: tuple | None = field(default=None, repr=False)

    def release(self) -> None:
        """Release the textures and forget this set in the in-memory cache."""
        if _MEMORY.get(self._key) is self:
            del _MEMORY[self._key]
        for tex in (self.shape, self.detail, self.curl):
            tex.release()


#: Noise sets in GPU memory by (id(context), arguments).
_MEMORY: dict[tuple, CloudNoise] = {}


def cloud_noise(
    ctx,
    seed: int = 1,
    *,
    shape_size: int = DEFAULT_SHAPE_SIZE,
    detail_size: int = DEFAULT_DETAIL_SIZE,
    curl_size: int = DEFAULT_CURL_SIZE,
    cache: bool = True,
) -> CloudNoise:
    """The cloud noise textures of ``seed`` on ``ctx``: the set already in memory for these
    arguments, else the texels from the disk cache, else drawn (and stored when ``cache``).

    Args:
        ctx: a moderngl context (OpenGL 3.3).
        seed: integer in [0, 2^31 - 1]; the same seed gives bit-identical textures.
        shape_size, detail_size: texels per axis of the 3D textures (powers of two, 4-512).
        curl_size: texels per axis of the curl texture (power of two, 4-4096).
        cache: read and write the disk cache.
    """
    seed = check_seed(seed)
    shape_size = check_size("shape_size", shape_size, 4, 512)
    detail_size = check_size("detail_size", detail_size, 4, 512)
    curl_size = check_size("curl_size", curl_size, 4, 4096)
    mem_key = (id(ctx), seed, shape_size, detail_size, curl_size)
    held = _MEMORY.get(mem_key)
    if held is not None and held.ctx is ctx:
        return held

    def build() -> dict[str, np.ndarray]:
        return {
            "shape": render_shape(ctx, seed, shape_size),
            "detail": render_detail(ctx, seed, detail_size),
            "curl": render_curl(ctx, seed, curl_size),
        }

    if cache:
        expected = {
            "shape": (shape_size,) * 3 + (4,),
            "detail": (detail_size,) * 3 + (4,),
            "curl": (curl_size, curl_size, 2),
        }

        def decode(arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
            for n, s in expected.items():
                a = arrays.get(n)
                if a is None or a.shape != s or a.dtype != np.float32 or not np.isfinite(a).all():
                    raise CacheError(f"cloud noise {n!r} is not finite float32 of shape {s}")
            return arrays

        arrays, loaded = load_or_build(
            noise_key(seed, shape_size, detail_size, curl_size),
            build,
            name="cloud-noise",
            meta={"seed": seed},
            decode=decode,
        )
    else:
        arrays, loaded = build(), False
    noise = CloudNoise(
        ctx=ctx,
        shape=_volume_texture(ctx, arrays["shape"]),
        detail=_volume_texture(ctx, arrays["detail"]),
        curl=_plane_texture(ctx, arrays["curl"]),
        seed=seed,
        from_cache=loaded,
        _key=mem_key,
    )
    _MEMORY[mem_key] = noise
    return noise
