"""Image-based lighting from the sky for a 3D scene: the split-sum approximation of Karis 2013
("Real Shading in Unreal Engine 4", SIGGRAPH course notes): a prefiltered specular cube map
with a mip chain, and the BRDF table that goes with it.

>>> from skydome import Sky
>>> from skydome.lighting_ibl import brdf_table, prefilter
>>> with Sky("Valletta", "2018-03-01T10:00") as sky:               # doctest: +SKIP
...     light = sky.lighting()
...     cube = light.prefiltered(sky.graph.ctx)                    # the sky alone
...     table = brdf_table(sky.graph.ctx)

A GGX surface's specular light under the sky is, in the split sum,
``prefiltered(r, roughness) * (F0 * scale + bias)`` with r the reflected view direction and
``(scale, bias) = table(n.v, roughness)``.

**The prefiltered cube** (:func:`prefilter`): from the equirect map of the sky in cd/m^2
(:attr:`skydome.lighting.Lighting.sky_map`, the Sun's and the Moon's disks split out), for
every texel direction n, with Karis' n = v = r,

    L(n) = sum_k L(l_k) (n.l_k) / sum_k (n.l_k),

l_k the reflections of half vectors drawn from the GGX lobe (Trowbridge-Reitz, alpha =
roughness^2) by Hammersley points, each read from the map's mip chain at the level whose
texel has the sample's solid angle 1 / (N pdf), plus one, and at most the level of
:data:`MIN_ROWS` rows (filtered importance sampling, Colbert & Krivanek 2007: a bright small
feature is spread over the lobe, not hit or missed by a few samples); the map's mip levels
average its texels by solid angle (:func:`weighted_map`), so that every level of the cube
keeps the map's mean (within 0.3 %: tests/test_lighting_ibl.py). Mip level k of a face of
n texels has n / 2^k texels and **roughness k / (levels - 1)**, levels = log2(n) - 1 (the
chain stops at 4 x 4: :data:`LAST_FACE_SIZE`; 6 levels for 128 texels, roughness 0, 0.2,
..., 1): read it with
``textureLod(cube, r, roughness * (levels - 1))``. Level 0 (roughness 0, a mirror) is the map
itself, read bilinearly at the texels' directions. The values stay cd/m^2.

The Sun: by default the cube holds the sky alone, since renderers treat the Sun as a light
of its own (a directional light of :attr:`Lighting.sun`'s illuminance: the cube holding it
too would light the scene twice). ``with_sun=True`` adds it as a point source of its
illuminance E: at level 0 into the texel it falls in (E / the texel's solid angle), at the
rougher levels as the estimator's limit for a delta, E D(n.h) (n.s) / 4 / mean(n.l).

**Faces and axes**: the file formats' (OpenGL and Direct3D address cube faces alike:
OpenGL 4.6, table 8.19): faces +X, -X, +Y, -Y, +Z, -Z, each's first row t = 0. The cube's
axes are (x, y, z) = (east, up, north), a y-up, left-handed frame (Direct3D's, Unity's): a
world direction (east, north, up) in our ENU frame is looked up as (east, up, north).
:func:`cube_directions` gives every texel's ENU direction.

**The BRDF table** (:func:`brdf_table`): scale and bias of F0 for n.v = (i + 0.5) / size
(columns) and roughness = (j + 0.5) / size (rows, the first row roughness ~0), Karis'
IntegrateBRDF with his Schlick-GGX visibility (k = alpha / 2, the choice for image
lighting; not the height-correlated Smith term): :data:`TABLE_SAMPLES` Hammersley half
vectors a texel.

Both run on the GPU as fragment shaders (``shaders/lighting/``) in the context given (the
Sky's: ``sky.graph.ctx``; default the shared headless one), and release every GL object
they make before they return.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skydome.errors import ParameterError
from skydome.gpu import FullscreenPass, shared_context
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.textures import FloatTargets, release_all
from skydome.spectra import SRGB_LUMINANCE

#: Face size of the cube map by default (texels).
DEFAULT_FACE_SIZE = 128
#: GGX samples per texel of the prefilter (with filtered importance sampling, 256 leave no
#: visible noise; Karis' example uses 1024 without it).
DEFAULT_SAMPLES = 256
#: Size of the BRDF table by default (n.v and roughness).
DEFAULT_TABLE_SIZE = 128
#: GGX samples per texel of the BRDF table. Karis' 1024 leave errors of 0.01 at grazing n.v
#: and roughness 0.25 (against a quadrature: tests/test_lighting_ibl.py); the error falls as
#: 1 / N (Hammersley points): 0.001 with 16384 (1.2 s for 128 x 128 on llvmpipe).
TABLE_SAMPLES = 16384
#: What the BRDF table's file says it is (its EXR header).
TABLE_DESCRIPTION = (
    "split-sum BRDF table (Karis 2013): R = scale, G = bias of F0; column i: n.v = (i + 0.5) "
    "/ width; row j (top first): roughness = (j + 0.5) / height, alpha = roughness^2; GGX with "
    "Schlick-GGX visibility k = alpha / 2"
)
#: The last mip level's face size (texels): 4 x 4. A 1 x 1 face would hold only the six axes'
#: values, whose mean is not the sphere's (the 6-point rule is exact to degree 3 only: 1 %
#: off for a daylight sky at roughness 1, measured 1-2 %); 4 x 4 hold roughness 1 (a lobe as
#: wide as a cosine) within 0.15 %.
LAST_FACE_SIZE = 4
#: The map's mip levels read stop where it has this many rows (11 deg for 16): coarser, the
#: bilinear blend between an equirect level's latitude rows no longer weighs them by solid
#: angle (the rows nearest the poles count 6 % too much at 4 rows), and the cube's mean
#: drifts (measured 0.8 % at roughness 1 with no limit, 0.3 % with this one).
MIN_ROWS = 16
#: The faces in file order, as (axis in cube space, its ENU direction).
FACES = ("+X east", "-X west", "+Y up", "-Y down", "+Z north", "-Z south")


@dataclass(frozen=True)
class PrefilteredCube:
    """A prefiltered specular cube map: ``levels[k]`` float32 (6, n_k, n_k, 3), cd/m^2,
    faces +X, -X, +Y, -Y, +Z, -Z (cube space (east, up, north)), row 0 = t = 0;
    ``roughness[k]`` = k / (len(levels) - 1); ``with_sun``: the Sun is in it."""

    levels: tuple[np.ndarray, ...]
    roughness: tuple[float, ...]
    with_sun: bool = False

    @property
    def face_size(self) -> int:
        return int(self.levels[0].shape[1])

    def mean(self, level: int) -> np.ndarray:
        """The level's RGB mean over the sphere (each texel weighted by its solid angle),
        cd/m^2."""
        data = np.asarray(self.levels[level], dtype=np.float64)
        omega = cube_texel_solid_angles(data.shape[1])
        return np.einsum("fijc,ij->c", data, omega) / (4.0 * math.pi)

    def cross(self, level: int) -> np.ndarray:
        """The level's faces as a horizontal cross (3n, 4n, 3) float32, cd/m^2, zero
        outside: -X, +Z, +X, -Z (west, north, east, south) in the middle row, +Y (up) above
        and -Y (down) below +Z, each face as stored (row 0 at the top): a view from inside
        the cube, north ahead, whose edges join (a preview of the file)."""
        faces = self.levels[level]
        n = faces.shape[1]
        out = np.zeros((3 * n, 4 * n, 3), dtype=np.float32)
        places = ((1, 2), (1, 0), (0, 1), (2, 1), (1, 1), (1, 3))  # (row, column) of +X..-Z
        for face, (row, col) in enumerate(places):
            out[row * n : (row + 1) * n, col * n : (col + 1) * n] = faces[face]
        return out

    def mean_luminance(self, level: int) -> float:
        """The level's mean luminance (cd/m^2) over the sphere."""
        return float(self.mean(level) @ SRGB_LUMINANCE)


@dataclass(frozen=True)
class PrefilterInputs(ShaderInputs):
    """``lighting/prefilter_ggx.glsl``."""

    u_env: object
    u_face_size: float
    u_alpha: float
    u_env_texel_sr: float
    u_sun_dir: tuple
    u_sun_rgb: tuple


@dataclass(frozen=True)
class TableInputs(ShaderInputs):
    """``lighting/brdf_table.glsl``."""

    u_size: tuple


def chain_length(face_size: int) -> int:
    """Mip levels of a cube of ``face_size`` texels: down to LAST_FACE_SIZE texels a side."""
    return int(math.log2(face_size)) - int(math.log2(LAST_FACE_SIZE)) + 1


def level_roughness(levels: int) -> tuple[float, ...]:
    """The roughness of mip levels 0..levels-1: k / (levels - 1) (0 for a single level)."""
    return tuple(k / max(levels - 1, 1) for k in range(levels))


def check_face_size(face_size) -> int:
    """``face_size`` as an int: a power of two from 4 to 2048, or ParameterError."""
    n = face_size
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 8 <= n <= 2048:
        raise ParameterError(f"cube size {face_size!r} must be a power of two from 8 to 2048")
    if n & (n - 1):
        raise ParameterError(f"cube size {face_size!r} must be a power of two from 8 to 2048")
    return int(n)


def cube_directions(face_size: int) -> np.ndarray:
    """Unit ENU directions (6, n, n, 3) of the texel centres of a cube face of ``face_size``
    texels, faces +X, -X, +Y, -Y, +Z, -Z in cube space (east, up, north), row t, column s
    (the twin of ``lighting/cube_faces.glsl``)."""
    n = int(face_size)
    s = (np.arange(n) + 0.5) / n * 2.0 - 1.0
    tc, sc = np.meshgrid(s, s, indexing="ij")
    one = np.ones_like(sc)
    cube = np.stack(
        [
            np.stack([one, -tc, -sc], -1),
            np.stack([-one, -tc, sc], -1),
            np.stack([sc, one, tc], -1),
            np.stack([sc, -one, -tc], -1),
            np.stack([sc, -tc, one], -1),
            np.stack([-sc, -tc, -one], -1),
        ]
    )
    cube /= np.linalg.norm(cube, axis=-1, keepdims=True)
    return cube[..., [0, 2, 1]]  # (east, up, north) -> (east, north, up)


def cube_texel_solid_angles(face_size: int) -> np.ndarray:
    """Exact solid angles (sr) of a face's texels (n, n), the same on every face: the
    rectangle [x0, x1] x [y0, y1] of the face at distance 1 subtends
    A(x1, y1) - A(x0, y1) - A(x1, y0) + A(x0, y0), A(x, y) = atan(x y / sqrt(x^2 + y^2 + 1))."""
    e = np.linspace(-1.0, 1.0, int(face_size) + 1)
    x, y = np.meshgrid(e, e, indexing="ij")
    a = np.arctan2(x * y, np.sqrt(x * x + y * y + 1.0))
    return a[1:, 1:] - a[:-1, 1:] - a[1:, :-1] + a[:-1, :-1]


def _context(ctx):
    return ctx if ctx is not None else shared_context()


def _check_samples(samples, what: str) -> int:
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)):
        raise ParameterError(f"{what} samples {samples!r} must be an integer from 1 to 65536")
    if not 1 <= samples <= 65536:
        raise ParameterError(f"{what} samples {samples!r} must be an integer from 1 to 65536")
    return int(samples)


def _env_map(sky_map) -> np.ndarray:
    data = getattr(sky_map, "data", sky_map)
    data = np.asarray(data)
    if data.ndim != 3 or data.shape[-1] < 3 or data.shape[1] != 2 * data.shape[0]:
        raise ParameterError(
            f"the sky map must be an equirect (H, 2H, 3 or 4) array, got shape {data.shape}"
        )
    if not np.all(np.isfinite(data[..., :3])):
        raise ParameterError("the sky map holds NaN or Inf")
    return np.asarray(data[..., :3], dtype=np.float64)


def weighted_map(radiance: np.ndarray) -> np.ndarray:
    """The texture the prefilter reads (H, W, 4) float32: each texel's radiance times its
    weight w = cos(latitude) (its solid angle's share) in RGB and w in A, so that the mip
    chain's 2 x 2 box averages, divided RGB / A, are means weighted by solid angle (a plain
    mip chain of an equirect map over-weights the poles: the last levels' mean would be the
    pixels', not the sphere's)."""
    h = radiance.shape[0]
    w = np.cos((0.5 - (np.arange(h) + 0.5) / h) * math.pi)[:, None, None]
    return np.concatenate(
        [radiance * w, np.broadcast_to(w, (*radiance.shape[:2], 1))], axis=-1
    ).astype(np.float32)


def prefilter(
    sky_map,
    ctx=None,
    *,
    face_size: int = DEFAULT_FACE_SIZE,
    samples: int = DEFAULT_SAMPLES,
    sun=None,
) -> PrefilteredCube:
    """The prefiltered specular cube of an equirect ``sky_map`` (a Frame or an (H, 2H, 3|4)
    array in cd/m^2, rows top first, north at the left edge, east a quarter in; see the
    module docstring), faces of ``face_size`` texels (a power of two, 4-2048), a full mip
    chain, ``samples`` GGX samples a texel. ``sun``: None (the sky alone), or a light with
    ``direction`` (unit ENU) and ``illuminance_rgb`` (lx facing it) to add as a point source
    (e.g. :attr:`Lighting.sun`). Runs in ``ctx`` (default the shared headless context)."""
    n = check_face_size(face_size)
    samples = _check_samples(samples, "prefilter")
    env = _env_map(sky_map)
    h, w = env.shape[:2]
    sun_dir, sun_rgb = (0.0, 0.0, 1.0), (0.0, 0.0, 0.0)
    if sun is not None:
        d = np.asarray(sun.direction, dtype=np.float64)
        sun_dir = tuple(float(v) for v in d / np.linalg.norm(d))
        sun_rgb = tuple(float(v) for v in sun.illuminance_rgb)
    ctx = _context(ctx)
    levels_count = chain_length(n)
    max_lod = max(math.log2(h / MIN_ROWS), 0.0)
    roughness = level_roughness(levels_count)
    tex = shader = targets = None
    out = []
    try:
        tex = ctx.texture((w, h), 4, weighted_map(env).tobytes(), dtype="f4")
        tex.build_mipmaps()
        tex.filter = (ctx.LINEAR_MIPMAP_LINEAR, ctx.LINEAR)
        tex.repeat_x, tex.repeat_y = True, False
        shader = FullscreenPass(
            ctx,
            "lighting/prefilter_ggx.glsl",
            {"SAMPLES": samples, "MAX_LOD": f"{max_lod:.1f}"},
            inputs=(PrefilterInputs,),
        )
        targets = FloatTargets(ctx)
        for k, r in enumerate(roughness):
            m = n >> k
            target, fbo = targets.get(f"level{k}", (6 * m, m))
            fbo.viewport = (0, 0, 6 * m, m)
            shader.draw(
                fbo,
                PrefilterInputs(
                    u_env=tex,
                    u_face_size=float(m),
                    u_alpha=float(r * r),
                    u_env_texel_sr=(2.0 * math.pi / w) * (math.pi / h),
                    u_sun_dir=sun_dir,
                    u_sun_rgb=sun_rgb,
                ),
            )
            data = np.frombuffer(fbo.read(components=4, dtype="f4"), dtype=np.float32)
            faces = data.reshape(m, 6, m, 4).transpose(1, 0, 2, 3)[..., :3]
            out.append(np.ascontiguousarray(faces))
    finally:
        if targets is not None:
            targets.release()
        if shader is not None:
            shader.release()
        release_all(tex)
    return PrefilteredCube(tuple(out), roughness, sun is not None)


def brdf_table(
    ctx=None, size: int = DEFAULT_TABLE_SIZE, samples: int = TABLE_SAMPLES
) -> np.ndarray:
    """Karis' split-sum BRDF table (size, size, 2) float32: [j, i] = (scale, bias) of F0 at
    n.v = (i + 0.5) / size and roughness = (j + 0.5) / size (see the module docstring);
    ``size`` 8-1024. Runs in ``ctx`` (default the shared headless context)."""
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or not 8 <= size <= 1024:
        raise ParameterError(f"BRDF table size {size!r} must be an integer from 8 to 1024")
    samples = _check_samples(samples, "BRDF table")
    ctx = _context(ctx)
    shader = targets = None
    try:
        shader = FullscreenPass(
            ctx, "lighting/brdf_table.glsl", {"SAMPLES": samples}, inputs=(TableInputs,)
        )
        targets = FloatTargets(ctx)
        _, fbo = targets.get("table", (size, size))
        fbo.viewport = (0, 0, size, size)
        shader.draw(fbo, TableInputs(u_size=(float(size), float(size))))
        data = np.frombuffer(fbo.read(components=4, dtype="f4"), dtype=np.float32)
    finally:
        if targets is not None:
            targets.release()
        if shader is not None:
            shader.release()
    return np.ascontiguousarray(data.reshape(size, size, 4)[..., :2])
