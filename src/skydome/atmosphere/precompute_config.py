"""Configuration of the multiple-scattering precomputation (Bruneton 2017 on the GPU).

:class:`PrecomputeConfig` holds every knob that changes the precomputed tables: their sizes,
the wavelengths, the number of scattering orders and the quadratures. ``key()`` is a stable
hash of all of them, for the on-disk cache. The defaults are the "default quality" of the
library: 1.8 s of precomputation on a 2-core llvmpipe (16 wavelengths, 4 orders), 25 MB of
tables (``memory_bytes``), within 1-2% of a Monte Carlo reference (tests/test_precompute.py).

Table sizes follow Bruneton's order ``(r, mu, mu_s, nu)``; the 4D tables are stored as 3D
textures of ``(nu * mu_s) x mu x r`` texels.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import asdict, dataclass

import numpy as np

from skydome.errors import ParameterError
from skydome.physics.geometry import horizon_dip_rad
from skydome.spectra import wavelengths as resolve_wavelengths

#: The twilight the tables must cover: the Sun down to 18 degrees below the horizon (the end of
#: astronomical twilight), with 2 degrees to spare.
MIN_SUN_ELEVATION_DEG = -20.0
#: Default wavelengths of the orders >= 2 (one group), from which the render wavelengths are
#: interpolated in a physical basis (precompute.ms_log_interpolation; 0.03-0.4% RMS in
#: luminance against computing them at all 16).
MS_WAVELENGTHS_NM = (430.0, 505.0, 580.0, 655.0)
#: Most wavelength groups per pass: fragment shaders write one group per draw buffer, and
#: OpenGL 3.3 guarantees 8 of them.
MAX_GROUPS = 8
#: Texture sizes accepted along any table dimension.
MAX_SIDE = 2048

Sizes4 = tuple[int, int, int, int]


def _check_int(name: str, value, lo: int, hi: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not lo <= value <= hi:
        raise ParameterError(f"{name} = {value!r} must be an integer in [{lo}, {hi}]")
    return int(value)


def _check_sizes(name: str, sizes, lows, his=None) -> tuple[int, ...]:
    sizes = tuple(sizes)
    if len(sizes) != len(lows):
        raise ParameterError(f"{name} = {sizes!r} must have {len(lows)} entries")
    his = his or [MAX_SIDE] * len(lows)
    return tuple(
        _check_int(f"{name}[{i}]", s, lo, hi)
        for i, (s, lo, hi) in enumerate(zip(sizes, lows, his, strict=True))
    )


@dataclass(frozen=True)
class PrecomputeConfig:
    """What the precomputed tables are made of. All sizes in texels or quadrature nodes.

    Attributes:
        wavelengths: the render wavelengths (nm): ``"accurate"`` (16, 380-755 nm), ``"fast"``
            (4) or a sorted list of 4, 8, ... values. Single scattering and the sky irradiance
            are computed at all of them, 4 per RGBA pass (the issue asks for "at least 15
            between 360 and 830 nm, in groups of 3 per pass"; 16 in groups of 4 use every
            channel of a float texture: 4 passes where 3-per-pass needs 5).
        ms_wavelengths: wavelengths of the orders >= 2, which are smooth in wavelength:
            ``None`` (automatic: the render wavelengths when they are one group of 4 or with
            ``output="spectral"``, else MS_WAVELENGTHS_NM), ``"same"`` (the render
            wavelengths), a mode name or a sorted list. Four of them are interpolated to the render
            wavelengths in ln L over the basis {1, ln λ, λ^-4, absorber spectrum}
            (``ms_log_interpolation``), other counts linearly in λ; the error this costs is
            measured in ``benchmarks/bench_precompute.py``.
        output: ``"rgbs"``: tables hold (R, G, B, scotopic) luminance in cd/m^2 for the
            params' solar spectrum (linear sRGB, Y = luminance); ``"spectral"``: tables hold
            the raw transfer values (sr^-1 per unit solar irradiance) of the 4 wavelengths
            (one group only: a debugging and testing mode).
        orders: scattering orders (1 = single scattering only). The tables hold orders
            1..orders, like Bruneton's ``num_scattering_orders``.
        tolerance: with > 0, orders are added until they converge (up to ``orders``): until
            an order adds less than this fraction of the sum so far, or, from order 4 on,
            until the orders fall geometrically (two successive ratios of an order's
            scattering density to the previous one's agree within 0.5 % at every wavelength),
            when the rest of the series is added at once (the last order times r / (1 - r)).
            0 = always compute ``orders``.
        scattering_size: (r, mu, mu_s, nu) of the single-scattering tables (mu even).
        multiple_size: (r, mu, mu_s, nu) of the table of orders >= 2 (smooth: coarser).
        ms_size: (r, mu, mu_s, nu) of the grid of the scattering density J, on which the
            orders >= 2 are computed (internal; not kept): smooth in direction, so coarse
            there, but J falls with the air density, and 16 altitudes left the orders >= 2
            about 1.5% low (the sky 0.8% low at 440 nm against the Monte Carlo; 32: 0.3%).
        irradiance_size: (mu_s, r) of the sky irradiance table.
        transmittance_size: (mu, r) of the column-density table; transmittance_steps its
            Simpson intervals per texel.
        single_samples: Gauss-Legendre nodes along each ray of the final table (even).
        ms_samples: nodes along the rays of the orders >= 2 (even).
        directions: (cosines above the horizon, cosines below it, azimuths) of the product
            quadrature over the sphere used for J (Bruneton: 16 x 32 midpoint directions).
        irradiance_directions: (cosines, azimuths over half a turn) of the hemisphere
            quadrature for the irradiance.
        mu_s_min: cut-off of the Sun zenith cosine (None: the lower of the params' mu_s_min
            and the cosine for the Sun at MIN_SUN_ELEVATION_DEG or twice the horizon dip
            from the top of the atmosphere, whichever is lower; see ``resolved_mu_s_min``).
        mu_s_knee_deg: e0 of the Sun-elevation mapping of the orders >= 2 (J and their
            table; atmosphere/precomputed_params.glsl): texels spaced as (1 + |e| / e0).
        dtype: ``"f2"`` (float16, scaled: 0.05% steps) or ``"f4"`` storage of the
            single-scattering tables.
        ms_dtype: storage of the table of orders >= 2, which holds logarithms: ``"u2"`` (16-bit
            normalized integers over 48 e-folds below its maximum: 0.073% steps) or ``"f4"``.
    """

    wavelengths: str | tuple[float, ...] = "accurate"
    ms_wavelengths: str | tuple[float, ...] | None = None
    output: str = "rgbs"
    orders: int = 4
    tolerance: float = 0.0
    scattering_size: Sizes4 = (32, 128, 32, 8)
    multiple_size: Sizes4 = (32, 64, 64, 8)
    ms_size: Sizes4 = (32, 64, 64, 8)
    irradiance_size: tuple[int, int] = (64, 16)
    transmittance_size: tuple[int, int] = (512, 128)
    transmittance_steps: int = 200
    single_samples: int = 16
    ms_samples: int = 16
    directions: tuple[int, int, int] = (12, 6, 16)
    irradiance_directions: tuple[int, int] = (8, 8)
    mu_s_min: float | None = None
    mu_s_knee_deg: float = 5.0
    dtype: str = "f2"
    ms_dtype: str = "u2"

    def __post_init__(self):
        wl = resolve_wavelengths(self.wavelengths)
        if len(wl) // 4 > MAX_GROUPS:
            raise ParameterError(f"at most {4 * MAX_GROUPS} wavelengths, got {len(wl)}")
        if len(self.multiple_wavelengths) // 4 > MAX_GROUPS:
            raise ParameterError(f"at most {4 * MAX_GROUPS} ms wavelengths")
        if self.output not in ("rgbs", "spectral"):
            raise ParameterError(f"output = {self.output!r} must be 'rgbs' or 'spectral'")
        if self.output == "spectral":
            if len(wl) != 4:
                raise ParameterError("output='spectral' needs exactly 4 wavelengths (one group)")
            if self.ms_wavelengths not in (None, "same") and not np.array_equal(
                resolve_wavelengths(self.ms_wavelengths), wl
            ):
                raise ParameterError(
                    "output='spectral' needs ms_wavelengths None, 'same' or equal to wavelengths"
                )
        _check_int("orders", self.orders, 1, 50)
        if not (0.0 <= float(self.tolerance) < 1.0):
            raise ParameterError(f"tolerance = {self.tolerance} must be in [0, 1)")
        r, mu, mu_s, nu = _check_sizes("scattering_size", self.scattering_size, (2, 4, 2, 2))
        if mu % 2:
            raise ParameterError(f"scattering_size mu = {mu} must be even (split at the horizon)")
        if nu * mu_s > MAX_SIDE:
            raise ParameterError(f"nu * mu_s must be at most {MAX_SIDE} texels")
        for name in ("multiple_size", "ms_size"):
            _, muc, musc, nuc = _check_sizes(name, getattr(self, name), (2, 4, 2, 2))
            if muc % 2:
                raise ParameterError(f"{name} mu = {muc} must be even (split at the horizon)")
            if nuc * musc > MAX_SIDE:
                raise ParameterError(f"{name}: nu * mu_s must be at most {MAX_SIDE} texels")
        _check_sizes("irradiance_size", self.irradiance_size, (2, 2))
        _check_sizes("transmittance_size", self.transmittance_size, (2, 2))
        steps = _check_int("transmittance_steps", self.transmittance_steps, 2, 10000)
        if steps % 2:
            raise ParameterError(f"transmittance_steps = {steps} must be even (Simpson's rule)")
        for name in ("single_samples", "ms_samples"):
            n = _check_int(name, getattr(self, name), 2, 512)
            if n % 2:
                raise ParameterError(f"{name} = {n} must be even")
        _check_sizes("directions", self.directions, (1, 1, 2), (64, 64, 256))
        _check_sizes("irradiance_directions", self.irradiance_directions, (1, 1), (64, 256))
        if self.mu_s_min is not None and not -1.0 <= float(self.mu_s_min) < 0.0:
            raise ParameterError(f"mu_s_min = {self.mu_s_min} must be in [-1, 0)")
        if not 0.1 <= float(self.mu_s_knee_deg) <= 1000.0:
            raise ParameterError(f"mu_s_knee_deg = {self.mu_s_knee_deg} must be in [0.1, 1000]")
        if self.dtype not in ("f2", "f4"):
            raise ParameterError(f"dtype = {self.dtype!r} must be 'f2' or 'f4'")
        if self.ms_dtype not in ("u2", "f4"):
            raise ParameterError(f"ms_dtype = {self.ms_dtype!r} must be 'u2' or 'f4'")

    # ------------------------------------------------------------------ derived values
    @property
    def render_wavelengths(self) -> np.ndarray:
        return resolve_wavelengths(self.wavelengths)

    @property
    def multiple_wavelengths(self) -> np.ndarray:
        wl = self.render_wavelengths
        if self.ms_wavelengths == "same" or (
            self.ms_wavelengths is None and (len(wl) == 4 or self.output == "spectral")
        ):
            return wl
        if self.ms_wavelengths is None:
            return np.array(MS_WAVELENGTHS_NM)
        return resolve_wavelengths(self.ms_wavelengths)

    def resolved_mu_s_min(
        self, bottom_radius_m: float, top_radius_m: float, params_mu_s_min: float
    ) -> float:
        """The Sun zenith cosine below which the tables hold their cut-off row.

        Twilight must work down to a Sun 18 degrees below the horizon (the issue). Seen from the
        ground, sunlit air is visible until the Sun is ``2 acos(Rb/Rt)`` below the horizon (the
        top of the atmosphere on the horizon, itself lit at grazing incidence: 20.2 degrees
        for Earth's 100 km atmosphere); below that only light scattered more than once
        remains, which is tiny. Bruneton's -0.2 (11.5 degrees) stops too early. The default
        cut-off is the lower of the params' value, MIN_SUN_ELEVATION_DEG and that angle.
        """
        if self.mu_s_min is not None:
            return float(self.mu_s_min)
        dip = 2.0 * math.degrees(horizon_dip_rad(top_radius_m, bottom_radius_m))
        elevation = -max(-MIN_SUN_ELEVATION_DEG, dip)
        return float(min(params_mu_s_min, math.sin(math.radians(elevation))))

    def glsl_size(self, sizes: Sizes4) -> tuple[float, float, float, float]:
        """(NU, MU_S, MU, R) as the shaders take it, from (r, mu, mu_s, nu)."""
        r, mu, mu_s, nu = sizes
        return (float(nu), float(mu_s), float(mu), float(r))

    def table_shape(self, sizes: Sizes4) -> tuple[int, int, int]:
        """(width, height, depth) of the 3D texture holding a 4D table."""
        r, mu, mu_s, nu = sizes
        return (nu * mu_s, mu, r)

    def to_dict(self) -> dict:
        d = asdict(self)
        d["wavelengths"] = [float(w) for w in self.render_wavelengths]
        d["ms_wavelengths"] = [float(w) for w in self.multiple_wavelengths]
        return d

    def key(self) -> str:
        """Stable hash of everything that changes the tables (wavelength modes resolved)."""
        blob = json.dumps({"version": 1, **self.to_dict()}, sort_keys=True, default=repr).encode()
        return hashlib.sha256(blob).hexdigest()

    def memory_bytes(self) -> dict[str, int]:
        """GPU memory of the tables kept after precomputation, by table (bytes)."""
        b4 = 2 if self.dtype == "f2" else 4
        bm = 2 if self.ms_dtype == "u2" else 4
        w, h, d = self.table_shape(self.scattering_size)
        wm, hm, dm = self.table_shape(self.multiple_size)
        tw, th = self.transmittance_size
        ew, eh = self.irradiance_size
        groups = len(self.render_wavelengths) // 4
        return {
            "transmittance": tw * th * 4 * 4,
            "scattering": w * h * d * 4 * b4,
            "single_mie": w * h * d * 4 * b4,
            "multiple_scattering": wm * hm * dm * 4 * bm,
            "irradiance_spectral": ew * eh * groups * 4 * 4,
        }


#: Settings of the reference run of ``benchmarks/bench_precompute.py --accuracy`` (minutes):
#: every shortcut of the defaults undone (2-4x the resolution, nodes and directions, orders >= 2
#: at every wavelength, float32 storage).
REFERENCE = dict(
    scattering_size=(48, 256, 48, 16),
    multiple_size=(48, 128, 128, 16),
    ms_size=(32, 128, 128, 16),
    single_samples=48,
    ms_samples=32,
    directions=(24, 12, 32),
    irradiance_directions=(16, 16),
    transmittance_size=(1024, 256),
    transmittance_steps=300,
    ms_wavelengths="same",
    dtype="f4",
    ms_dtype="f4",
)
