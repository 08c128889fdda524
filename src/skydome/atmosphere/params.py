"""Atmosphere parameters: an immutable, validated description of a planet's atmosphere.

The model is Bruneton's (2017 reference implementation, also seed 001 appendix B and seed
004 ch. 5): Rayleigh scattering, Mie (aerosol) scattering and absorption, and an
absorbing layer (ozone), each with a density profile made of up to two layers of the form
``clamp(exp_term·exp(exp_scale·h) + linear_term·h + constant_term, 0, 1)``, or tabulated:
relative densities at altitudes, log-linear between them (``DensityProfile.tabulated``; the
U.S. Standard Atmosphere 1976 air is ``standard_atmosphere.air_density_profile()``).
Python uses metres; spectral coefficients are per metre.

The atmosphere knobs of pvlib or Blender users (ground albedo, aerosol optical depth at
550 nm with an Ångström exponent, total ozone in Dobson units) are methods of
:class:`AtmosphereParams`: ``with_albedo``, ``with_aerosol``, ``with_ozone`` and
``with_knobs`` (all at once), and read back as ``aod_550``, ``angstrom_exponent`` and
``ozone_du``. They set the spectra and leave the density profiles' shapes alone, so a later
physical model (standard-atmosphere air, aerosol types) can keep the same interface.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from skydome.atmosphere.phase import MiePhaseLobes
from skydome.errors import ParameterError, check_range
from skydome.physics.droplets import KOSCHMIEDER
from skydome.physics.phase import cornette_shanks
from skydome.spectra import photopic_efficiency
from skydome.spectra import solar_irradiance as tabulated
from skydome.spectra.tables import ozone_cross_section, surface_albedo

#: One Dobson unit: 2.687e20 molecules per m^2 of column (0.01 mm of pure ozone at 0 °C and
#: 1013.25 hPa; WMO definition).
DOBSON_UNIT_PER_M2 = 2.687e20

#: Valid ranges of the knobs (closed intervals, except the single-scattering albedo's (0, 1]).
#: Ground albedo: a reflectance. Aerosol optical depth at 550 nm: 0 (none) to 5, past the
#: heaviest smoke and dust events AERONET records (~4 at 500 nm). Ångström exponent: about 0
#: (or slightly negative) for coarse dust and sea salt to 2-2.5 for fine smoke (Eck et al.
#: 1999, J. Geophys. Res. 104, 31333), kept within [-0.5, 3]. Total ozone: record lows near
#: 90 DU (Antarctic ozone hole) and highs near 650 DU, kept within [0, 700] DU.
ALBEDO_RANGE = (0.0, 1.0)
AOD_550_RANGE = (0.0, 5.0)
ANGSTROM_RANGE = (-0.5, 3.0)
OZONE_DU_RANGE = (0.0, 700.0)
SSA_RANGE = (0.0, 1.0)

#: Wavelengths (nm) at which aerosol spectra set from the knobs are sampled: the visible range
#: of the renderers and the 870 nm band of sun photometers (AERONET's 440/870 nm pair).
AEROSOL_GRID_NM = np.arange(360.0, 1001.0, 5.0)
#: The two wavelengths (nm) of the Ångström exponent read back by ``angstrom_exponent``.
ANGSTROM_PAIR_NM = (440.0, 870.0)
#: Wavelengths (nm) at which ozone spectra are sampled (where the cross-sections are tabulated).
OZONE_GRID_NM = np.arange(360.0, 831.0, 5.0)

_GL_NODES, _GL_WEIGHTS = np.polynomial.legendre.leggauss(8)


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


def surface_spectrum(surface: str) -> Spectrum:
    """The spectral albedo of a named surface (``skydome.spectra.SURFACES``: grassland,
    cropland, forest, desert, snow, ocean, urban) as a Spectrum (CMAQ's IGBP table)."""
    return Spectrum.sampled(*surface_albedo(surface))


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


#: Most samples a tabulated density profile may hold.
MAX_TABLE_SAMPLES = 1024


@dataclass(frozen=True)
class DensityProfile:
    """The relative density of one constituent versus altitude, in one of two forms.

    - **Layered** (Bruneton 2017): up to two :class:`DensityLayer`; the first applies below
      ``layers[0].width_m``, the second above. Built by :meth:`exponential`, :meth:`tent` or
      ``DensityProfile((layer, ...))``.
    - **Tabulated**: relative densities ``values`` (>= 0) at increasing ``altitudes_m``,
      built by :meth:`tabulated`; ``layers`` is then empty. See :meth:`tabulated` for the
      interpolation.
    """

    layers: tuple[DensityLayer, ...] = ()
    altitudes_m: tuple[float, ...] = ()
    values: tuple[float, ...] = ()

    def __post_init__(self):
        layers = tuple(self.layers)
        if self.altitudes_m or self.values:
            if layers:
                raise ParameterError("a DensityProfile is either layered or tabulated, not both")
            alt, val = _check_table(self.altitudes_m, self.values)
            object.__setattr__(self, "altitudes_m", alt)
            object.__setattr__(self, "values", val)
        else:
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

    @classmethod
    def tabulated(cls, altitudes_m, values) -> DensityProfile:
        """A profile through relative densities ``values`` (>= 0) at ``altitudes_m`` (m).

        The altitudes increase strictly and the first is at or below the ground (0 m); 2 to
        ``MAX_TABLE_SAMPLES`` (1024) finite samples. Between two samples the density is
        log-linear (an exponential through both), or linear where one of them is 0 (the top
        of an ozone layer). Below the first sample it is the first value; above the last it
        continues as the last segment's exponential when that decreases, else it holds the
        last value (so 0 after a 0). Values are not clamped to 1.
        """
        alt, val = _check_table(altitudes_m, values)
        return cls(altitudes_m=alt, values=val)

    @property
    def is_tabulated(self) -> bool:
        """True for a tabulated profile, False for a layered one."""
        return not self.layers

    def density(self, altitude_m) -> np.ndarray:
        """Relative density at altitude(s) above the ground, in metres (0..1 when layered)."""
        h = np.asarray(altitude_m, dtype=np.float64)
        if self.is_tabulated:
            return self._table_density(h)
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

    def _segments(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Per segment of the table: (base altitude m, base value, ln slope per m, linear?).

        One more segment than gaps: the last one, from the last sample up, continues the last
        gap's exponential if it decreases, else it is constant (linear with slope 0).
        """
        alt = np.asarray(self.altitudes_m)
        val = np.asarray(self.values)
        v0, v1 = val[:-1], val[1:]
        linear = (v0 == 0.0) | (v1 == 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            slope = np.where(linear, (v1 - v0) / np.diff(alt), np.log(v1 / v0) / np.diff(alt))
        tail_linear = bool(linear[-1]) or slope[-1] >= 0.0
        tail_slope = 0.0 if tail_linear else float(slope[-1])
        return (
            alt,
            val,
            np.append(slope, tail_slope),
            np.append(linear, tail_linear),
        )

    def _table_density(self, h: np.ndarray) -> np.ndarray:
        alt, val, slope, linear = self._segments()
        hc = np.maximum(h, alt[0])  # constant below the first sample
        i = np.clip(np.searchsorted(alt, hc, side="right") - 1, 0, len(alt) - 1)
        dh = hc - alt[i]
        with np.errstate(over="ignore"):
            d = np.where(linear[i], val[i] + slope[i] * dh, val[i] * np.exp(slope[i] * dh))
        return np.maximum(d, 0.0)  # rounding of a linear piece that ends at 0

    def column_m(self, top_m: float, subintervals: int = 1024) -> float:
        """Column of the relative density from the ground to ``top_m``: ∫ density dh, metres.

        Tabulated: exact, piece by piece (log-linear pieces ∫ = Δh (v1 - v0) / ln(v1/v0)).
        Layered: the integral is split at the layer boundary and where a purely linear layer
        is clamped (at 0 or 1), then each piece is integrated by 8-point Gauss-Legendre
        quadrature on ``subintervals`` equal parts: exact for linear pieces, ~1e-12 relative
        for exponentials (an exp + linear layer's clamp points fall inside a part: ~1e-6).
        """
        top = check_range("top_m", top_m, 0.0, 1e8, "m")
        if self.is_tabulated:
            return self._table_column(top)
        lo, hi = self.layers
        cuts = {0.0, top, min(max(lo.width_m, 0.0), top)}
        for layer, start, end in ((lo, 0.0, lo.width_m), (hi, lo.width_m, top)):
            if layer.exp_term == 0.0 and layer.linear_per_m != 0.0:
                for level in (0.0, 1.0):
                    h = (level - layer.constant) / layer.linear_per_m
                    if start < h < min(end, top):
                        cuts.add(h)
        edges = np.array(sorted(cuts))
        total = 0.0
        for a, b in zip(edges[:-1], edges[1:], strict=True):
            parts = np.linspace(a, b, subintervals + 1)
            half = 0.5 * np.diff(parts)[:, None]
            h = half * _GL_NODES[None, :] + 0.5 * (parts[:-1] + parts[1:])[:, None]
            total += float(np.sum(self.density(h) * _GL_WEIGHTS[None, :] * half))
        return total

    def _table_column(self, top_m: float) -> float:
        alt, _, slope, linear = self._segments()
        edges = np.unique(np.concatenate([[0.0, top_m], alt[(alt > 0.0) & (alt < top_m)]]))
        a, b = edges[:-1], edges[1:]
        if a.size == 0:
            return 0.0
        # Each piece [a, b] lies within one segment (a >= 0 >= the first sample).
        seg = np.clip(np.searchsorted(alt, a, side="right") - 1, 0, len(alt) - 1)
        da, db = self.density(a), self.density(b)
        width = b - a
        k = slope[seg] * width  # ln(db / da) of a log-linear piece
        lin = linear[seg]
        with np.errstate(divide="ignore", invalid="ignore"):
            log_piece = np.where(np.abs(k) < 1e-9, da * width * (1.0 + 0.5 * k),
                                 width * (db - da) / k)  # fmt: skip
        piece = np.where(lin, 0.5 * width * (da + db), log_piece)
        return float(np.sum(piece))

    def to_dict(self) -> dict:
        """The fields that define the profile (only those of its form), JSON-ready."""
        if self.is_tabulated:
            return {"altitudes_m": self.altitudes_m, "values": self.values}
        return {"layers": tuple(asdict(layer) for layer in self.layers)}


def _check_table(altitudes_m, values) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Validated (altitudes, values) of a tabulated profile, as tuples of floats."""
    try:
        alt = np.asarray(altitudes_m, dtype=np.float64).ravel()
        val = np.asarray(values, dtype=np.float64).ravel()
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(
            "a tabulated DensityProfile needs numeric altitudes and values"
        ) from None
    if alt.size != val.size:
        raise ParameterError(
            f"a tabulated DensityProfile needs as many values ({val.size}) as altitudes "
            f"({alt.size})"
        )
    if not 2 <= alt.size <= MAX_TABLE_SAMPLES:
        raise ParameterError(
            f"a tabulated DensityProfile has 2 to {MAX_TABLE_SAMPLES} samples, got {alt.size}"
        )
    if not (np.all(np.isfinite(alt)) and np.all(np.isfinite(val))):
        raise ParameterError("a tabulated DensityProfile's altitudes and values must be finite")
    if np.any(np.diff(alt) <= 0.0):
        raise ParameterError("a tabulated DensityProfile's altitudes must increase strictly")
    if alt[0] > 0.0:
        raise ParameterError(
            f"a tabulated DensityProfile must start at or below the ground (0 m), got {alt[0]} m"
        )
    if np.any(val < 0.0):
        raise ParameterError("a tabulated DensityProfile's values must be >= 0")
    return tuple(float(x) for x in alt), tuple(float(x) for x in val)


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
    #: The aerosol's phase function per wavelength (Henyey-Greenstein lobes), or None for the
    #: Cornette-Shanks function of ``mie_g`` at every wavelength.
    mie_phase: MiePhaseLobes | None = None
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

        wl = np.arange(360.0, 831.0, 1.0)
        v = photopic_efficiency(wl)
        return float(np.sum(self.solar_irradiance.at(wl) * v) / np.sum(tabulated(wl) * v))

    def with_(self, **changes) -> AtmosphereParams:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)

    # --- Atmosphere knobs: column-integrated quantities a pvlib or Blender user sets. ---

    @property
    def mie_column_m(self) -> float:
        """∫ mie_density dh from the ground to the top, metres (the aerosol's equivalent
        thickness: its scale height for an exponential profile)."""
        return self.mie_density.column_m(self.atmosphere_height_m)

    @property
    def absorption_column_m(self) -> float:
        """∫ absorption_density dh from the ground to the top, metres (15 km for the ozone
        tent of the ``earth`` preset)."""
        return self.absorption_density.column_m(self.atmosphere_height_m)

    def aerosol_optical_depth(self, wavelengths_nm) -> np.ndarray:
        """Vertical aerosol (Mie extinction) optical depth, ground to top, per wavelength (nm)."""
        return self.mie_extinction.at(wavelengths_nm) * self.mie_column_m

    @property
    def aod_550(self) -> float:
        """Vertical aerosol optical depth at 550 nm."""
        return float(self.aerosol_optical_depth(550.0))

    @property
    def angstrom_exponent(self) -> float:
        """Ångström exponent between 440 and 870 nm, α = -ln(τ(440)/τ(870)) / ln(440/870).

        0 for a wavelength-independent aerosol; NaN when the atmosphere has no aerosol.
        """
        a, b = ANGSTROM_PAIR_NM
        tau_a, tau_b = self.aerosol_optical_depth([a, b])
        if tau_a <= 0.0 or tau_b <= 0.0:
            return math.nan
        return float(-math.log(tau_a / tau_b) / math.log(a / b))

    @property
    def ozone_du(self) -> float:
        """Total column of the absorber, in Dobson units, taken as ozone.

        The least-squares fit of ``absorption_extinction`` to peak number density × the ozone
        cross-section (Serdyuchenko et al. 2014, 360-830 nm), times the absorber column, over
        2.687e20 m^-2: exact for spectra set by ``with_ozone``, 0 for no absorber.
        """

        sigma = ozone_cross_section(OZONE_GRID_NM)
        k = self.absorption_extinction.at(OZONE_GRID_NM)
        peak_per_m3 = float(np.dot(k, sigma) / np.dot(sigma, sigma))
        return peak_per_m3 * self.absorption_column_m / DOBSON_UNIT_PER_M2

    def with_albedo(self, albedo: float | Spectrum) -> AtmosphereParams:
        """A copy with a Lambertian ground albedo: a constant in [0, 1] or a Spectrum."""
        if isinstance(albedo, Spectrum):
            return self.with_(ground_albedo=albedo)
        value = check_range("albedo", albedo, *ALBEDO_RANGE)
        return self.with_(ground_albedo=Spectrum.constant(value))

    def with_ozone(self, dobson: float) -> AtmosphereParams:
        """A copy whose absorber is ``dobson`` Dobson units of ozone over its own profile.

        Peak number density n = dobson · 2.687e20 m^-2 / ∫ absorption_density dh, and
        absorption_extinction(λ) = n · σ_O3(λ) with the ozone cross-section of
        ``skydome.spectra`` (Serdyuchenko et al. 2014, 233 K), sampled every 5 nm over
        360-830 nm. The profile's shape is kept (``earth``: the AFGL 1986 profile, whose
        column is 18.9 km at peak density; ``earth_bruneton``: the seeds' tent, 15 km).
        """

        du = check_range("ozone_du", dobson, *OZONE_DU_RANGE, "DU")
        column = self.absorption_column_m
        if column <= 0.0:
            raise ParameterError(f"{self.name}: the absorber's density profile is zero everywhere")
        peak = du * DOBSON_UNIT_PER_M2 / column
        return self.with_(
            absorption_extinction=Spectrum.sampled(
                OZONE_GRID_NM, peak * ozone_cross_section(OZONE_GRID_NM)
            )
        )

    @property
    def ground_extinction_550_per_m(self) -> float:
        """The extinction coefficient (1/m) at 550 nm at the ground: Rayleigh scattering,
        aerosol extinction and the absorber's, each its coefficient times its density there."""
        h = 0.0
        return float(
            self.rayleigh_scattering.at(550.0) * self.rayleigh_density.density(h)
            + self.mie_extinction.at(550.0) * self.mie_density.density(h)
            + self.absorption_extinction.at(550.0) * self.absorption_density.density(h)
        )

    @property
    def visibility_km(self) -> float:
        """The meteorological visibility at the ground (km): Koschmieder's 3.912 / beta_ext at
        550 nm, the distance at which a black object's contrast against the horizon sky falls
        to 2 % (WMO-No. 8). About 340 km in air without aerosol."""
        return KOSCHMIEDER / self.ground_extinction_550_per_m / 1e3

    def with_visibility(self, km: float) -> AtmosphereParams:
        """A copy whose visibility at the ground is ``km`` (Koschmieder): the aerosol column
        scaled, its profile and spectrum kept, so that the extinction at 550 nm at the ground
        is 3.912 / V. Refused where that needs no aerosol at all (beyond the aerosol-free air's
        visibility) or an optical depth beyond the knob's range (a visibility of a few km in
        a deep aerosol profile: mist and fog are not layers of this kind)."""
        v = check_range("visibility", km, 1e-3, 1e4, "km")
        target = KOSCHMIEDER / (v * 1e3)
        mie_ground = float(self.mie_extinction.at(550.0) * self.mie_density.density(0.0))
        clear = self.ground_extinction_550_per_m - mie_ground
        if target <= clear:
            raise ParameterError(
                f"visibility {v:g} km needs less than no aerosol: this air without aerosol "
                f"sees {KOSCHMIEDER / clear / 1e3:.0f} km"
            )
        density0 = float(self.mie_density.density(0.0))
        if density0 <= 0.0:
            raise ParameterError("visibility needs an aerosol at the ground: this one has none")
        aod = (target - clear) / density0 * self.mie_column_m
        if aod > AOD_550_RANGE[1]:
            least = KOSCHMIEDER / (clear + AOD_550_RANGE[1] * density0 / self.mie_column_m)
            raise ParameterError(
                f"visibility {v:g} km needs an aerosol optical depth of {aod:.1f} in this "
                f"profile (at most {AOD_550_RANGE[1]:g}): {least / 1e3:.1f} km is the least; "
                "mist and fog are not modelled yet"
            )
        return self.with_aerosol(aod_550=aod)

    def with_aerosol(
        self,
        aod_550: float | None = None,
        angstrom: float | None = None,
        *,
        ssa: float | None = None,
        scale_height_m: float | None = None,
        mie_g: float | None = None,
    ) -> AtmosphereParams:
        """A copy with its aerosol (Mie) set by column-integrated knobs; None keeps the current.

        - ``aod_550``: vertical aerosol optical depth at 550 nm, in [0, 5].
        - ``angstrom``: Ångström exponent α in [-0.5, 3]: τ_a(λ) = τ_550 (λ/550 nm)^(-α)
          (Ångström 1929, Geogr. Ann. 11, 156), sampled every 5 nm over 360-1000 nm. None
          keeps the current spectral shape (scaled to ``aod_550``).
        - ``ssa``: single-scattering albedo (scattering / extinction) in (0, 1], e.g. ~0.9 for
          continental aerosol; None keeps the current ratio at each wavelength.
        - ``scale_height_m``: makes the Mie density profile exponential with this scale height
          (keeping the optical depth unless ``aod_550`` is given); ``mie_g``: the
          Cornette-Shanks asymmetry parameter (it replaces a ``mie_phase``).

        The sea-level extinction follows from the profile's column: β_ext(λ) = τ_a(λ) /
        ∫ mie_density dh (for an exponential profile, τ / H).
        """
        if aod_550 is not None:
            aod_550 = check_range("aod_550", aod_550, *AOD_550_RANGE)
        if angstrom is not None:
            angstrom = check_range("angstrom", angstrom, *ANGSTROM_RANGE)
        if ssa is not None:
            ssa = _check_ssa(ssa)
        density = (
            self.mie_density
            if scale_height_m is None
            else DensityProfile.exponential(scale_height_m)
        )
        column = density.column_m(self.atmosphere_height_m)
        if column <= 0.0:
            raise ParameterError(f"{self.name}: the aerosol's density profile is zero everywhere")
        old_ext_550 = float(self.mie_extinction.at(550.0))
        tau_550 = self.aod_550 if aod_550 is None else aod_550

        if angstrom is not None:
            grid = AEROSOL_GRID_NM
            tau = tau_550 * (grid / 550.0) ** (-angstrom)
            extinction = Spectrum.sampled(grid, tau / column)
        elif old_ext_550 > 0.0:
            extinction = self.mie_extinction.scaled(tau_550 / (old_ext_550 * column))
        elif tau_550 == 0.0:
            extinction = Spectrum.constant(0.0)
        else:
            raise ParameterError(
                f"{self.name} has no aerosol to take a spectral shape from: give angstrom too"
            )

        # Scattering = extinction × albedo, sampled wherever either spectrum has a sample.
        grid = np.asarray(extinction.wavelengths_nm)
        if ssa is None:
            grid = np.union1d(grid, self.mie_scattering.wavelengths_nm)
            grid = np.union1d(grid, self.mie_extinction.wavelengths_nm)
        ext = extinction.at(grid)
        if ssa is None:
            old_ext = self.mie_extinction.at(grid)
            old_sca = self.mie_scattering.at(grid)
            if np.any((old_ext <= 0.0) & (ext > 0.0)):
                raise ParameterError(
                    f"{self.name} has no aerosol to take a single-scattering albedo from: "
                    "give ssa too"
                )
            ratio = np.divide(old_sca, old_ext, out=np.zeros_like(ext), where=old_ext > 0.0)
        else:
            ratio = np.full_like(ext, ssa)
        changes: dict[str, object] = {
            "mie_extinction": extinction,
            "mie_scattering": Spectrum.sampled(grid, ext * ratio),
            "mie_density": density,
        }
        if mie_g is not None:  # one Cornette-Shanks asymmetry replaces a spectral phase
            changes["mie_g"] = mie_g
            changes["mie_phase"] = None
        return self.with_(**changes)

    def with_aerosol_tilt(self, delta_angstrom: float) -> AtmosphereParams:
        """A copy whose aerosol extinction and scattering spectra are multiplied by
        (lambda / 550 nm)^-delta_angstrom: the Angstrom exponent of any pair of wavelengths
        moves by ``delta_angstrom``, the optical depth at 550 nm and the albedo stay, and the
        spectrum keeps its own shape otherwise (a humidity's growth, skydome.weather.humidity).
        Sampled every 5 nm over 360-1000 nm where a spectrum is coarser."""
        delta = check_range("Angstrom exponent change", delta_angstrom, -3.0, 3.0)
        if delta == 0.0:
            return self
        changes = {}
        for name in ("mie_extinction", "mie_scattering"):
            spectrum = getattr(self, name)
            grid = np.union1d(AEROSOL_GRID_NM, spectrum.wavelengths_nm)
            tilt = (grid / 550.0) ** (-delta)
            changes[name] = Spectrum.sampled(grid, spectrum.at(grid) * tilt)
        return self.with_(**changes)

    def with_knobs(
        self,
        *,
        albedo: float | Spectrum | None = None,
        aod_550: float | None = None,
        angstrom: float | None = None,
        ozone_du: float | None = None,
        ssa: float | None = None,
    ) -> AtmosphereParams:
        """A copy with any of the knobs set (None keeps this atmosphere's own value).

        ``albedo`` as in :meth:`with_albedo`, ``aod_550``, ``angstrom`` and ``ssa`` as in
        :meth:`with_aerosol`, ``ozone_du`` (total ozone, DU, in [0, 700]) as in
        :meth:`with_ozone`. Linke turbidity is not offered: converting it to an aerosol optical
        depth (Ineichen & Perez 2002) needs the water-vapour column, which this model lacks.
        """
        params = self
        if albedo is not None:
            params = params.with_albedo(albedo)
        if aod_550 is not None or angstrom is not None or ssa is not None:
            params = params.with_aerosol(aod_550, angstrom, ssa=ssa)
        if ozone_du is not None:
            params = params.with_ozone(ozone_du)
        return params

    def mie_phase_function(self, cos_theta, wavelengths_nm) -> np.ndarray:
        """The aerosol's phase function (sr^-1), shape (cosines..., wavelengths): ``mie_phase``
        where set, else Cornette-Shanks of ``mie_g`` (the same at every wavelength)."""
        if self.mie_phase is not None:
            return self.mie_phase.phase(cos_theta, wavelengths_nm)
        p = cornette_shanks(np.asarray(cos_theta, float)[..., None], self.mie_g)
        return np.broadcast_to(p, (*np.shape(cos_theta), np.size(wavelengths_nm))).copy()

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
        """Every field that changes the physics; a density profile gives only the fields of
        its form (a layered one exactly as before tabulated profiles existed)."""
        d = asdict(self)
        d.pop("description", None)
        if self.mie_phase is None:  # as before spectral phase functions existed
            d.pop("mie_phase")
        for name in ("rayleigh_density", "mie_density", "absorption_density"):
            d[name] = getattr(self, name).to_dict()
        return d

    def digest(self) -> str:
        """A stable hash of every field that changes the physics (for cache keys)."""
        blob = json.dumps(self.to_dict(), sort_keys=True, default=repr).encode()
        return hashlib.sha256(blob).hexdigest()


_CHECK_NM = np.linspace(360.0, 830.0, 48)


def _check_ssa(ssa: float) -> float:
    """The single-scattering albedo as a float, or ParameterError naming (0, 1]."""
    lo, hi = SSA_RANGE
    try:
        value = float(ssa)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(f"ssa must be a number, got {ssa!r}") from None
    if not (lo < value <= hi):  # also rejects NaN
        raise ParameterError(f"ssa = {ssa} is outside the valid range ({lo}, {hi}]")
    return value
