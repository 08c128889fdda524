"""Published aerosol types: OPAC's clean continental, average continental, urban, clean
maritime and desert aerosol (Hess, Koepke & Schult 1998, "Optical Properties of Aerosols and
Clouds: The Software Package OPAC", Bull. Amer. Meteor. Soc. 79, 831-844; "OPAC" below).

Each :class:`AerosolType` carries what the renderer's one Mie species can hold: the optical
depth at 550 nm of the type's standard column, the spectral shape of the extinction, the
spectral single-scattering albedo, the asymmetry parameter at 550 nm and a vertical profile.
:func:`with_aerosol_type` puts a type into an :class:`AtmosphereParams`, scaled to any optical
depth (the ``aod_550`` knob scales a type).

Where the numbers come from:

- **Composition** (number densities of OPAC's components in the mixing layer, particles per
  cm^3, OPAC Table 4): clean continental: insoluble 0.15, water-soluble 2600; average
  continental: insoluble 0.4, water-soluble 7000, soot 8300; urban: insoluble 1.5,
  water-soluble 28 000, soot 130 000; clean maritime: water-soluble 1500, sea salt
  (accumulation) 20, sea salt (coarse) 3.2e-3; desert: water-soluble 2000, mineral (nucleation)
  269.5, mineral (accumulation) 30.5, mineral (coarse) 0.142. As reproduced in AeroMix
  (Raj & Sinha 2023, github.com/sampr7/AeroMix, ``getAerosolType.py``).
- **Spectra** (``extinction_ratio``, ``ssa``) and the asymmetry parameter: the mixing rule of
  OPAC (extinction and scattering add by number density; g is the scattering-weighted mean)
  applied to OPAC's component files at 80 % relative humidity (1 particle cm^-3 each: inso00,
  waso80, soot00, ssam80, sscm80, minm00, miam00, micm00, as shipped with AeroMix), at OPAC's
  wavelengths 350-800 nm every 50 nm, 900 and 1000 nm. The same rule on the same files gives
  OPAC's own program output for continental polluted at 550 nm (opac_calc/copo of the GEISA
  OPAC distribution: extinction 0.1746 km^-1, albedo 0.8925, g 0.6977) to all four digits,
  and, for the types here, the OPAC Table 4 values quoted in the tests. The desert's mineral
  files in AeroMix are OPAC 4.0's non-spherical (spheroid) minerals (Koepke, Gasteiger & Hess
  2015, Atmos. Chem. Phys. 15, 5947), so its albedo and g differ slightly from OPAC 1998's
  spheres.
- **Optical depth of the standard column** at 550 nm (OPAC Table 4, which integrates the
  mixing layer, OPAC's free-tropospheric aerosol up to 12 km and its stratospheric sulfate
  layer): clean continental 0.064, average continental 0.151, urban 0.643, clean maritime 0.096
  (as quoted from OPAC in the published Swift file ``NishitaAerosol`` of the Daydream Home
  engine, which cites Hess et al. 1998). The desert's 0.286 and its scale height of 2 km were
  NOT found in the stored sources: they are the values of OPAC Table 4 as recalled, and OPAC's
  profile model (its mixing layer, free troposphere 6-12 km and stratosphere, computed from
  the component files) gives 0.2865 with them; AeroMix lists 8 km for the desert, which would
  give 0.62. Treat the desert's column as unconfirmed.
- **Profile** (OPAC Table 4, via AeroMix): exponential with scale height Z within the mixing
  layer, 0-2 km (Z = 8 km continental and urban, 1 km maritime) or 0-6 km for the desert.

The renderer's Mie density is one profile of two layers (:class:`DensityLayer`), normalised
to 1 at the ground: exp(-h/Z) below the mixing-layer top H, and above it an exponential that
continues from exp(-H/Z) with the scale height that leaves the rest of the standard column
(free troposphere and stratosphere, τ_550 minus the mixing layer's) above H. The optical depth
and its spectrum are the source's; OPAC's free-tropospheric aerosol, spread to 12 km and of a
different composition, is here the mixing layer's aerosol within a few hundred metres to
1.5 km above H.

The renderer's phase function is Cornette-Shanks with one parameter: its parameter is chosen
so that the phase function's mean cosine equals the type's asymmetry parameter at 550 nm
(``cornette_shanks_g``); the mean cosine of Cornette-Shanks is 3g(4+g²) / (5(2+g²)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skydome.atmosphere.params import (
    AOD_550_RANGE,
    AtmosphereParams,
    DensityLayer,
    DensityProfile,
    Spectrum,
)
from skydome.errors import ParameterError, check_range
from skydome.physics.phase import cornette_shanks_mean_cosine

#: OPAC's wavelengths (nm) at which the types' spectra are tabulated.
OPAC_WAVELENGTHS_NM = (350.0, 400.0, 450.0, 500.0, 550.0, 600.0, 650.0, 700.0, 750.0, 800.0,
                       900.0, 1000.0)  # fmt: skip
#: Wavelengths (nm) at which :func:`with_aerosol_type` samples the spectra (5 nm steps, so that
#: the linear interpolation of :class:`Spectrum` follows the log-log one within 1e-4).
TYPE_GRID_NM = np.arange(350.0, 1001.0, 5.0)


def cornette_shanks_g_for(asymmetry: float) -> float:
    """The Cornette-Shanks parameter whose mean cosine is ``asymmetry`` (in (-0.9, 0.9)).

    The mean cosine increases monotonically with g on (-1, 1), so bisection converges; 60
    halvings reach 1e-15.
    """
    a = check_range("asymmetry", asymmetry, -0.9, 0.9)
    lo, hi = -0.999, 0.999
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if cornette_shanks_mean_cosine(mid) < a:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@dataclass(frozen=True)
class AerosolType:
    """A published aerosol type: optical properties, standard column and vertical profile.

    - ``aod_550``: vertical optical depth at 550 nm of the type's standard column.
    - ``wavelengths_nm``, ``extinction_ratio``: τ(λ)/τ(550 nm) at the source's wavelengths
      (interpolated log-log in between, end values held outside).
    - ``ssa``: single-scattering albedo at the same wavelengths (interpolated linearly).
    - ``asymmetry_550``: asymmetry parameter (mean scattering cosine) at 550 nm.
    - ``surface_extinction_550_per_m``: extinction coefficient of the mixing layer's aerosol at
      the ground, 550 nm, per metre (sets how much of ``aod_550`` is in the mixing layer).
    - ``mixing_layer_height_m``, ``scale_height_m``: the mixing layer's top and the scale
      height of its exponential profile, metres.
    """

    name: str
    description: str
    source: str
    aod_550: float
    wavelengths_nm: tuple[float, ...]
    extinction_ratio: tuple[float, ...]
    ssa: tuple[float, ...]
    asymmetry_550: float
    surface_extinction_550_per_m: float
    mixing_layer_height_m: float
    scale_height_m: float

    def __post_init__(self):
        n = len(self.wavelengths_nm)
        if not (len(self.extinction_ratio) == len(self.ssa) == n >= 2):
            raise ParameterError(f"{self.name}: spectra need one value per wavelength")
        if any(b <= a for a, b in zip(self.wavelengths_nm, self.wavelengths_nm[1:], strict=False)):
            raise ParameterError(f"{self.name}: wavelengths must increase")
        if min(self.extinction_ratio) <= 0.0:
            raise ParameterError(f"{self.name}: the extinction ratio must be > 0")
        if not all(0.0 < w <= 1.0 for w in self.ssa):
            raise ParameterError(f"{self.name}: the single-scattering albedo must be in (0, 1]")
        if not math.isclose(float(self.extinction_ratio_at(550.0)), 1.0, rel_tol=1e-3):
            raise ParameterError(f"{self.name}: the extinction ratio must be 1 at 550 nm")
        if self.mixing_layer_aod_550 >= self.aod_550:
            raise ParameterError(
                f"{self.name}: the mixing layer alone ({self.mixing_layer_aod_550:.4f}) exceeds "
                f"the standard column's optical depth {self.aod_550}"
            )

    def extinction_ratio_at(self, wavelengths_nm) -> np.ndarray:
        """τ(λ)/τ(550 nm) at the given wavelengths (nm), log-log interpolation."""
        log_wl = np.log(np.asarray(wavelengths_nm, dtype=np.float64))
        return np.exp(np.interp(log_wl, np.log(self.wavelengths_nm), np.log(self.extinction_ratio)))

    def ssa_at(self, wavelengths_nm) -> np.ndarray:
        """Single-scattering albedo at the given wavelengths (nm), linear interpolation."""
        return np.interp(np.asarray(wavelengths_nm, dtype=np.float64), self.wavelengths_nm,
                         self.ssa)  # fmt: skip

    def angstrom_exponent(self, wavelength_a_nm: float, wavelength_b_nm: float) -> float:
        """Ångström exponent α = -ln(τ(a)/τ(b)) / ln(a/b) of the type's spectrum."""
        ta, tb = self.extinction_ratio_at([wavelength_a_nm, wavelength_b_nm])
        return float(-math.log(ta / tb) / math.log(wavelength_a_nm / wavelength_b_nm))

    @property
    def cornette_shanks_g(self) -> float:
        """The renderer's phase-function parameter: Cornette-Shanks with this type's mean
        cosine at 550 nm."""
        return cornette_shanks_g_for(self.asymmetry_550)

    @property
    def mixing_layer_aod_550(self) -> float:
        """Optical depth at 550 nm of the mixing layer: β0 · Z · (1 - exp(-H/Z))."""
        z, h = self.scale_height_m, self.mixing_layer_height_m
        return self.surface_extinction_550_per_m * z * -math.expm1(-h / z)

    @property
    def free_troposphere_scale_height_m(self) -> float:
        """Scale height (m) above the mixing layer, continuing from its top, that holds the
        rest of the standard column: (τ_550 - τ_mixing layer) / (β0 · exp(-H/Z))."""
        top_density = math.exp(-self.mixing_layer_height_m / self.scale_height_m)
        above = self.aod_550 - self.mixing_layer_aod_550
        return above / (self.surface_extinction_550_per_m * top_density)

    @property
    def transition_scale_height_m(self) -> float:
        """The decay above the mixing layer that the profile uses: the free-troposphere scale
        height, but at least MIN_TRANSITION_SCALE_HEIGHT_M. Urban's 66 m would put a near-step
        in ln density at the layer top, which the tables' interpolation turns into bands along
        the horizon; 300 m (average continental has 310 m) shows none. Where the floor applies
        the column above the layer grows (urban: from 2.8 % to 12 % of the optical depth), and
        with_aerosol_type still scales the whole column to the type's optical depth."""
        return max(self.free_troposphere_scale_height_m, MIN_TRANSITION_SCALE_HEIGHT_M)

    @property
    def density_profile(self) -> DensityProfile:
        """Relative density: 1 at the ground, exp(-h/Z) to the mixing-layer top H, then
        exp(-H/Z) · exp(-(h - H)/H_t) (continuous at H) with H_t the
        transition_scale_height_m."""
        z, h = self.scale_height_m, self.mixing_layer_height_m
        h_ft = self.transition_scale_height_m
        return DensityProfile(
            (
                DensityLayer(width_m=h, exp_term=1.0, exp_scale_per_m=-1.0 / z),
                DensityLayer(exp_term=math.exp(h / h_ft - h / z), exp_scale_per_m=-1.0 / h_ft),
            )
        )


#: The sharpest decay above a mixing layer that the profiles use (m); see
#: AerosolType.transition_scale_height_m.
MIN_TRANSITION_SCALE_HEIGHT_M = 300.0

_OPAC = "Hess, Koepke & Schult 1998 (OPAC), BAMS 79, 831, Table 4; spectra from OPAC's "
_OPAC += "component files at 80 % relative humidity"

#: The five types, by name. Spectra at OPAC_WAVELENGTHS_NM; see the module docstring.
AEROSOL_TYPES: dict[str, AerosolType] = {
    t.name: t
    for t in (
        AerosolType(
            name="continental_clean",
            description="clean continental (remote land, no anthropogenic influence)",
            source=_OPAC,
            aod_550=0.064,
            wavelengths_nm=OPAC_WAVELENGTHS_NM,
            extinction_ratio=(
                1.672,
                1.460,
                1.283,
                1.130,
                1.0,
                0.8900,
                0.7960,
                0.7160,
                0.6461,
                0.5792,
                0.4827,
                0.4083,
            ),  # fmt: skip
            ssa=(
                0.9778,
                0.9777,
                0.9766,
                0.9757,
                0.9720,
                0.9707,
                0.9667,
                0.9653,
                0.9599,
                0.9538,
                0.9423,
                0.9311,
            ),  # fmt: skip
            asymmetry_550=0.7086,
            surface_extinction_550_per_m=2.6193e-5,
            mixing_layer_height_m=2000.0,
            scale_height_m=8000.0,
        ),
        AerosolType(
            name="continental_average",
            description="average continental (rural land with some anthropogenic aerosol)",
            source=_OPAC,
            aod_550=0.151,
            wavelengths_nm=OPAC_WAVELENGTHS_NM,
            extinction_ratio=(
                1.682,
                1.466,
                1.286,
                1.132,
                1.0,
                0.8894,
                0.7956,
                0.7154,
                0.6458,
                0.5797,
                0.4840,
                0.4103,
            ),  # fmt: skip
            ssa=(
                0.9320,
                0.9317,
                0.9304,
                0.9290,
                0.9253,
                0.9235,
                0.9186,
                0.9167,
                0.9104,
                0.9029,
                0.8891,
                0.8758,
            ),  # fmt: skip
            asymmetry_550=0.7034,
            surface_extinction_550_per_m=7.5085e-5,
            mixing_layer_height_m=2000.0,
            scale_height_m=8000.0,
        ),
        AerosolType(
            name="urban",
            description="urban (strong pollution: soot and water-soluble particles)",
            source=_OPAC,
            aod_550=0.643,
            wavelengths_nm=OPAC_WAVELENGTHS_NM,
            extinction_ratio=(
                1.707,
                1.481,
                1.293,
                1.135,
                1.0,
                0.8880,
                0.7943,
                0.7135,
                0.6447,
                0.5802,
                0.4864,
                0.4140,
            ),  # fmt: skip
            ssa=(
                0.8276,
                0.8261,
                0.8237,
                0.8210,
                0.8170,
                0.8137,
                0.8069,
                0.8034,
                0.7952,
                0.7849,
                0.7663,
                0.7490,
            ),  # fmt: skip
            asymmetry_550=0.6889,
            surface_extinction_550_per_m=3.5312e-4,
            mixing_layer_height_m=2000.0,
            scale_height_m=8000.0,
        ),
        AerosolType(
            name="maritime_clean",
            description="clean maritime (sea salt and sulfate over the open ocean)",
            source=_OPAC,
            aod_550=0.096,
            wavelengths_nm=OPAC_WAVELENGTHS_NM,
            extinction_ratio=(
                1.055,
                1.037,
                1.020,
                1.009,
                1.0,
                0.9946,
                0.9865,
                0.9811,
                0.9771,
                0.9705,
                0.9580,
                0.9434,
            ),  # fmt: skip
            ssa=(
                0.9965,
                0.9971,
                0.9974,
                0.9977,
                0.9975,
                0.9977,
                0.9976,
                0.9978,
                0.9975,
                0.9973,
                0.9967,
                0.9963,
            ),  # fmt: skip
            asymmetry_550=0.7720,
            surface_extinction_550_per_m=8.9935e-5,
            mixing_layer_height_m=2000.0,
            scale_height_m=1000.0,
        ),
        AerosolType(
            name="desert",
            description="desert (mineral dust, non-spherical minerals of OPAC 4.0); its "
            "standard column (0.286, scale height 2 km) is unconfirmed, see the module docstring",
            source=_OPAC + "; minerals: Koepke, Gasteiger & Hess 2015, ACP 15, 5947",
            aod_550=0.286,
            wavelengths_nm=OPAC_WAVELENGTHS_NM,
            extinction_ratio=(
                1.094,
                1.065,
                1.040,
                1.019,
                1.0,
                0.9844,
                0.9707,
                0.9594,
                0.9491,
                0.9392,
                0.9234,
                0.9096,
            ),  # fmt: skip
            ssa=(
                0.7725,
                0.8029,
                0.8464,
                0.8591,
                0.8908,
                0.9081,
                0.9114,
                0.9217,
                0.9244,
                0.9264,
                0.9311,
                0.9348,
            ),  # fmt: skip
            asymmetry_550=0.7305,
            surface_extinction_550_per_m=1.4494e-4,
            mixing_layer_height_m=6000.0,
            scale_height_m=2000.0,
        ),
    )
}


def aerosol_type(type_or_name: AerosolType | str) -> AerosolType:
    """The :class:`AerosolType` itself, or the one of that name (ParameterError listing the
    names otherwise)."""
    if isinstance(type_or_name, AerosolType):
        return type_or_name
    try:
        return AEROSOL_TYPES[type_or_name]
    except KeyError:
        raise ParameterError(
            f"unknown aerosol type {type_or_name!r}; choose one of {', '.join(AEROSOL_TYPES)}"
        ) from None


def with_aerosol_type(
    params: AtmosphereParams, type_or_name: AerosolType | str, aod_550: float | None = None
) -> AtmosphereParams:
    """A copy of ``params`` whose aerosol (Mie) is the type's, with optical depth ``aod_550``.

    The type's profile becomes ``mie_density``; ``mie_extinction`` is τ_550 ·
    τ(λ)/τ(550) / ∫ mie_density dh (ground to the top of ``params``), sampled every 5 nm over
    350-1000 nm, so the vertical optical depth at 550 nm is ``aod_550`` (default: the type's
    standard column) and the spectral shape is the type's at any ``aod_550``;
    ``mie_scattering`` is the type's single-scattering albedo times the extinction;
    ``mie_g`` the Cornette-Shanks parameter of the type's asymmetry at 550 nm. Afterwards
    ``with_aerosol(aod_550=...)`` or ``with_knobs(aod_550=...)`` scales it, keeping all else.
    """
    kind = aerosol_type(type_or_name)
    tau = kind.aod_550 if aod_550 is None else check_range("aod_550", aod_550, *AOD_550_RANGE)
    density = kind.density_profile
    column_m = density.column_m(params.atmosphere_height_m)
    extinction = tau * kind.extinction_ratio_at(TYPE_GRID_NM) / column_m
    return params.with_(
        mie_extinction=Spectrum.sampled(TYPE_GRID_NM, extinction),
        mie_scattering=Spectrum.sampled(TYPE_GRID_NM, extinction * kind.ssa_at(TYPE_GRID_NM)),
        mie_density=density,
        mie_g=kind.cornette_shanks_g,
    )
