"""Bruneton's precomputed atmospheric scattering with all orders, on the GPU (GLSL 3.30).

``precompute(ctx, params, config)`` fills the lookup tables that the renderer samples through
``shaders/atmosphere/precomputed_lookup.glsl`` (luminance in cd/m^2 for the params' solar spectrum, i.e.
Bruneton's precomputed-luminance mode, or raw transfer values of 4 wavelengths with
``output="spectral"``, a debugging mode):

* the transmittance table (column densities, ``transmittance.py``);
* ``scattering`` / ``single_mie``: single Rayleigh / Mie scattering without phase functions,
  4D (r, mu, mu_s, nu) in 3D textures, divided by a normalization F (the air density at the
  lowest sunlit point of the ray over that at its lowest point) that carries their steep fall
  in twilight, so that they can be interpolated linearly (float16 by default);
* ``multiple_scattering``: orders >= 2 divided by the Rayleigh phase function, stored as
  logarithms (interpolated geometrically: they fall exponentially in twilight);
* ``irradiance_spectral``: the sky irradiance on a horizontal surface (r, mu_s) per wavelength
  (per unit solar irradiance), so that the ground shading can apply a spectral albedo and
  illuminance is converted after summing the groups (``common/ground_shading.glsl``).

The algorithm (seed 004 ch. 5.2.2.3, Bruneton 2017) computes order n from order n - 1:
J_n = beta P (x) L_{n-1} (scattering density), L_n = integral T J_n (+ ground reflection),
E_n = integral L_n cos. The textbook loop does this on full 4D tables and spends nearly all its
time in J: texels x directions x wavelength passes (490 s here with 15 wavelengths). This
implementation reorganizes it (measured in ``benchmarks/bench_precompute.py``):

1. The radiance arriving at a point does not depend on the view direction, so for each
   (r, mu_s) of the grid of J it is evaluated once per direction of a sphere quadrature (the
   "field", a 2D texture); J for every (mu, nu) is then a sum over the field with phase
   functions only, without texture lookups. The first order of the field is marched directly
   from the transmittance table, not read from an interpolated table.
2. Orders >= 2 are smooth in view direction: J lives on a coarse grid (default 16 x 64 x 64 x 8
   in r, mu, mu_s, nu) and all the orders are integrated along the rays at once (the integral
   is linear in J: S_ms = integral T sum_n J_n), into a table of their own (32 x 64 x 64 x 8).
   Their mappings differ from the single-scattering ones: mu is sqrt of Bruneton's distance
   mapping (texels 40 degrees apart near the zenith otherwise) and mu_s follows the Sun's
   elevation above the point's own horizon, densest at its sunset (atmosphere/precomputed_params.glsl).
3. Orders >= 2 are computed at 4 wavelengths (smooth in wavelength) and interpolated; single
   scattering and the sky irradiance at all render wavelengths.
4. Quadratures: Gauss-Legendre along rays in a variable that makes the density smooth
   (16 nodes instead of 50), a product rule over the sphere split at the horizon and crowded
   towards it ((12 + 6) x 16 = 288 directions instead of 512), self-normalized for the Mie lobe.
6. Twilight: single scattering is stored divided by the lit-density normalization F and the
   orders >= 2 as logarithms, so that the 1-3 e-folds per degree of Sun depression are not
   interpolated linearly; the tables cover the Sun down to -20 degrees (``mu_s_min``).
5. 4 wavelengths per RGBA pass and all wavelength groups of a pass in one fragment (draw
   buffers), so the geometry and the transmittance lookups are shared by all wavelengths.
7. Several nu per fragment (one draw buffer each, ``views_per_fragment``; reordered on the
   read-back, ``interleave_views``; up to MAX_VIEWS = 4): the density pass fetches each
   direction of the field once for 4 nu of a (r, mu, mu_s) (the fetches were 3/4 of that pass
   on llvmpipe); the pass of the orders >= 2 marches a ray's nodes, columns and transmittances
   once for them (they do not depend on nu), and so does the field of orders >= 2 for 4
   azimuths of one cosine. Each pass 2-3x faster; the tables are bit-identical to one nu per
   fragment.
8. Symmetry: the field is mirror-symmetric about the Sun's vertical plane (the air is
   spherically symmetric), so the field pass draws the azimuths on one side of it and the
   others are their mirror images (``mirror_azimuths``; bit-identical to drawing them), and
   the density pass fetches each value once for a direction and its mirror image.
9. Above the aerosols (``mie_runs``: where they scatter below ``MIE_NEGLIGIBLE`` of the air)
   J's layers are drawn without the Mie sum, the Rayleigh sum taken from the field's moments.
"""

from __future__ import annotations

import itertools
import math
import time
import weakref
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from skydome.atmosphere.inputs import (
    AirGeometry,
    AirSpectra,
    LookupInputs,
    TransmittanceInputs,
    broadened_lobe_uniforms,
    geometry_inputs,
    mie_kink_radius_km,
    mie_phase_defines,
    profile_defines,
    spectra_inputs,
)
from skydome.atmosphere.params import AtmosphereParams
from skydome.atmosphere.precompute_config import MAX_GROUPS, PrecomputeConfig
from skydome.atmosphere.transmittance import TransmittanceTable
from skydome.errors import CacheError
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.textures import copy_array_to_3d, linear_clamped, release_unbound
from skydome.physics.packing import mat4, mat4_groups
from skydome.spectra import LINEAR_SRGB_TO_XYZ, XYZ_TO_LINEAR_SRGB, conversion_matrix

__all__ = [
    "PrecomputeConfig",
    "PrecomputedAtmosphere",
    "ProgressCallback",
    "conversion_matrix",
    "precompute",
    "transmittance_weights",
]

ProgressCallback = Callable[[str, float], None]

#: Range (natural-log units) of the 16-bit logarithmic tables: values from e^-48 (1.4e-21) of
#: the largest value of the table up to it, in steps of 48 / 65535 (0.073% relative).
LOG16_SPAN = 48.0
#: Largest stored value of a float16 single-scattering table (values are scaled to it): float16
#: keeps 11 significant bits from 6.1e-5 to 65504, so this leaves 4x headroom and 2^28 of range.
F16_TABLE_MAX = 16384.0

# ----------------------------------------------------------------------------------------------
# Spectral conversions
# ----------------------------------------------------------------------------------------------


def output_matrix(output: str = "rgbs") -> np.ndarray:
    """(4, 4) matrix from the tables' channels to lookup results: (X, Y, Z, S) -> (R, G, B, S).

    Tables hold (X, Y, Z, scotopic) luminance, which is non-negative for any spectrum (the
    colour-matching functions are), so that they can store logarithms; linear sRGB channels can
    be negative (saturated twilight colours are outside the sRGB gamut).
    """
    if output == "spectral":
        return np.eye(4)
    m = np.eye(4)
    m[:3, :3] = XYZ_TO_LINEAR_SRGB
    return m


def table_matrix(wavelengths_nm, output: str = "rgbs") -> np.ndarray:
    """(4, N) matrix from N transfer values to the tables' channels (see output_matrix)."""
    m = conversion_matrix(wavelengths_nm, output)
    if output == "spectral":
        return m
    to_xyzs = np.eye(4)
    to_xyzs[:3, :3] = LINEAR_SRGB_TO_XYZ
    return to_xyzs @ m


def transmittance_weights(wavelengths_nm, output: str = "rgbs") -> np.ndarray:
    """(4, N) non-negative weights, rows summing to 1, giving a transmittance per output channel.

    Tables store luminance, so attenuating stored light by a spectral transmittance T(λ) (the
    shadow of light shafts, or the in-scatter behind a point for aerial perspective) has to be
    done per channel: T_c = Σ_λ W[c, λ] T(λ), with W ∝ max(M[c, λ], 0)·(λ/550)^-4, the
    channel's response to a sky-blue (Rayleigh-like) spectrum. Exact when T is constant over a
    channel's band; Bruneton's luminance mode makes the same kind of approximation with 3
    wavelengths.
    """
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    if output == "spectral":
        return np.eye(4)
    m = np.maximum(conversion_matrix(wl, output), 0.0) * (wl / 550.0) ** -4
    return m / m.sum(axis=1, keepdims=True)


def behind_transmittance_weights(to_output: np.ndarray) -> np.ndarray:
    """(4, N) weights W with T_c = sum_l W[c, l] T(l) the transmittance of output channel c
    for light of the solar spectrum's shape: M[c, l] / sum_l M[c, l], M = ``to_output`` (the
    signed sRGB rows included: exact, since each channel is linear in the spectrum)."""
    m = np.asarray(to_output, dtype=np.float64)
    return m / m.sum(axis=1, keepdims=True)


def ms_log_interpolation(params: AtmosphereParams, to_nm, from_nm) -> np.ndarray | None:
    """(len(to), 4) matrix W with ln L(to) = W ln L(from), for 4 ``from`` wavelengths, or None.

    Radiance of the orders >= 2 is smooth in wavelength, but its shape is not linear: in twilight
    it is made by Rayleigh scattering (λ^-4) and the ozone Chappuis band. ln L is interpolated
    exactly through the 4 samples in the basis {1, ln λ, (λ/550)^-4, a(λ)}, a the absorber's
    extinction spectrum (or (ln λ)^2 when the absorber is absent or flat). Measured against
    orders >= 2 computed at all 16 wavelengths: 0.03-0.4% RMS in luminance from a 60 deg Sun to
    -12 deg, where linear interpolation in λ is off by 3-10%. None when there are not 4
    samples or the basis is ill-conditioned (then linear interpolation is used).
    """
    src = np.asarray(from_nm, dtype=np.float64)
    dst = np.asarray(to_nm, dtype=np.float64)
    if len(src) != 4:
        return None

    def basis(w: np.ndarray, absorber: bool) -> np.ndarray:
        x = np.log(w / 550.0)
        fourth = params.absorption_extinction.at(w) / scale if absorber else x * x
        return np.stack([np.ones_like(w), x, (w / 550.0) ** -4, fourth], axis=1)

    a = params.absorption_extinction.at(np.concatenate([src, dst]))
    scale = float(a.max())
    absorber = scale > 0 and float(np.ptp(params.absorption_extinction.at(src))) > 0.05 * scale
    b = basis(src, absorber)
    if np.linalg.cond(b) > 1e4:
        return None
    return basis(dst, absorber) @ np.linalg.inv(b)


def interpolation_matrix(to_nm, from_nm) -> np.ndarray:
    """(len(to), len(from)) linear interpolation in wavelength, held flat beyond the ends."""
    src = np.asarray(from_nm, dtype=np.float64)
    eye = np.eye(len(src))
    return np.stack(
        [np.interp(np.asarray(to_nm, float), src, eye[i]) for i in range(len(src))], axis=1
    )


# ----------------------------------------------------------------------------------------------
# Quadrature rules
# ----------------------------------------------------------------------------------------------


def gauss_legendre(n: int, a: float = -1.0, b: float = 1.0) -> np.ndarray:
    """(n, 2) Gauss-Legendre nodes and weights on [a, b]."""
    x, w = np.polynomial.legendre.leggauss(int(n))
    h = 0.5 * (b - a)
    return np.stack([a + h * (x + 1.0), h * w], axis=1)


@dataclass(frozen=True)
class QuadratureInputs(ShaderInputs):
    """The quadrature rules of ``atmosphere/precompute_common.glsl`` as (node, weight)
    pairs: along rays (n, n/2, and n/4, n/8, 3n/4 when n is a multiple of 8 nodes on [0, 1]),
    over the view cosine above and below the horizon and over azimuth (cos, sin), and over
    the cosine for the irradiance."""

    u_ray_rule: list[float]
    u_ray_rule_half: list[float]
    u_ray_rule_quarter: list[float] | None = None
    u_ray_rule_eighth: list[float] | None = None
    u_ray_rule_three_quarters: list[float] | None = None
    u_mu_rule_sky: list[float] | None = None
    u_mu_rule_ground: list[float] | None = None
    u_phi_cs: list[float] | None = None
    u_irr_mu_rule: list[float] | None = None


@dataclass(frozen=True)
class PrecomputeInputs(ShaderInputs):
    """A stage of the precomputation (``atmosphere/precompute_*.glsl``): the air and its
    transmittance, the quadrature rules, the lit-density normalisation's mapping, the
    conversion of spectral values to the tables' channels, and the stage's own tables and
    sizes (None where a stage has none)."""

    geometry: AirGeometry
    spectra: AirSpectra
    transmittance: TransmittanceInputs
    rules: QuadratureInputs
    u_kink_radius: float
    u_mu_s_min: float
    u_mu_s_knee: float
    u_spectral_to_table: list[float]
    u_density_size: tuple[float, float, float, float] | None = None
    u_ms_size: tuple[float, float, float, float] | None = None
    u_scattering_size: tuple[float, float, float, float] | None = None
    u_table_scale: float | None = None
    u_irradiance_size: tuple[float, float] | None = None
    u_part_stride: int | None = None
    u_ms_log_interp: list[float] | None = None
    u_render_to_table: list[float] | None = None
    u_density: object = None
    u_field: object = None
    u_ground_irradiance: object = None


def quadrature_rules(
    ray_samples: int,
    directions: tuple[int, int, int] | None = None,
    irradiance_mu: int | None = None,
) -> QuadratureInputs:
    """The Gauss-Legendre rules of a stage: ``ray_samples`` nodes along rays; the
    ``directions`` (sky, ground, azimuth) of the sphere quadrature; ``irradiance_mu``
    cosines of the irradiance."""
    n = int(ray_samples)

    def rule(k: int, a: float = 0.0, b: float = 1.0) -> list[float]:
        return gauss_legendre(k, a, b).ravel().tolist()

    extra = {}
    if n % 8 == 0:
        extra = dict(
            u_ray_rule_quarter=rule(n // 4),
            u_ray_rule_eighth=rule(n // 8),
            u_ray_rule_three_quarters=rule(3 * n // 4),
        )
    if directions is not None:
        n_sky, n_ground, n_phi = directions
        phi = (np.arange(n_phi) + 0.5) * 2.0 * math.pi / n_phi
        extra.update(
            u_mu_rule_sky=rule(n_sky, -1.0, 1.0),
            u_mu_rule_ground=rule(n_ground, -1.0, 1.0),
            u_phi_cs=np.stack([np.cos(phi), np.sin(phi)], axis=1).ravel().tolist(),
        )
    if irradiance_mu is not None:
        extra["u_irr_mu_rule"] = rule(int(irradiance_mu), -1.0, 1.0)
    return QuadratureInputs(rule(n), rule(n // 2), **extra)


# ----------------------------------------------------------------------------------------------
# GL helpers
# ----------------------------------------------------------------------------------------------

_PROGRAMS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _program(
    ctx, name: str, defines: dict[str, object], layered: bool = False, inputs: tuple = ()
) -> FullscreenPass:
    """A compiled pass of a stage (inputs: ``PrecomputeInputs``, or ``inputs``), cached per
    context (compiling costs ~0.1 s on llvmpipe)."""
    inputs = inputs or (PrecomputeInputs,)
    cache = _PROGRAMS.setdefault(ctx, {})
    key = (name, tuple(sorted(defines.items())), layered, inputs)
    if key not in cache:
        cache[key] = FullscreenPass(ctx, name, defines, inputs=inputs, layered=layered)
    return cache[key]


def _nearest(tex, ctx):
    tex.filter = (ctx.NEAREST, ctx.NEAREST)
    tex.repeat_x = tex.repeat_y = False
    return tex


def _read_array(tex, dtype: str = "f4") -> np.ndarray:
    """A texture array or 3D texture as (depth, height, width, 4)."""
    w, h, d = tex.size
    return np.frombuffer(tex.read(), dtype=dtype).reshape(d, h, w, 4)


def _read_2d(tex) -> np.ndarray:
    w, h = tex.size
    return np.frombuffer(tex.read(), dtype="f4").reshape(h, w, 4)


class _Stages:
    """Per-stage wall-clock timings (each stage ends with ctx.finish())."""

    def __init__(self, ctx, progress: ProgressCallback | None, total_work: float):
        self.ctx = ctx
        self.progress = progress
        self.times: dict[str, float] = {}
        self.total_work = max(total_work, 1e-9)
        self.done = 0.0
        self.t0 = time.perf_counter()

    def run(self, stage: str, work: float, fn, *args):
        t = time.perf_counter()
        out = fn(*args)
        self.ctx.finish()
        self.times[stage] = self.times.get(stage, 0.0) + time.perf_counter() - t
        self.done += work
        if self.progress is not None:
            self.progress(stage, min(self.done / self.total_work, 1.0))
        return out


# ----------------------------------------------------------------------------------------------
# The result
# ----------------------------------------------------------------------------------------------


@dataclass(eq=False)
class PrecomputedAtmosphere:
    """Lookup tables of one atmosphere on the GPU, ready for ``atmosphere/precomputed_lookup.glsl``.

    Bind ``textures()`` and set ``uniforms()`` on a pass compiled with ``defines()`` that
    includes ``atmosphere/precomputed_lookup.glsl``. Lookups return (R, G, B, scotopic) in cd/m^2 (radiance)
    or lx (irradiance) for the params' solar spectrum at unit scale.

    Tables (see the shaders for their exact encodings): ``scattering`` and ``single_mie``
    (single scattering / F, times ``table_scale``), ``multiple_scattering`` (ln of orders >= 2,
    16-bit with ``multiple_log_range`` = (lo, span) or float32), ``irradiance_spectral`` (ln of
    the sky irradiance per wavelength group), and the transmittance (column densities).
    """

    ctx: object
    params: AtmosphereParams
    config: PrecomputeConfig
    transmittance_texture: object
    transmittance_size: tuple[int, int]
    scattering: object
    single_mie: object
    multiple_scattering: object
    irradiance_spectral: object
    mu_s_min: float
    table_scale: float = 1.0
    multiple_log_range: tuple[float, float] = (0.0, 1.0)
    orders_computed: int = 0
    timings: dict[str, float] = field(default_factory=dict)
    _inputs: LookupInputs | None = field(default=None, repr=False)

    @property
    def wavelengths_nm(self) -> np.ndarray:
        return self.config.render_wavelengths

    @property
    def groups(self) -> int:
        return len(self.wavelengths_nm) // 4

    def defines(self) -> dict[str, object]:
        """Preprocessor defines the lookup shader needs."""
        return {
            "NUM_GROUPS": self.groups,
            **profile_defines(self.params),
            **mie_phase_defines(self.params),
        }

    def inputs(self) -> LookupInputs:
        """The tables as ``atmosphere/precomputed_lookup.glsl`` reads them (made once)."""
        if self._inputs is None:
            cfg = self.config
            wl = self.wavelengths_nm
            to_output = conversion_matrix(wl, cfg.output)
            self._inputs = LookupInputs(
                geometry=geometry_inputs(self.params),
                spectra=spectra_inputs(self.params, wl, cfg.output),
                transmittance=TransmittanceInputs(
                    self.transmittance_texture, self.transmittance_size
                ),
                u_transmittance_to_output=mat4_groups(transmittance_weights(wl, cfg.output)),
                u_table_to_output=mat4(output_matrix(cfg.output)),
                u_mu_s_min=self.mu_s_min,
                u_mu_s_knee=math.radians(cfg.mu_s_knee_deg),
                u_scattering_size=cfg.glsl_size(cfg.scattering_size),
                u_scattering_scale=1.0 / self.table_scale,
                u_multiple_scattering_size=cfg.glsl_size(cfg.multiple_size),
                u_multiple_scattering_log_range=tuple(self.multiple_log_range),
                u_irradiance_size=tuple(float(s) for s in cfg.irradiance_size),
                # the light behind the air: per-channel weights of its spectral
                # transmittance (exact for light of the solar spectrum's shape)
                u_behind_transmittance=mat4_groups(behind_transmittance_weights(to_output)),
                u_scattering_texture=self.scattering,
                u_single_mie_texture=self.single_mie,
                u_multiple_scattering_texture=self.multiple_scattering,
                u_irradiance_spectral=self.irradiance_spectral,
            )
        return self._inputs

    def memory_bytes(self) -> int:
        """GPU memory of the tables (bytes)."""
        return int(sum(self.config.memory_bytes().values()))

    # -------------------------------------------------------------- arrays (for the disk cache)
    def to_arrays(self) -> dict[str, np.ndarray]:
        """The tables as NumPy arrays, exactly as stored on the GPU.

        ``scattering``/``single_mie``: (r, mu, nu * mu_s, 4) float16 or float32;
        ``multiple_scattering``: (r, mu, nu * mu_s, 4) uint16 or float32;
        ``irradiance_spectral``: (groups, r, mu_s, 4) float32
        ln(E / E_sun); ``transmittance``: (r, mu, 3) float32 column densities (km); ``meta``:
        mu_s_min, table_scale, multiple_log_range, orders computed.
        """
        cfg = self.config
        tw, th = self.transmittance_size
        trans = np.frombuffer(self.transmittance_texture.read(), dtype="f4").reshape(th, tw, 4)
        ew, eh = cfg.irradiance_size
        spec = _read_2d(self.irradiance_spectral).reshape(self.groups, eh, ew, 4)
        meta = [self.mu_s_min, self.table_scale, *self.multiple_log_range, self.orders_computed]
        return {
            "transmittance": trans[..., :3].copy(),
            "scattering": _read_array(self.scattering, _NP_DTYPE[cfg.dtype]).copy(),
            "single_mie": _read_array(self.single_mie, _NP_DTYPE[cfg.dtype]).copy(),
            "multiple_scattering": _read_array(
                self.multiple_scattering, _NP_DTYPE[cfg.ms_dtype]
            ).copy(),
            "irradiance_spectral": spec.copy(),
            "meta": np.array(meta, dtype=np.float64),
        }

    @classmethod
    def from_arrays(
        cls, ctx, params: AtmosphereParams, config: PrecomputeConfig, arrays: dict[str, np.ndarray]
    ) -> PrecomputedAtmosphere:
        """Rebuild the GL tables from ``to_arrays()`` output; CacheError if they do not fit."""
        cfg = config
        w, h, d = cfg.table_shape(cfg.scattering_size)
        wm, hm, dm = cfg.table_shape(cfg.multiple_size)
        tw, th = cfg.transmittance_size
        ew, eh = cfg.irradiance_size
        groups = len(cfg.render_wavelengths) // 4
        expect = {
            "transmittance": ((th, tw, 3), "f4"),
            "scattering": ((d, h, w, 4), _NP_DTYPE[cfg.dtype]),
            "single_mie": ((d, h, w, 4), _NP_DTYPE[cfg.dtype]),
            "multiple_scattering": ((dm, hm, wm, 4), _NP_DTYPE[cfg.ms_dtype]),
            "irradiance_spectral": ((groups, eh, ew, 4), "f4"),
            "meta": ((5,), "f8"),
        }
        for name, (shape, kind) in expect.items():
            a = arrays.get(name)
            if a is None or tuple(a.shape) != shape or a.dtype != np.dtype(kind):
                got = None if a is None else (tuple(a.shape), str(a.dtype))
                raise CacheError(f"precomputed table {name!r} is {got}, expected {(shape, kind)}")
            if a.dtype.kind == "f" and not np.all(np.isfinite(a)):
                raise CacheError(f"precomputed table {name!r} holds non-finite values")

        def tex3d(a, size, dtype):
            data = np.ascontiguousarray(a).tobytes()
            return linear_clamped(ctx.texture3d(size, 4, data, dtype=_GL_DTYPE[dtype]), ctx)

        def tex2d(a, size):
            return linear_clamped(
                ctx.texture(size, 4, np.ascontiguousarray(a, dtype="f4").tobytes(), dtype="f4"), ctx
            )

        trans = np.zeros((th, tw, 4), dtype="f4")
        trans[..., :3] = arrays["transmittance"]
        spec = arrays["irradiance_spectral"].reshape(groups * eh, ew, 4)
        meta = [float(x) for x in arrays["meta"]]
        return cls(
            ctx, params, cfg, tex2d(trans, (tw, th)), (tw, th),
            tex3d(arrays["scattering"], (w, h, d), cfg.dtype),
            tex3d(arrays["single_mie"], (w, h, d), cfg.dtype),
            tex3d(arrays["multiple_scattering"], (wm, hm, dm), cfg.ms_dtype),
            tex2d(spec, (ew, eh * groups)),
            meta[0], meta[1], (meta[2], meta[3]), int(meta[4]), {},
        )  # fmt: skip

    def gl_textures(self) -> list:
        """Every GL texture these tables own (what :meth:`release` frees)."""
        return [
            self.transmittance_texture,
            self.scattering,
            self.single_mie,
            self.multiple_scattering,
            self.irradiance_spectral,
        ]

    def release(self) -> None:
        for tex in self.gl_textures():
            tex.release()


_GL_DTYPE = {"f2": "f2", "f4": "f4", "u2": "nu2"}
#: Values a slice of the tables' encoding converts at once (2 MB of float64).
ENCODE_SLICE = 1 << 18
_NP_DTYPE = {"f2": "f2", "f4": "f4", "u2": "u2"}


def encode_log_table(log_values: np.ndarray, dtype: str) -> tuple[np.ndarray, tuple[float, float]]:
    """A table of natural logarithms -> stored values and (lo, span): ln v = lo + span * stored."""
    if dtype == "f4":
        return np.ascontiguousarray(log_values, dtype="f4"), (0.0, 1.0)
    hi = float(log_values.max())
    lo = hi - LOG16_SPAN

    def encode(part: np.ndarray) -> np.ndarray:
        return np.clip(np.rint((part.astype(np.float64) - lo) * (65535.0 / LOG16_SPAN)), 0, 65535)

    return convert_in_slices(log_values, np.uint16, encode), (lo, LOG16_SPAN)


def convert_in_slices(values: np.ndarray, dtype, convert: Callable) -> np.ndarray:
    """``convert(values)`` stored as ``dtype``, computed ENCODE_SLICE values at a time: a
    fresh float64 copy of a whole table (32 MB) costs more in page faults than its
    arithmetic."""
    out = np.empty(values.shape, dtype)
    flat, stored = values.reshape(-1), out.reshape(-1)
    for start in range(0, flat.size, ENCODE_SLICE):
        part = slice(start, start + ENCODE_SLICE)
        stored[part] = convert(flat[part])
    return out


#: The least normal float16 (2^-14); below it float16 holds multiples of 2^-24.
_F16_MIN_NORMAL = np.float32(2.0**-14)


def to_float16(values: np.ndarray) -> np.ndarray:
    """``values`` (float32) as float16, the same bits as ``values.astype(np.float16)``.

    NumPy converts values below float16's normal range (|x| < 2^-14) on a slow path (240 ms
    for 4M values of a single-scattering table against 10 ms for normal ones): here those
    are rounded as multiples of 2^-24 by ``np.rint`` (half to even, as the IEEE conversion;
    x 2^24 is exact in float32) and their bits put in place of the fast path's zeros.
    """
    magnitude = np.abs(values)
    small = magnitude < _F16_MIN_NORMAL
    normal = np.where(small, np.float32(0.0), values).astype(np.float16).view(np.uint16)
    np.minimum(magnitude, _F16_MIN_NORMAL, out=magnitude)
    magnitude *= np.float32(2.0**24)
    subnormal = np.rint(magnitude, out=magnitude).astype(np.uint16)
    subnormal |= np.signbit(values).astype(np.uint16) << 15
    return np.where(small, subnormal, normal).view(np.float16)


# ----------------------------------------------------------------------------------------------
# The precomputation
# ----------------------------------------------------------------------------------------------


def precompute(
    ctx,
    params: AtmosphereParams,
    config: PrecomputeConfig | None = None,
    *,
    progress: ProgressCallback | None = None,
) -> PrecomputedAtmosphere:
    """Precompute the scattering and irradiance tables of ``params`` (see the module docstring).

    ``progress(stage, fraction)`` is called after each stage with the fraction of the work done.
    Stage timings (s) are in the result's ``timings``; ``timings["total"]`` is the sum.
    """
    cfg = config or PrecomputeConfig()
    return _Precomputation(ctx, params, cfg, progress).run()


class _Precomputation:
    def __init__(self, ctx, params: AtmosphereParams, cfg: PrecomputeConfig, progress):
        self.ctx, self.params, self.cfg = ctx, params, cfg
        self.wl = cfg.render_wavelengths
        self.ms_wl = cfg.multiple_wavelengths
        self.groups = len(self.wl) // 4
        self.ms_groups = len(self.ms_wl) // 4
        self.mu_s_min = cfg.resolved_mu_s_min(
            params.bottom_radius_m, params.top_radius_m, params.mu_s_min
        )
        n_ms = max(cfg.orders - 1, 0)
        # Rough relative costs of the stages at default settings, for the progress fraction.
        self.stages = _Stages(ctx, progress, 1.0 + 0.3 + 0.5 * n_ms + 0.5 + 3.0 + 0.5)
        self._released: list = []
        self._field_targets: dict[int, tuple] = {}  # views per fragment -> (parts, fbo)

    # ------------------------------------------------------------------ small helpers
    def _keep(self, obj):
        self._released.append(obj)
        return obj

    def _inputs(self, wl, rules: QuadratureInputs, to_table=None, **stage) -> PrecomputeInputs:
        """A stage's inputs at the wavelengths ``wl`` (to the tables' channels by
        ``to_table``, default ``table_matrix``), with its ``rules`` and ``stage`` fields."""
        cfg = self.cfg
        return PrecomputeInputs(
            geometry=self.geometry,
            spectra=spectra_inputs(self.params, wl, cfg.output),
            transmittance=self.transmittance_inputs,
            rules=rules,
            u_kink_radius=mie_kink_radius_km(self.params),
            u_mu_s_min=self.mu_s_min,
            u_mu_s_knee=math.radians(cfg.mu_s_knee_deg),
            u_spectral_to_table=mat4_groups(
                table_matrix(wl, cfg.output) if to_table is None else to_table
            ),
            **stage,
        )

    def _to_3d(self, arr, dtype: str = "f4"):
        """Copy a float32 texture array into a new (linearly filtered) 3D texture."""
        tex = linear_clamped(self.ctx.texture3d(arr.size, 4, dtype=dtype), self.ctx)
        copy_array_to_3d(self.ctx, arr, tex)
        return tex

    # ------------------------------------------------------------------ stages
    def run(self) -> PrecomputedAtmosphere:
        cfg, ctx = self.cfg, self.ctx
        st = self.stages
        try:
            self.transmittance = st.run(
                "transmittance", 1.0, TransmittanceTable, ctx, self.params,
                cfg.transmittance_size, cfg.transmittance_steps,
            )  # fmt: skip
            self.geometry = geometry_inputs(self.params)
            self.transmittance_inputs = TransmittanceInputs(
                self.transmittance.texture, self.transmittance.size
            )
            self._setup_ms()
            orders = 1
            j_total = None
            ratio_before = j_prev = scratch = None
            if cfg.orders >= 2:
                st.run("field", 0.3, self._field, 1)
                st.run("ground_irradiance", 0.01, self._ground_irradiance)
                for n in range(2, cfg.orders + 1):
                    log_j = st.run("density", 0.4, self._density)
                    orders = n
                    # in float64, into arrays made once: J's grid is 34 MB, and a fresh array
                    # of it costs its page faults (~60 ms) besides the arithmetic (~6 ms)
                    keep = cfg.tolerance > 0  # j_n is then the next order's j_prev
                    if j_total is None:
                        j_total = np.exp(log_j, dtype=np.float64)
                        j_n = j_total.copy() if keep else j_total
                    else:
                        if keep or scratch is None:
                            scratch = np.empty_like(j_total)
                        j_n = np.exp(log_j, out=scratch, dtype=np.float64)
                        j_total += j_n
                    if n == cfg.orders:
                        break
                    # the series' sums and ratios with a tolerance only (each reads J's grid)
                    ratio = None
                    if cfg.tolerance > 0:
                        added = float(j_n.sum()) / max(float(j_total.sum()), 1e-300)
                        if added < cfg.tolerance:
                            break
                        if j_prev is not None:
                            ratio = order_ratio(j_n, j_prev, self.ms_groups)
                        j_prev = j_n
                    settling = cfg.tolerance > 0 and n >= FIRST_SETTLED_ORDER
                    if settling and geometric(ratio, ratio_before):
                        # the orders fall geometrically: the rest of the series, added at
                        # once (each later order the last times the ratio, per wavelength)
                        j_total = j_total + tail(j_n, ratio, self.ms_groups)
                        break
                    ratio_before = ratio
                    st.run("field", 0.1, self._field, n, log_j)
                    st.run("ground_irradiance", 0.01, self._ground_irradiance)
                st.run("density", 0.01, self._upload_density, j_total)
            ms_tex, ms_range = st.run(
                "multiple_scattering", 0.5, self._multiple_scattering, j_total is not None
            )
            scat, mie, scale = st.run("single_scattering", 3.0, self._single_scattering)
            irr_s = st.run("irradiance", 0.5, self._irradiance, j_total is not None)
        finally:
            for obj in self._released:  # the last pass's framebuffer is still bound
                release_unbound(obj)
        timings = dict(st.times)
        timings["total"] = sum(st.times.values())
        if self.stages.progress is not None:
            self.stages.progress("done", 1.0)
        return PrecomputedAtmosphere(
            ctx, self.params, cfg, self.transmittance.texture, self.transmittance.size,
            scat, mie, ms_tex, irr_s, self.mu_s_min, scale, ms_range, orders, timings,
        )  # fmt: skip

    def _setup_ms(self) -> None:
        """Textures and uniforms of the grid of J (orders >= 2)."""
        cfg, ctx = self.cfg, self.ctx
        r, mu, mu_s, nu = cfg.ms_size
        self.j_shape = cfg.table_shape(cfg.ms_size)
        n_sky, n_ground, n_phi = cfg.directions
        self.n_dir = (n_sky + n_ground) * n_phi
        gm = self.ms_groups
        self.ms_defines = {
            **profile_defines(self.params),
            **mie_phase_defines(self.params),
            "NUM_GROUPS": gm,
            "RAY_SAMPLES": cfg.ms_samples,
            "N_MU_SKY": n_sky,
            "N_MU_GROUND": n_ground,
            "N_PHI": n_phi,
        }
        self.ms_inputs = self._inputs(
            self.ms_wl,
            quadrature_rules(cfg.ms_samples, cfg.directions),
            u_density_size=cfg.glsl_size(cfg.ms_size),
            u_ms_size=cfg.glsl_size(cfg.multiple_size),
        )
        # the density pass: a spectral phase function's lobes broadened and those then alike
        # merged, their g compile-time constants (Mars: -8 %)
        self.density_inputs, self.density_defines = self.ms_inputs, self.ms_defines
        if self.params.mie_phase is not None:
            lobes = broadened_lobe_uniforms(self.params, self.ms_wl, MS_MIE_LOBE_G_MAX)
            spectra = replace(self.ms_inputs.spectra, **lobes)
            self.density_inputs = replace(self.ms_inputs, spectra=spectra)
            self.density_defines = {
                **self.ms_defines,
                "MIE_LOBES": len(lobes["u_mie_lobe_g"]),
                "MIE_LOBE_G_VALUES": ", ".join(f"{g:.9e}" for g in lobes["u_mie_lobe_g"]),
            }
        self.mie_runs = mie_runs(self.params, self.ms_wl, cfg.ms_size[0])
        w, h, d = self.j_shape
        self.j3d = self._keep(linear_clamped(ctx.texture3d((w, h, d * gm), 4, dtype="f4"), ctx))
        if cfg.orders < 2:
            return
        self.field = self._keep(
            _nearest(ctx.texture((self.n_dir * gm, mu_s * r), 4, dtype="f4"), ctx)
        )
        self.ground = self._keep(linear_clamped(ctx.texture((mu_s, gm), 4, dtype="f4"), ctx))
        self.ground_fbo = self._keep(ctx.framebuffer(color_attachments=[self.ground]))
        # J is drawn nu_per views per fragment, one draw buffer per (group, view)
        self.nu_per = views_per_fragment(nu, gm)
        self.j_arrays = [
            self._keep(ctx.texture_array((w // self.nu_per, h, d), 4, dtype="f4"))
            for _ in range(gm * self.nu_per)
        ]
        self.j_fbo = self._keep(ctx.framebuffer(color_attachments=self.j_arrays))

    def _field(self, order: int, log_j: np.ndarray | None = None) -> None:
        """The radiance field of ``order`` (from ln J of that order): the azimuths of one side
        of the Sun's vertical plane drawn, the others their mirror images."""
        n_phi = self.cfg.directions[2]
        drawn = drawn_azimuths(n_phi)
        # orders >= 2: nv azimuths per fragment (one draw buffer each, reordered on read-back)
        nv = 1 if order == 1 else views_per_fragment(drawn, 1)
        defines = {
            **self.ms_defines,
            "FIELD_SINGLE": int(order == 1),
            "NU_PER_FRAGMENT": nv,
            "PHI_DRAWN": drawn,
        }
        prog = _program(self.ctx, "atmosphere/precompute_field.glsl", defines)
        if log_j is not None:
            self.j3d.write(np.ascontiguousarray(log_j, dtype="f4").tobytes())
        inputs = replace(self.ms_inputs, u_density=self.j3d, u_ground_irradiance=self.ground)
        w, h = self.field.size
        w = w // n_phi * drawn
        if nv not in self._field_targets:  # the orders >= 2 share theirs
            parts = [self._keep(self.ctx.texture((w // nv, h), 4, dtype="f4")) for _ in range(nv)]
            self._field_targets[nv] = (parts, self._keep(self.ctx.framebuffer(parts)))
        parts, fbo = self._field_targets[nv]
        fbo.viewport = (0, 0, w // nv, h)
        prog.draw(fbo, inputs)
        field = interleave_views([_read_2d(t)[None] for t in parts], 1)[0]
        field = mirror_azimuths(field, n_phi)
        self.field.write(np.ascontiguousarray(field).tobytes())

    def _ground_irradiance(self) -> None:
        prog = _program(self.ctx, "atmosphere/precompute_ground_irradiance.glsl", self.ms_defines)
        self.ground_fbo.viewport = (0, 0, *self.ground.size)
        prog.draw(self.ground_fbo, replace(self.ms_inputs, u_field=self.field))

    def _density(self) -> np.ndarray:
        """ln J_n from the field of order n-1, as (groups * r, mu, nu * mu_s, 4) float32."""
        nv = self.nu_per
        w, h, d = self.j_shape
        self.j_fbo.viewport = (0, 0, w // nv, h)
        inputs = replace(self.density_inputs, u_field=self.field)
        # the layers above the aerosols without J's Mie sum (NO_MIE), each run in one draw
        for first, count, negligible in self.mie_runs:
            defines = {**self.density_defines, "NU_PER_FRAGMENT": nv}
            if negligible:
                defines["NO_MIE"] = 1
            prog = _program(self.ctx, "atmosphere/precompute_density.glsl", defines, layered=True)
            prog.draw(self.j_fbo, inputs, layers=(first, count))
        reads = [_read_array(a) for a in self.j_arrays]  # draw buffer g * nv + t
        mu_s = self.cfg.ms_size[2]
        groups = [
            interleave_views(reads[g * nv : (g + 1) * nv], mu_s) for g in range(self.ms_groups)
        ]
        return np.concatenate(groups, axis=0)

    def _upload_density(self, j_total: np.ndarray) -> None:
        """Upload ln J summed over the orders (``j_total`` is overwritten: see run)."""
        log_j = np.log(np.maximum(j_total, 1e-37, out=j_total), out=j_total).astype("f4")
        self.j3d.write(log_j.tobytes())

    def _ms_interp(self) -> np.ndarray | None:
        """Log-space interpolation from the ms wavelengths to the render ones (or None)."""
        if self.ms_groups != 1 or np.array_equal(self.ms_wl, self.wl):
            return None
        return ms_log_interpolation(self.params, self.wl, self.ms_wl)

    def _multiple_scattering(self, has_ms: bool):
        """The table of orders >= 2: ln(table channels) (zero without them)."""
        cfg, ctx = self.cfg, self.ctx
        w, h, d = cfg.table_shape(cfg.multiple_size)
        if not has_ms:
            data, log_range = encode_log_table(
                np.full((d, h, w, 4), -87.0, dtype="f4"), cfg.ms_dtype
            )
            return linear_clamped(
                ctx.texture3d((w, h, d), 4, data.tobytes(), dtype=_GL_DTYPE[cfg.ms_dtype]), ctx
            ), log_range
        # nv views (nu) per fragment, one draw buffer each (see _density)
        nv = views_per_fragment(cfg.multiple_size[3], 1)
        arrays = [self._keep(ctx.texture_array((w // nv, h, d), 4, dtype="f4")) for _ in range(nv)]
        fbo = self._keep(ctx.framebuffer(color_attachments=arrays))
        fbo.viewport = (0, 0, w // nv, h)
        defines = {**self.ms_defines, "NU_PER_FRAGMENT": nv}
        inputs = replace(self.ms_inputs, u_density=self.j3d)
        interp = self._ms_interp()
        if interp is not None:
            defines.update(MS_LOG_INTERP=1, NUM_RENDER_GROUPS=self.groups)
            # one mat4 per render group: its 4 rows of ln L(render) = W ln L(samples)
            blocks = [mat4(interp[4 * k : 4 * k + 4]) for k in range(self.groups)]
            inputs = replace(
                inputs,
                u_ms_log_interp=[x for b in blocks for x in b],
                u_render_to_table=mat4_groups(table_matrix(self.wl, cfg.output)),
            )
        prog = _program(ctx, "atmosphere/precompute_ms_scattering.glsl", defines, layered=True)
        prog.draw(fbo, inputs, layers=(0, d))
        log_table = interleave_views([_read_array(a) for a in arrays], cfg.multiple_size[2])
        data, log_range = encode_log_table(log_table, cfg.ms_dtype)
        tex = ctx.texture3d((w, h, d), 4, data.tobytes(), dtype=_GL_DTYPE[cfg.ms_dtype])
        return linear_clamped(tex, ctx), log_range

    def _single_scattering(self):
        """The single-scattering tables at the render wavelengths (divided by F)."""
        cfg, ctx = self.cfg, self.ctx
        w, h, d = cfg.table_shape(cfg.scattering_size)
        defines = {
            **profile_defines(self.params),
            **mie_phase_defines(self.params),
            "NUM_GROUPS": self.groups,
            "RAY_SAMPLES": cfg.single_samples,
        }
        prog = _program(ctx, "atmosphere/precompute_scattering.glsl", defines, layered=True)
        arrays = [self._keep(ctx.texture_array((w, h, d), 4, dtype="f4")) for _ in range(2)]
        fbo = self._keep(ctx.framebuffer(color_attachments=arrays))
        fbo.viewport = (0, 0, w, h)
        inputs = self._inputs(
            self.wl,
            quadrature_rules(cfg.single_samples),
            # Linear tables: (R, G, B, scotopic) directly.
            to_table=conversion_matrix(self.wl, cfg.output),
            u_scattering_size=cfg.glsl_size(cfg.scattering_size),
            u_table_scale=1.0,
        )
        prog.draw(fbo, inputs, layers=(0, d))
        if cfg.dtype == "f4":
            return self._to_3d(arrays[0]), self._to_3d(arrays[1]), 1.0
        data = [_read_array(a) for a in arrays]
        peak = max(max(float(x.max()), -float(x.min())) for x in data)  # no |x| copy
        scale = F16_TABLE_MAX / peak if peak > 0 else 1.0
        out = []
        for x in data:
            half = convert_in_slices(
                x, np.float16, lambda part: to_float16(part * np.float32(scale))
            )
            out.append(linear_clamped(ctx.texture3d((w, h, d), 4, half, dtype="f2"), ctx))
        return out[0], out[1], scale

    def _irradiance(self, has_ms: bool):
        """Sky irradiance: single scattering at the render wavelengths + orders >= 2."""
        cfg, ctx = self.cfg, self.ctx
        ew, eh = cfg.irradiance_size
        n_mu, n_phi = cfg.irradiance_directions

        # the table drawn in IRRADIANCE_PARTS copies, each in tiles of its own (see the shader)
        stride = -(-ew // RASTER_TILE) * RASTER_TILE

        def run_pass(wl, single: bool) -> np.ndarray:
            groups = len(wl) // 4
            samples = cfg.single_samples if single else cfg.ms_samples
            defines = {
                **profile_defines(self.params),
                **mie_phase_defines(self.params),
                "NUM_GROUPS": groups,
                "RAY_SAMPLES": samples,
                "IRR_N_MU": n_mu,
                "IRR_N_PHI": n_phi,
                "IRRADIANCE_SINGLE": int(single),
                "IRR_PARTS": IRRADIANCE_PARTS,
            }
            prog = _program(ctx, "atmosphere/precompute_irradiance.glsl", defines)
            size = (stride * IRRADIANCE_PARTS, eh)
            texs = [self._keep(ctx.texture(size, 4, dtype="f4")) for _ in range(groups)]
            fbo = self._keep(ctx.framebuffer(color_attachments=texs))
            fbo.viewport = (0, 0, *size)
            inputs = self._inputs(
                wl,
                quadrature_rules(samples, irradiance_mu=n_mu),
                u_irradiance_size=(float(ew), float(eh)),
                u_part_stride=stride,
                u_density_size=cfg.glsl_size(cfg.ms_size),
                u_density=None if single else self.j3d,
            )
            prog.draw(fbo, inputs)
            # (groups, eh, parts x stride, 4) -> the parts summed -> (eh, ew, N) per wavelength
            e = np.stack([_read_2d(t) for t in texs], axis=0).astype(np.float64)
            e = e.reshape(groups, eh, IRRADIANCE_PARTS, stride, 4)[:, :, :, :ew].sum(axis=2)
            return np.moveaxis(e, 0, 2).reshape(eh, ew, 4 * groups)

        e = run_pass(self.wl, True)
        if has_ms:
            e_ms = run_pass(self.ms_wl, False)
            linear = e_ms @ interpolation_matrix(self.wl, self.ms_wl).T
            interp = self._ms_interp()
            if interp is not None:
                # ln-space interpolation where all 4 samples are well above 0 (as in the table)
                ok = e_ms.min(axis=-1, keepdims=True) > 1e-6 * e_ms.max(axis=-1, keepdims=True)
                logged = np.exp(np.log(np.maximum(e_ms, 1e-300)) @ interp.T)
                linear = np.where(ok, logged, linear)
            e = e + linear
        e = np.maximum(e, 0.0)
        spec = np.moveaxis(e.reshape(eh, ew, self.groups, 4), 2, 0)  # (groups, eh, ew, 4)

        def log_tex(a, size):
            la = np.log(np.maximum(a, 1e-37)).astype("f4")
            return linear_clamped(
                ctx.texture(size, 4, np.ascontiguousarray(la).tobytes(), dtype="f4"), ctx
            )

        return log_tex(spec.reshape(self.groups * eh, ew, 4), (ew, eh * self.groups))


#: The largest g of a spectral phase function's lobes in the scattering density of the orders
#: >= 2 (precompute_density.glsl: its directions are ~20 deg apart, and a narrower lobe made
#: the weighted mean jump from one direction to the next).
MS_MIE_LOBE_G_MAX = 0.8

#: Copies of the sky irradiance table drawn side by side, each summing a share of the
#: directions (precompute_irradiance.glsl): the table (64 x 16) is one of a CPU rasterizer's
#: 64-pixel tiles, which one thread draws (llvmpipe, 2 threads: 123 ms in one copy, 85 ms in
#: 2, 4 or 8; 8 for machines with more threads).
IRRADIANCE_PARTS = 8
#: The tile size of llvmpipe's rasterizer (texels).
RASTER_TILE = 64

#: J's Mie sum is left out of a layer of its grid where the aerosols scatter less than this
#: fraction of what the air scatters, at every wavelength (precompute_density.glsl's NO_MIE):
#: their share of J is the ratio times the Mie-weighted mean of the radiance over the
#: Rayleigh-weighted one (at most ~1e2, a lobe on the brightest part of the sky), so it stays
#: below float32's resolution of J (6e-8).
MIE_NEGLIGIBLE = 1e-10


def mie_runs(
    params: AtmosphereParams, wavelengths_nm, n_layers: int
) -> list[tuple[int, int, bool]]:
    """The layers of J's grid (``n_layers`` radii, spaced as ``scattering_texel_params``
    spaces them) as runs ``(first, count, negligible)``: whether the aerosols' scattering is
    below MIE_NEGLIGIBLE of the air's in each layer of the run at every wavelength."""
    rb, rt = params.bottom_radius_m, params.top_radius_m
    rho = math.sqrt(rt * rt - rb * rb) * np.arange(n_layers) / max(n_layers - 1, 1)
    altitude_m = np.sqrt(rho * rho + rb * rb) - rb
    rho_r = params.rayleigh_density.density(altitude_m)
    rho_m = params.mie_density.density(altitude_m)
    c = params.coefficients(wavelengths_nm)
    mie = rho_m * float(np.max(c["mie_scattering"]))
    negligible = mie <= MIE_NEGLIGIBLE * rho_r * float(np.min(c["rayleigh_scattering"]))
    runs, first = [], 0
    for flag, layers in itertools.groupby(negligible.tolist()):
        count = len(list(layers))
        runs.append((first, count, flag))
        first += count
    return runs


def drawn_azimuths(n_phi: int) -> int:
    """How many of the field's ``n_phi`` azimuths are drawn: those up to the Sun's
    antisolar half-plane, (j + 1/2) 2 pi / n_phi <= pi; the rest mirror them."""
    return (n_phi + 1) // 2


def mirror_azimuths(half: np.ndarray, n_phi: int) -> np.ndarray:
    """The field (rows, groups * cosines * n_phi, 4) from its drawn azimuths (rows, groups *
    cosines * drawn, 4): azimuth n_phi - 1 - j is the mirror image of azimuth j."""
    rows, width, c = half.shape
    drawn = drawn_azimuths(n_phi)
    blocks = half.reshape(rows, width // drawn, drawn, c)
    mirrored = blocks[:, :, n_phi - drawn - 1 :: -1] if n_phi > drawn else blocks[:, :, :0]
    return np.concatenate([blocks, mirrored], axis=2).reshape(rows, -1, c)


#: The most views one fragment computes. 8 (the draw buffers' limit) made the density pass and
#: the table of orders >= 2 slower than 4 on llvmpipe (0.64 / 0.52 s against 0.44 / 0.28 s,
#: 16 wavelengths, 4 orders; 2 views: 0.75 / 0.38 s): each view keeps its sums in registers,
#: and 8 views' spill, while 4 still share most of the work.
MAX_VIEWS = 4


def views_per_fragment(n_nu: int, groups: int) -> int:
    """How many of ``n_nu`` views (nu, or the field's azimuths) one fragment computes: the
    largest divisor of ``n_nu`` up to MAX_VIEWS with one draw buffer per (group, view) within
    MAX_GROUPS (8, the draw buffers OpenGL 3.3 guarantees). The views share the fragment's
    fetches of the field (density pass) or its ray's nodes and transmittances (the passes of
    the orders >= 2)."""
    most = max(min(MAX_VIEWS, MAX_GROUPS // max(groups, 1)), 1)
    return max(k for k in range(1, min(most, n_nu) + 1) if n_nu % k == 0)


def interleave_views(parts: list[np.ndarray], n_mu_s: int) -> np.ndarray:
    """A 4D table as (r, mu, nu * mu_s, 4) from the draw buffers of a pass that computed
    ``len(parts)`` nu per fragment: part t is (r, mu, blocks * mu_s, 4) and holds the nu
    indices block * len(parts) + t."""
    nv = len(parts)
    d, h, wb, c = parts[0].shape
    stacked = np.stack(parts).reshape(nv, d, h, wb // n_mu_s, n_mu_s, c)
    return stacked.transpose(1, 2, 3, 0, 4, 5).reshape(d, h, wb * nv, c)


#: Orders fall geometrically once two successive ratios of an order's scattering density to
#: the previous one's differ by less than this (relative), per wavelength.
RATIO_SETTLED = 0.005
#: The first order whose ratio may settle the series (orders 2-3 are still shaped by the
#: single scattering's angular structure).
FIRST_SETTLED_ORDER = 4


def order_ratio(j_n: np.ndarray, j_before: np.ndarray, groups: int) -> np.ndarray:
    """The ratio of order n's scattering density to order n-1's, summed over the grid, per
    wavelength group and channel: (groups, 4)."""
    a = j_n.reshape(groups, -1, 4).sum(axis=1)
    b = j_before.reshape(groups, -1, 4).sum(axis=1)
    return a / np.maximum(b, 1e-300)


def geometric(ratio: np.ndarray | None, before: np.ndarray | None) -> bool:
    """Whether the series has settled into a geometric fall (the successive ratios agree
    within RATIO_SETTLED and are below 1) from order FIRST_SETTLED_ORDER on."""
    if ratio is None or before is None:
        return False
    settled = np.abs(ratio - before) <= RATIO_SETTLED * np.abs(before)
    return bool(np.all(settled) and np.all((ratio > 0) & (ratio < 1)))


def tail(j_n: np.ndarray, ratio: np.ndarray, groups: int) -> np.ndarray:
    """The orders after n of a geometric series: J_n r / (1 - r), per group and channel
    (the eigenmode the higher orders converge to has the last order's shape)."""
    factor = ratio / (1.0 - ratio)
    shaped = j_n.reshape(groups, -1, *j_n.shape[1:])
    return (shaped * factor[:, None, None, None, :]).reshape(j_n.shape)
