"""Artificial sky glow (light pollution): its zenith brightness, its rise towards the horizon,
the glow domes of cities (Walker's law) and the lamps' spectra.

Float64 twins of ``shaders/night/light_pollution.glsl``. Every brightness here is the one an
observer on the ground sees (the glow is made in the air around the observer, so the
atmosphere's extinction is part of the model, not applied again by the scene).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skydome.astro.photometry import mag_to_optical_depth
from skydome.astro.places import Place
from skydome.errors import ParameterError, check_choice, check_range
from skydome.night.airglow import bin_relative_to_sun, luminance_to_mag, mag_to_luminance
from skydome.physics.airmass import kasten_young_airmass
from skydome.physics.refraction import horizon_dip_sin
from skydome.spectra.tables import cmf_xyz, photopic_efficiency, scotopic_efficiency

#: Natural zenith sky at a dark site at sunspot minimum, V mag/arcsec^2 (Benn & Ellison 1998,
#: La Palma Technical Note 115: V = 21.9); a Bortle class's total less this is artificial.
NATURAL_ZENITH_MAG = 21.9

#: Bortle class -> zenith total sky brightness (SQM, ~V mag/arcsec^2), the centre of each
#: class's range in the SQM-per-class table widely used with sky quality meters (class 1
#: 21.99-22.00, 2 21.89-21.99, 3 21.69-21.89, 4 20.49-21.69, 5 19.50-20.49, 6 18.94-19.50,
#: 7 18.38-18.94, 8 18.00-18.38, 9 brighter than 18.00: taken as 17.60-18.00). Class 8's
#: 18.0-18.4 agrees with the brief's measured city skies.
BORTLE_SQM_RANGES = {
    1: (21.99, 22.00),
    2: (21.89, 21.99),
    3: (21.69, 21.89),
    4: (20.49, 21.69),
    5: (19.50, 20.49),
    6: (18.94, 19.50),
    7: (18.38, 18.94),
    8: (18.00, 18.38),
    9: (17.60, 18.00),
}

#: A city's artificial zenith brightness at its centre grows as the square root of its
#: population: b ~ P^0.5, Berry's (1976, JRASC 70, 97) fit to his measured city centres
#: (Cinzano 1997's review, eq. 87; Garstang 1986, PASP 98, 364, models the same centres).
CITY_POPULATION_EXPONENT = 0.5
#: The calibration of that law today (lighting has grown since 1976): central Berlin, urban
#: area 3.6 million people, where clear nights measure a total zenith of about 18.0
#: mag_SQM/arcsec^2 (Kyba et al. 2011, PLoS ONE 6, e17307: SQM in the city centre, clear
#: and moonless). The tests compare the law with other cities' measurements.
CITY_CALIBRATION = (3.6e6, 18.0)

#: Default V extinction (mag per airmass) of a lowland site's air, for the glow's profile
#: (typical sea-level clear-sky values are 0.2-0.3; Krisciunas & Schaefer 1991, PASP 103,
#: 1033, use 0.172 for Mauna Kea at 4.2 km).
DEFAULT_EXTINCTION_MAG = 0.25

#: Azimuthal concentration of a city's dome and its fall-off with elevation (see city_profile).
CITY_AZIMUTH_KAPPA = 2.0
CITY_ELEVATION_ETA = 1.5
#: Largest number of cities the shader takes.
MAX_CITIES = 8


def bortle_zenith_mag(bortle_class: int) -> float:
    """Total zenith sky brightness (V mag/arcsec^2) of a Bortle class 1-9: its range's centre
    (class 8: 18.19)."""
    try:
        known = bortle_class in BORTLE_SQM_RANGES and not isinstance(bortle_class, bool)
    except TypeError:  # unhashable: a list, an array...
        known = False
    if not known:
        raise ParameterError(f"bortle class = {bortle_class!r} is outside the valid range 1 to 9")
    lo, hi = BORTLE_SQM_RANGES[bortle_class]
    return 0.5 * (lo + hi)


def artificial_zenith_luminance(total_mag: float, natural_mag: float = NATURAL_ZENITH_MAG):
    """The artificial part (cd/m^2) of a total zenith brightness: total less natural, never
    below 0 (a Bortle 1 sky is as dark as the natural one)."""
    return max(float(mag_to_luminance(total_mag) - mag_to_luminance(natural_mag)), 0.0)


def slab_profile(zenith_rad, extinction_mag: float = DEFAULT_EXTINCTION_MAG) -> np.ndarray:
    """Zenith-angle profile of a glow that fills the air around the observer, relative to the
    zenith: the radiance of a plane-parallel layer with a uniform source function and zenith
    optical depth tau, (1 - exp(-tau X(z))) / (1 - exp(-tau X(0))) (the formal solution of the
    transfer equation for a homogeneous slab: Chandrasekhar 1960, Radiative Transfer, ch. I;
    with X the Kasten-Young air mass for the curved air). tau = extinction_mag / (2.5 log10 e).
    At 0.25 mag/airmass the horizon is 4.86 times the zenith.
    GLSL twin: ``slab``."""
    tau = float(mag_to_optical_depth(extinction_mag))
    x = kasten_young_airmass(zenith_rad)
    x0 = float(kasten_young_airmass(0.0))
    return np.expm1(-tau * x) / math.expm1(-tau * x0)


def bortle_class_of(total_mag: float) -> int:
    """The Bortle class (1-9) whose zenith range (BORTLE_SQM_RANGES) holds a total zenith
    brightness, V mag/arcsec^2 (brighter than 18.0: 9; darker than 21.99: 1)."""
    for cls in range(9, 0, -1):
        if total_mag < BORTLE_SQM_RANGES[cls][1]:
            return cls
    return 1


def city_zenith_mag(population: float, natural_mag: float = NATURAL_ZENITH_MAG) -> float:
    """Estimated total zenith sky brightness (V mag/arcsec^2) at the centre of a city of
    ``population`` people on a clear, moonless night: the natural sky plus an artificial part
    k P^0.5 (CITY_POPULATION_EXPONENT), k set by CITY_CALIBRATION. 11 million (Paris): 17.4;
    1 million: 18.7; 100,000: 19.8; 10,000: 20.8."""
    pop = check_range("population", population, 1.0, 1e9)
    ref_pop, ref_mag = CITY_CALIBRATION
    k = artificial_zenith_luminance(ref_mag, NATURAL_ZENITH_MAG)
    art = k * (pop / ref_pop) ** CITY_POPULATION_EXPONENT
    return float(luminance_to_mag(art + mag_to_luminance(natural_mag)))


@dataclass(frozen=True)
class City:
    """A town's glow on the sky: ``azimuth_deg`` from north through east, ``distance_km``
    from the observer, ``population`` (people)."""

    azimuth_deg: float
    distance_km: float
    population: float

    def __post_init__(self):
        check_range("city azimuth_deg", self.azimuth_deg, -360.0, 360.0, "deg")
        check_range("city distance_km", self.distance_km, 1.0, 500.0, "km")
        check_range("city population", self.population, 1.0, 1e8)

    def walker_fraction(self) -> float:
        """Walker's law (Walker 1977, PASP 89, 405): the city raises the sky at 45 deg
        elevation towards it by I = 0.01 P d^-2.5 of the natural background (P people,
        d km)."""
        return 0.01 * self.population * self.distance_km**-2.5


def city_profile(zenith_rad, delta_azimuth_rad, extinction_mag=DEFAULT_EXTINCTION_MAG):
    """A city's glow relative to its value at 45 deg elevation towards it: the slab profile
    (slab_profile) times exp(kappa (cos da - 1) sin z) (concentrated towards the city near the
    horizon, no azimuth dependence at the zenith) times exp(-eta (cos z - cos 45 deg)) (falling
    with elevation). kappa = 2 (half width 48 deg at the horizon) and eta = 1.5 are skydome's
    smooth simplification of the domes Garstang's (1986, PASP 98, 364) model computes, not a
    fit to them."""
    z = np.asarray(zenith_rad, dtype=np.float64)
    da = np.asarray(delta_azimuth_rad, dtype=np.float64)
    c45 = math.cos(math.radians(45.0))
    lobe = np.exp(CITY_AZIMUTH_KAPPA * (np.cos(da) - 1.0) * np.sin(z))
    fall = np.exp(-CITY_ELEVATION_ETA * (np.cos(z) - c45))
    return (
        slab_profile(z, extinction_mag)
        / slab_profile(math.radians(45.0), extinction_mag)
        * (lobe * fall)
    )


def _people(population: float) -> str:
    """``11 million``, ``400,000``."""
    if population >= 1e6:
        return f"{population / 1e6:.3g} million"
    return f"{population:,.0f}"


# ---------------------------------------------------------------------- spectra

LAMPS = ("hps", "led4000")


def lamp_spectrum(lamp: str, grid_nm) -> np.ndarray:
    """Relative spectral power (energy per nm) of a street lamp on ``grid_nm``.

    ``"hps"``: high-pressure sodium as Gaussian components: the self-reversed, pressure-
    broadened Na D emission as two lobes at 583 nm (sigma 7 nm) and 598 nm (12 nm), Na lines at
    568.8, 515, 498 and 466 nm, and a weak continuum 400-700 nm; built to give the lamp's
    published colour, CCT ~2000 K, and scotopic/photopic ratio ~0.62 (HPS: CCT 1900-2100 K,
    S/P 0.62: IES TM-12-12 table 1). ``"led4000"``: a phosphor-converted white LED as a blue
    die peak (450 nm, sigma 9 nm) and a phosphor band (570 nm, sigma 55 nm), the two-Gaussian
    model of Ohno 2005 (Opt. Eng. 44, 111302), weighted 0.3 : 1 for CCT 4000 K.
    """
    check_choice("lamp", lamp, LAMPS, "lamp spectrum")
    g = np.asarray(grid_nm, dtype=np.float64)

    def gauss(centre, sigma):
        return np.exp(-0.5 * ((g - centre) / sigma) ** 2)

    if lamp == "hps":
        lines = gauss(498.0, 2.0) + gauss(466.0, 2.0) + 0.7 * gauss(515.0, 2.0)
        continuum = ((g > 400.0) & (g < 700.0)).astype(np.float64)
        return (
            gauss(583.0, 7.0)
            + gauss(598.0, 12.0)
            + 0.3 * gauss(568.8, 2.0)
            + 0.2 * lines
            + 0.045 * continuum
        )
    return 0.3 * gauss(450.0, 9.0) + gauss(570.0, 55.0)


def lamp_relative_spectrum(lamp: str, wavelengths_nm) -> np.ndarray:
    """A lamp's spectrum binned onto ``wavelengths_nm`` relative to the solar spectrum."""
    grid = np.arange(360.0, 831.0, 1.0)
    return bin_relative_to_sun(grid, lamp_spectrum(lamp, grid), wavelengths_nm)


def correlated_colour_temperature(grid_nm, spectrum) -> float:
    """CCT (K) of a spectral power distribution by McCamy's (1992, Color Res. Appl. 17, 142)
    formula from its CIE 1931 chromaticity."""

    xyz = cmf_xyz(np.asarray(grid_nm, dtype=np.float64)).T @ np.asarray(spectrum, np.float64)
    x, y = xyz[0] / xyz.sum(), xyz[1] / xyz.sum()
    n = (x - 0.3320) / (0.1858 - y)
    return float(449.0 * n**3 + 3525.0 * n**2 + 6823.3 * n + 5520.33)


def scotopic_photopic_ratio(grid_nm, spectrum) -> float:
    """S/P ratio: 1700 lm/W * int V'(l) S / (683 lm/W * int V(l) S)."""

    g = np.asarray(grid_nm, dtype=np.float64)
    s = np.asarray(spectrum, dtype=np.float64)
    return float(1700.0 * (scotopic_efficiency(g) @ s) / (683.0 * (photopic_efficiency(g) @ s)))


# ---------------------------------------------------------------------- the model


class LightPollution:
    """Artificial sky glow: a uniform part set by its zenith brightness, plus city domes.

    Give at most one of ``zenith_mag_arcsec2`` (the artificial part alone, V mag/arcsec^2),
    ``zenith_cd_m2`` (the artificial part's luminance) or use :meth:`from_bortle` (a class's
    total brightness less the natural 21.9). With none, only the cities glow.

    Args:
        zenith_mag_arcsec2: artificial zenith brightness, V mag/arcsec^2 (10 to 30).
        zenith_cd_m2: artificial zenith luminance, cd/m^2 (0 to 1).
        cities: ``City`` objects (at most 8), each with Walker's law at 45 deg elevation.
        lamp: ``"hps"`` (high-pressure sodium, default) or ``"led4000"``.
        extinction_mag: the air's V extinction (mag/airmass, 0.05 to 1) in the profile.
        natural_zenith_mag: the natural sky Walker's law and Bortle classes refer to.
    """

    def __init__(
        self,
        zenith_mag_arcsec2: float | None = None,
        *,
        zenith_cd_m2: float | None = None,
        cities=(),
        lamp: str = "hps",
        extinction_mag: float = DEFAULT_EXTINCTION_MAG,
        natural_zenith_mag: float = NATURAL_ZENITH_MAG,
    ):
        if zenith_mag_arcsec2 is not None and zenith_cd_m2 is not None:
            raise ParameterError("give zenith_mag_arcsec2 or zenith_cd_m2, not both")
        self.natural_zenith_mag = check_range(
            "natural_zenith_mag", natural_zenith_mag, 15.0, 25.0, "mag/arcsec^2"
        )
        if zenith_mag_arcsec2 is not None:
            m = check_range("zenith_mag_arcsec2", zenith_mag_arcsec2, 10.0, 30.0, "mag/arcsec^2")
            self.zenith_cd_m2 = float(mag_to_luminance(m))
        elif zenith_cd_m2 is not None:
            self.zenith_cd_m2 = check_range("zenith_cd_m2", zenith_cd_m2, 0.0, 1.0, "cd/m^2")
        else:
            self.zenith_cd_m2 = 0.0
        try:
            self.cities = tuple(cities)
        except TypeError:
            raise ParameterError(f"cities must be City objects, got {cities!r}") from None
        if len(self.cities) > MAX_CITIES:
            raise ParameterError(f"{len(self.cities)} cities: at most {MAX_CITIES}")
        for c in self.cities:
            if not isinstance(c, City):
                raise ParameterError(f"cities must be City objects, got {c!r}")
        self.lamp = check_choice("lamp", lamp, LAMPS, "lamp spectrum")
        self.extinction_mag = check_range("extinction_mag", extinction_mag, 0.05, 1.0, "mag")
        self.bortle_class: int | None = None
        #: where the glow comes from, for a report (a place's estimate), or None
        self.source: str | None = None

    @classmethod
    def from_bortle(cls, bortle_class: int, **kwargs) -> LightPollution:
        """The glow of a Bortle class (1-9): its zenith total (bortle_zenith_mag) less the
        natural sky, uniform over the sky with the slab profile (plus any ``cities``)."""
        natural = kwargs.get("natural_zenith_mag", NATURAL_ZENITH_MAG)
        natural = check_range("natural_zenith_mag", natural, 15.0, 25.0, "mag/arcsec^2")
        lum = artificial_zenith_luminance(bortle_zenith_mag(bortle_class), natural)
        lp = cls(zenith_cd_m2=lum, **kwargs)
        lp.bortle_class = int(bortle_class)
        return lp

    @property
    def natural_cd_m2(self) -> float:
        return float(mag_to_luminance(self.natural_zenith_mag))

    def city_luminance_45(self) -> list[float]:
        """Each city's added luminance (cd/m^2) at 45 deg elevation towards it."""
        return [c.walker_fraction() * self.natural_cd_m2 for c in self.cities]

    def luminance(self, directions_enu, observer_height_m: float = 0.0) -> np.ndarray:
        """Artificial luminance (cd/m^2) seen in unit ENU ``directions_enu`` (..., 3); 0 where
        the ray meets the ground."""

        d = np.asarray(directions_enu, dtype=np.float64)
        z = np.arccos(np.clip(d[..., 2], -1.0, 1.0))
        az = np.arctan2(d[..., 0], d[..., 1])
        out = self.zenith_cd_m2 * slab_profile(z, self.extinction_mag)
        for city, l45 in zip(self.cities, self.city_luminance_45(), strict=True):
            da = az - math.radians(city.azimuth_deg)
            out = out + l45 * city_profile(z, da, self.extinction_mag)
        return np.where(d[..., 2] >= -horizon_dip_sin(observer_height_m), out, 0.0)

    def zenith_mag(self) -> float:
        """The artificial zenith brightness (V mag/arcsec^2; inf when dark)."""
        return float(luminance_to_mag(self.luminance(np.array([0.0, 0.0, 1.0]))))

    @classmethod
    def for_place(cls, place: Place) -> LightPollution | None:
        """A gazetteer place's own light pollution, or None for none (a dark site, or a
        position given as numbers): an observatory's Bortle class (``place.bortle``; classes
        1 and 2 are as dark as the natural sky: None), a city's glow estimated from its
        population (city_zenith_mag). ``source`` says which, for a report."""
        if not isinstance(place, Place):
            raise ParameterError(f"for_place takes a skydome Place, got {place!r}")
        if place.population is not None:
            total = city_zenith_mag(place.population)
            lp = cls(zenith_cd_m2=artificial_zenith_luminance(total))
            lp.source = (
                f"{place.name}: estimated from its population, "
                f"{_people(place.population)} (Berry's P^0.5 law)"
            )
            return lp
        if place.bortle is not None:
            if artificial_zenith_luminance(bortle_zenith_mag(place.bortle)) == 0.0:
                return None
            lp = cls.from_bortle(place.bortle)
            lp.source = f"{place.name}: the site's Bortle class"
            return lp
        return None

    def total_zenith_mag(self) -> float:
        """The zenith brightness with the natural sky's (V mag/arcsec^2), as an SQM reads."""
        art = float(self.luminance(np.array([0.0, 0.0, 1.0])))
        return float(luminance_to_mag(art + self.natural_cd_m2))

    def summary(self) -> str:
        """One line: the total zenith brightness, its Bortle class and where it comes from."""
        total = self.total_zenith_mag()
        cls = self.bortle_class or bortle_class_of(total)
        source = self.source or "given"
        return f"zenith {total:.2f} mag/arcsec^2 (Bortle {cls}), {source}"

    def __repr__(self) -> str:
        return (
            f"LightPollution(zenith {self.zenith_mag():.2f} mag/arcsec^2, "
            f"{len(self.cities)} cities, {self.lamp})"
        )
