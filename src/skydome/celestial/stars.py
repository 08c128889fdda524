"""The stars layer: the packaged Hipparcos catalogue as point sources beyond the atmosphere.

Positions: the geocentric apparent places of date (``skydome.astro.stars``: space motion,
annual parallax, light deflection, annual aberration, precession and nutation), recomputed
when the time moves by more than ``APPARENT_PLACE_REFRESH_DAYS`` of TT (in an hour the
places move by < 0.02": aberration's change with the Earth's velocity, 20.5" x 2 pi / 8766 h,
and precession, 50"/yr); every update rotates them to East-North-Up with the local apparent
sidereal time (one 3x3 matrix), adds the diurnal aberration (<= 0.32") and refracts them
with the scene's weather (``refraction_saemundsson``, the observer's pressure and
temperature, as ``Observer.sky`` does for the Sun and the Moon; tabulated once per weather,
within 0.01" of the law: ``refraction_tabulated``). Stars more than 1 deg below
the camera's horizon (the dip at its altitude) are dropped: the atmosphere's ground hides
them anyway.

Light: each star's illuminance outside the atmosphere, E = 10^(-0.4 (V + 14.18)) lx
(``skydome.astro.stars.star_illuminance_lux``), in the colour of a black body at the
catalogue's effective temperature through the frame's spectral basis (``basis.colour`` of
the Planck spectrum relative to the solar one, the sky's spectral pipeline), drawn by
:class:`~skydome.celestial.point_sources.PointSources` (flux-conserving PSF) and hidden
behind the Moon's disk. The atmosphere layer applies each pixel's transmittance; this layer
applies no extinction. Light of stars fainter than the catalogue (Hp > 8) is the Milky Way
layer's, not this one's.

Twinkling (``twinkle=True``): :mod:`skydome.celestial.scintillation`, evaluated when the
layer draws, for the stars it draws (those above the camera's horizon) only.
"""

from __future__ import annotations

import math

import numpy as np

from skydome.astro import frames
from skydome.astro import stars as catalogue
from skydome.astro.time import gast
from skydome.celestial.point_sources import PointSources
from skydome.celestial.scintillation import Scintillation, scintillation_sigma
from skydome.core.basis import SpectralBasis
from skydome.core.layer import DrawContext, Layer
from skydome.core.lights import SkyState
from skydome.errors import ParameterError
from skydome.physics.constants import J2000_JD
from skydome.physics.refraction import (
    SAEMUNDSSON,
    horizon_dip_sin,
    refraction_scale,
    refraction_tabulated,
)
from skydome.spectra import SRGB_LUMINANCE, conversion_matrix
from skydome.spectra.blackbody import planck_relative
from skydome.spectra.tables import solar_irradiance

#: Recompute the apparent places of date when the time has moved by more than this (TT).
APPARENT_PLACE_REFRESH_DAYS = 1.0 / 24.0
#: Stars this far below the camera's geometric horizon are still drawn (deg).
BELOW_HORIZON_MARGIN_DEG = 1.0
#: Stars with an airless ENU z above this go through the refraction (Saemundsson's law is 0
#: below its lowest altitude, -1.9 deg; 0.01 deg below it, to be safe at the edge).
_REFRACTED_ABOVE_Z = math.sin(math.radians(SAEMUNDSSON[3] - 0.01))


def black_body_colours(basis: SpectralBasis, temperature_k) -> np.ndarray:
    """(N, 4) output channels per unit luminance of black bodies at ``temperature_k``:
    ``basis.colour(planck / solar_irradiance)`` for every temperature at once (the same
    arithmetic as SpectralBasis.colour, vectorized)."""

    wl = basis.wavelengths_nm
    f = planck_relative(wl, temperature_k) / solar_irradiance(wl)[:, None]  # (W, N)
    f /= f.max(axis=0, keepdims=True)  # any scale: the colour is per unit luminance
    y = SRGB_LUMINANCE @ (conversion_matrix(wl, "rgbs") @ f)[:3]
    return (basis.to_output @ f / y).T


class StarsLayer(Layer):
    """The catalogue's stars (37,622 with Hp <= 8; see the module docstring).

    Args:
        mag_limit: draw the stars with V <= mag_limit (None: the whole catalogue).
        psf_sigma_px: the point-spread function's sigma in frame pixels.
        seeing_fwhm_arcsec: a seeing disk added in quadrature (FWHM, arcsec).
        twinkle: scintillation growing with air mass (naked eye).
        seed: the twinkling's random seed.
    """

    name = "stars"
    stage = "space"

    def __init__(
        self,
        *,
        mag_limit: float | None = None,
        psf_sigma_px: float = 0.8,
        seeing_fwhm_arcsec: float = 0.0,
        twinkle: bool = False,
        seed: int = 0,
        enabled: bool = True,
    ):
        super().__init__(enabled=enabled)
        cat = catalogue.catalog()
        if mag_limit is None:
            self._index = np.arange(cat.n)
        else:
            if not -2.0 <= float(mag_limit) <= 30.0:
                raise ParameterError(f"mag_limit = {mag_limit!r} must lie in [-2, 30] (V mag)")
            self._index = np.flatnonzero(cat.vmag <= float(mag_limit))
        self.mag_limit = None if mag_limit is None else float(mag_limit)
        if not 0.05 <= float(psf_sigma_px) <= 32.0:
            raise ParameterError(f"psf_sigma_px = {psf_sigma_px!r} must lie in [0.05, 32] pixels")
        if not 0.0 <= float(seeing_fwhm_arcsec) <= 3600.0:
            raise ParameterError(
                f"seeing_fwhm_arcsec = {seeing_fwhm_arcsec!r} must lie in [0, 3600] arcsec"
            )
        self.psf_sigma_px = float(psf_sigma_px)
        self.seeing_fwhm_arcsec = float(seeing_fwhm_arcsec)
        self.twinkle = bool(twinkle)
        self.seed = int(seed)
        self.vmag = np.asarray(cat.vmag[self._index], dtype=np.float64)
        self.teff_k = np.asarray(cat.teff_k[self._index], dtype=np.float64)
        self.hip = np.asarray(cat.hip[self._index])
        self.lux = catalogue.star_illuminance_lux(self.vmag)
        self._scint = Scintillation(len(self._index), self.seed) if self.twinkle else None
        self._places_jd: float | None = None
        self._places: np.ndarray | None = None  # (N, 3) apparent, true equator of date
        self._columns: tuple | None = None  # (the places, their (3, N) columns)
        self._points: PointSources | None = None
        self._colours: tuple | None = None  # (basis, (N, 4))
        self._lit: tuple | None = None  # (the colours, colours x lux)
        self._drawn: tuple | None = None  # (key, directions, channels)
        self._serial = 0
        self._state_key = None
        self.directions: np.ndarray | None = None  # (N, 3) apparent ENU of the last update
        self.altitude_rad: np.ndarray | None = None  # apparent altitudes
        self._twinkle_at: tuple | None = None  # (time s since J2000 UTC, observer elevation m)
        self._factors: np.ndarray | None = None
        self._moon = None
        self._n_drawn = 0

    # ------------------------------------------------------------------ update

    def apparent_enu(self, state: SkyState) -> tuple[np.ndarray, np.ndarray]:
        """Apparent (refracted) unit ENU directions and apparent altitudes (rad) of the
        layer's stars for a state with an observer and a time (see the module docstring)."""

        obs, t = state.observer, state.time
        jd_tt = float(t.jd_tt)
        if self._places_jd is None or abs(jd_tt - self._places_jd) > APPARENT_PLACE_REFRESH_DAYS:
            self._places = catalogue.apparent_unit_vectors(jd_tt, self._index)
            self._places_jd = jd_tt
        if self._columns is None or self._columns[0] is not self._places:
            # the places as three contiguous columns: every step below works on 1-D arrays
            # (an (N, 3) product goes to multithreaded BLAS, whose idle threads spin on the
            # cores a CPU rasterizer draws with; row gathers of (N, 3) cost more than 1-D)
            self._columns = (self._places, np.ascontiguousarray(self._places.T))
        px, py, pz = self._columns[1]
        lat = math.radians(float(obs.latitude))
        lon = math.radians(float(obs.longitude))
        lst = float(gast(float(t.jd_ut1), jd_tt)) + lon
        m = frames.equatorial_to_enu_matrix(lst, lat)
        x, y, z = (px * m[k, 0] + py * m[k, 1] + pz * m[k, 2] for k in range(3))
        # Diurnal aberration: the observer moves east at omega x (distance from the axis).
        # frames.aberrate's first-order formula u' = normalize(u + b - u (u.b)), written out
        # for b = (beta, 0, 0) (a third of the general form's cost for 37,622 stars): its
        # length is sqrt(1 + beta^2 (1 - u_x^2)) for a unit u.
        speed = frames.diurnal_speed_au_per_day(lat, float(obs.elevation_m))
        beta = speed / frames.C_AU_PER_DAY
        inv_length = 1.0 / np.sqrt(1.0 + beta * beta * (1.0 - x * x))
        shrink = (1.0 - beta * x) * inv_length
        x = x * shrink + beta * inv_length
        y *= shrink
        z *= shrink
        # Refraction raises each star towards the zenith along its vertical; Saemundsson's
        # law refracts nothing below its lowest altitude, so only the stars above it (about
        # half of them) go through it: the others keep their airless directions.
        # (by the law tabulated for the weather: within 0.01" of it, a fifth of its cost)
        alt = np.arcsin(np.clip(z, -1.0, 1.0))
        seen = np.flatnonzero(z > _REFRACTED_ABOVE_Z)
        scale = refraction_scale(state.pressure_hPa, state.temperature_C)
        alt_seen, ratio = refraction_tabulated(alt[seen], scale)
        alt[seen] = alt_seen
        x[seen] *= ratio
        y[seen] *= ratio
        z[seen] = np.sin(alt_seen)
        enu = np.stack([x, y, z], axis=1)
        return enu, alt

    def fresh(self) -> StarsLayer:
        """A new layer with this one's arguments and its stars' apparent places of date (they
        hold for APPARENT_PLACE_REFRESH_DAYS, whichever sky asks: ``Sky.at``) and colours."""
        layer = super().fresh()
        layer._places_jd, layer._places = self._places_jd, self._places
        layer._columns = self._columns
        layer._colours = self._colours
        return layer

    def update(self, state: SkyState) -> None:
        key = id(state)
        if key == self._state_key:
            return
        self._state_key = key
        self._serial += 1
        self._drawn = None
        self._factors = self._twinkle_at = None
        if state.observer is None or state.time is None:  # the abstract mode: no night sky
            self.directions = self.altitude_rad = None
            self._moon = None
            return
        self.directions, self.altitude_rad = self.apparent_enu(state)
        if self._scint is not None:
            # The factors themselves are computed when drawn, for the stars drawn only.
            t_s = (float(state.time.jd_utc) - J2000_JD) * 86400.0
            self._twinkle_at = (t_s, float(state.observer.elevation_m))
        moon = state.moon
        self._moon = None if moon is None else (moon.direction, moon.angular_radius_rad)

    def twinkle_factors(self, index=slice(None)) -> np.ndarray | None:
        """Twinkling intensity factors of the stars ``index`` (indices into the layer's
        stars) at the last update's time and altitudes, or None without twinkling."""
        if self._twinkle_at is None:
            return None
        t_s, elevation_m = self._twinkle_at
        sigma = scintillation_sigma(self.altitude_rad[index], elevation_m)
        return self._scint.factors(t_s, sigma, index)

    @property
    def factors(self) -> np.ndarray | None:
        """Every star's twinkling factor at the last update (None without twinkling)."""
        if self._factors is None and self._twinkle_at is not None:
            self._factors = self.twinkle_factors()
        return self._factors

    # ------------------------------------------------------------------ draw

    def colours(self, basis: SpectralBasis) -> np.ndarray:
        """(N, 4) channels per unit luminance of the layer's stars in ``basis`` (cached)."""
        if self._colours is None or self._colours[0] is not basis:
            self._colours = (basis, black_body_colours(basis, self.teff_k))
        return self._colours[1]

    def lit_colours(self, basis: SpectralBasis) -> np.ndarray:
        """(N, 4) channels of the layer's stars in ``basis`` at their own illuminance (lux),
        without twinkling: :meth:`colours` times ``lux`` (cached)."""
        colours = self.colours(basis)
        if self._lit is None or self._lit[0] is not colours:
            self._lit = (colours, colours * self.lux[:, None])
        return self._lit[1]

    def draw(self, frame: DrawContext) -> None:
        if self.directions is None:
            return
        dip = math.asin(horizon_dip_sin(frame.altitude_m))
        lowest = -(dip + math.radians(BELOW_HORIZON_MARGIN_DEG))
        key = (self._serial, id(frame.basis), lowest)
        if self._drawn is None or self._drawn[0] != key:
            keep = np.flatnonzero(self.altitude_rad > lowest)
            if self._twinkle_at is not None:
                lux = self.lux[keep] * self.twinkle_factors(keep)
                channels = np.take(self.colours(frame.basis), keep, axis=0) * lux[:, None]
            else:
                channels = np.take(self.lit_colours(frame.basis), keep, axis=0)
            # (rows gathered by np.take: 4-8x a fancy index of an (N, 3) array)
            self._drawn = (key, np.take(self.directions, keep, axis=0), channels)
        _, directions, channels = self._drawn
        self._n_drawn = len(directions)
        if self._points is None:
            self._points = PointSources(frame.ctx)
        self._points.draw(
            frame,
            directions,
            channels,
            psf_sigma_px=self.psf_sigma_px,
            seeing_fwhm_arcsec=self.seeing_fwhm_arcsec,
            occluder=None if self._moon is None else [self._moon],
            cache_key=key,
        )

    def info(self) -> dict:
        faintest = float(self.vmag.max()) if self.vmag.size else float("nan")
        return {
            "stars_drawn": int(self._n_drawn if self.directions is not None else 0),
            "stars_mag_limit": faintest if self.mag_limit is None else self.mag_limit,
        }

    def release(self) -> None:
        super().release()
        if self._points is not None:
            self._points.release()
            self._points = None
