"""Atmosphere parameters: an immutable, validated description of a planet's atmosphere.

The model is Bruneton's (2017 reference implementation, also seed 001 appendix B and seed
004 ch. 5): Rayleigh scattering, Mie (aerosol) scattering and absorption, and an
absorbing layer (ozone), each with a density profile made of up to two layers of the form
``clamp(exp_term·exp(exp_scale·h) + linear_term·h + constant_term, 0, 1)``.
Python uses metres; spectral coefficients are per metre.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from skydome.errors import ParameterError, check_range


@dataclass(frozen=True)
class Spectrum:
    """A spectral quantity sampled at increasing wavelengths (nm), interpolated linearly.

    Outside the sampled range the end values are held. A single sample is a constant.
    """

    wavelengths_nm: tuple[float, ...]
    values: tuple[float, ...]

    def __post_init__(self):
        wl = tuple(float(w) for w in self.wavelengths_nm)
        v = tuple(float(x) for x in self.values)
        if len(wl) != len(v) or not wl:
            raise ParameterError("a Spectrum needs as many values as wavelengths (at least one)")
        if any(b <= a for a, b in zip(wl, wl[1:], strict=False)):
            raise ParameterError(f"Spectrum wavelengths must increase, got {wl}")
        if not all(math.isfinite(x) for x in v):
            raise ParameterError(f"Spectrum values must be finite, got {v}")
        object.__setattr__(self, "wavelengths_nm", wl)
        object.__setattr__(self, "values", v)

    @classmethod
    def constant(cls, value: float) -> Spectrum:
        return cls((550.0,), (float(value),))

    @classmethod
    def sampled(cls, wavelengths_nm, values) -> Spectrum:
        return cls(tuple(np.asarray(wavelengths_nm, float)), tuple(np.asarray(values, float)))

    def at(self, wavelengths_nm) -> np.ndarray:
        """Values at the given wavelengths (nm)."""
        return np.interp(np.asarray(wavelengths_nm, float), self.wavelengths_nm, self.values)

    def scaled(self, factor: float) -> Spectrum:
        return Spectrum(self.wavelengths_nm, tuple(factor * v for v in self.values))


@dataclass(frozen=True)
class DensityLayer:
    """One layer: density(h) = exp_term·exp(exp_scale_per_m·h) + linear_per_m·h + constant.

    ``width_m`` is the layer's thickness from its base (the last layer extends to the top).
    """

    width_m: float = 0.0
    exp_term: float = 0.0
    exp_scale_per_m: float = 0.0
    linear_per_m: float = 0.0
    constant: float = 0.0

    def __post_init__(self):
        for name in ("width_m", "exp_term", "exp_scale_per_m", "linear_per_m", "constant"):
            v = getattr(self, name)
            if not math.isfinite(float(v)):
                raise ParameterError(f"DensityLayer.{name} must be finite, got {v}")
            object.__setattr__(self, name, float(v))
        if self.width_m < 0:
            raise ParameterError(f"DensityLayer.width_m = {self.width_m} must be >= 0")


@dataclass(frozen=True)
class DensityProfile:
    """Up to two layers; the first applies below ``layers[0].width_m``, the second above."""

    layers: tuple[DensityLayer, ...]

    def __post_init__(self):
        layers = tuple(self.layers)
        if not 1 <= len(layers) <= 2:
            raise ParameterError(f"a DensityProfile has 1 or 2 layers, got {len(layers)}")
        if len(layers) == 1:
            layers = (DensityLayer(), layers[0])
        object.__setattr__(self, "layers", layers)

    @classmethod
    def exponential(cls, scale_height_m: float) -> DensityProfile:
        h = check_range("scale height", scale_height_m, 1.0, 1e6, "m")
        return cls((DensityLayer(exp_term=1.0, exp_scale_per_m=-1.0 / h),))

    @classmethod
    def tent(cls, center_m: float, half_width_m: float) -> DensityProfile:
        """Triangular profile: 0 at center ± half_width, 1 at center (ozone layer)."""
        c, w = float(center_m), float(half_width_m)
        return cls(
            (
                DensityLayer(width_m=c, linear_per_m=1.0 / w, constant=1.0 - c / w),
                DensityLayer(linear_per_m=-1.0 / w, constant=1.0 + c / w),
            )
        )

    def density(self, altitude_m) -> np.ndarray:
        """Relative density (0..1) at altitude(s) above the ground, in metres."""
        h = np.asarray(altitude_m, dtype=np.float64)
        lo, hi = self.layers

        def eval_layer(layer: DensityLayer) -> np.ndarray:
            with np.errstate(over="ignore"):
                d = (
                    layer.exp_term * np.exp(layer.exp_scale_per_m * h)
                    + layer.linear_per_m * h
                    + layer.constant
                )
            return np.clip(d, 0.0, 1.0)

        return np.where(h < lo.width_m, eval_layer(lo), eval_layer(hi))


@dataclass(frozen=True)
class AtmosphereParams:
    """Everything that determines the appearance of a clear atmosphere.

    Lengths in metres, coefficients per metre, angles in radians, irradiance in
    W m^-2 nm^-1 at the top of the atmosphere.
    """

    name: str
    bottom_radius_m: float
    top_radius_m: float
    rayleigh_scattering: Spectrum
    rayleigh_density: DensityProfile
    mie_scattering: Spectrum
    mie_extinction: Spectrum
    mie_g: float
    mie_density: DensityProfile
    absorption_extinction: Spectrum
    absorption_density: DensityProfile
    ground_albedo: Spectrum
    sun_angular_radius_rad: float
    solar_irradiance: Spectrum
    #: Shortest Sun elevation cosine the precomputed tables must cover (Bruneton's mu_s_min).
    mu_s_min: float = -0.2
    description: str = field(default="", compare=False)

    def __post_init__(self):
        check_range("bottom_radius_m", self.bottom_radius_m, 1e3, 1e8, "m")
        check_range(
            "top_radius_m",
            self.top_radius_m,
            self.bottom_radius_m + 1e3,
            self.bottom_radius_m * 1.5,
            "m",
        )
        check_range("mie_g", self.mie_g, -0.999, 0.999)
        check_range("sun_angular_radius_rad", self.sun_angular_radius_rad, 1e-5, 0.2, "rad")
        check_range("mu_s_min", self.mu_s_min, -1.0, 0.0)
        for name in (
            "rayleigh_scattering",
            "mie_scattering",
            "absorption_extinction",
            "solar_irradiance",
        ):
            spec: Spectrum = getattr(self, name)
            if min(spec.values) < 0:
                raise ParameterError(f"{name} must be >= 0 everywhere, got {spec.values}")
        if any(
            e < s - 1e-15
            for e, s in zip(
                self.mie_extinction.at(_CHECK_NM), self.mie_scattering.at(_CHECK_NM), strict=True
            )
        ):
            raise ParameterError(
                "mie_extinction must be >= mie_scattering (absorption cannot be negative)"
            )
        if min(self.ground_albedo.values) < 0 or max(self.ground_albedo.values) > 1:
            raise ParameterError(
                f"ground_albedo must be within [0, 1], got {self.ground_albedo.values}"
            )

    @property
    def atmosphere_height_m(self) -> float:
        return self.top_radius_m - self.bottom_radius_m

    @property
    def solar_scale(self) -> float:
        """Illuminance of this atmosphere's Sun relative to the tabulated (ASTM G-173, 1 AU) one.

        The spectral conversions (``spectral_to_rgbs_matrix``) and the precomputed tables use the
        shape of the tabulated spectrum; renderers multiply by this factor (e.g. 1/1.524^2 for
        Mars), so that a scaled ``solar_irradiance`` gives the right absolute luminance.
        """
        from skydome.spectra import photopic_efficiency
        from skydome.spectra import solar_irradiance as tabulated

        wl = np.arange(360.0, 831.0, 1.0)
        v = photopic_efficiency(wl)
        return float(np.sum(self.solar_irradiance.at(wl) * v) / np.sum(tabulated(wl) * v))

    def with_(self, **changes) -> AtmosphereParams:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)

    def coefficients(self, wavelengths_nm) -> dict[str, np.ndarray]:
        """Per-wavelength coefficients (per metre), albedo and solar irradiance."""
        wl = np.asarray(wavelengths_nm, float)
        return {
            "rayleigh_scattering": self.rayleigh_scattering.at(wl),
            "mie_scattering": self.mie_scattering.at(wl),
            "mie_extinction": self.mie_extinction.at(wl),
            "absorption_extinction": self.absorption_extinction.at(wl),
            "ground_albedo": self.ground_albedo.at(wl),
            "solar_irradiance": self.solar_irradiance.at(wl),
        }

    def to_dict(self) -> dict:
        d = asdict(self)
        d.pop("description", None)
        return d

    def digest(self) -> str:
        """A stable hash of every field that changes the physics (for cache keys)."""
        blob = json.dumps(self.to_dict(), sort_keys=True, default=repr).encode()
        return hashlib.sha256(blob).hexdigest()


_CHECK_NM = np.linspace(360.0, 830.0, 48)
