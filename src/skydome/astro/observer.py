"""The observer-facing API: where is everything in my sky, and how bright is it?

>>> from skydome.astro import Observer
>>> obs = Observer(latitude=48.85, longitude=2.35, elevation_m=35)
>>> sky = obs.sky(["2024-06-21T12:00Z", "2024-06-21T22:00Z"], bodies=("sun", "moon"))
>>> sky["sun"].alt_deg            # apparent (refracted) altitude, degrees
>>> sky["moon"].enu               # unit vectors (x east, y north, z up) for the renderer

Chain for every body (all vectorized over times and, by broadcasting, observers):

1. geocentric astrometric position, light-time corrected, in the mean ecliptic of date
   (:mod:`~skydome.astro.sun`, :mod:`~skydome.astro.moon`, :mod:`~skydome.astro.planets`);
2. rotated to the true equator of date with the mean obliquity and the nutation matrix;
3. topocentric: minus the observer's position (WGS84, rotated by the apparent sidereal
   time; polar motion, < 0.3", is neglected);
4. for the planets, light deflection by the Sun (finite-distance NOVAS formula,
   :func:`~skydome.astro.frames.deflect_by_sun`); aberration with the Earth's orbital
   velocity plus the observer's diurnal velocity;
5. to East-North-Up with the local apparent sidereal time and the geodetic latitude;
6. refraction (Saemundsson, with the observer's pressure and temperature) for the
   apparent altitude; ``alt_unrefracted`` is the airless one.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from skydome.astro import frames, moon, photometry, planets, sun
from skydome.astro.frames import ARCSEC, AU_KM, C_AU_PER_DAY
from skydome.astro.time import Time, gmst, julian_centuries, to_time
from skydome.errors import ParameterError
from skydome.physics.constants import ARCMIN_RAD

__all__ = ["Observer", "BodyPosition", "SkyPositions", "BODIES"]

BODIES = ("sun", "moon") + planets.PLANETS
_OMEGA_RAD_PER_DAY = frames.EARTH_OMEGA * 86400.0


def _check_array(name: str, value: Any, lo: float, hi: float, unit: str) -> np.ndarray | float:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(f"{name} must be a number, got {value!r}") from None
    bad = ~((a >= lo) & (a <= hi))  # also catches NaN
    if np.any(bad):
        shown = a if a.ndim == 0 else a[bad].ravel()[0]
        raise ParameterError(
            f"{name} = {shown:g} {unit} is outside the valid range [{lo:g}, {hi:g}] {unit}"
        )
    return float(a) if a.ndim == 0 else a


@dataclass
class BodyPosition:
    """Where one body is for each requested time (arrays shaped like the times).

    Angles are radians (``*_deg`` properties give degrees); azimuth from north via east.
    ``alt`` is apparent (refracted for the observer's pressure and temperature),
    ``alt_unrefracted`` airless; ``ra``/``dec`` are topocentric apparent, true equator and
    equinox of date; ``enu`` (..., 3) unit vectors of the refracted direction,
    ``enu_unrefracted`` of the airless one. ``extra`` holds body-specific quantities
    (phase angle, illuminated fraction, magnitude...).
    """

    name: str
    alt: np.ndarray
    alt_unrefracted: np.ndarray
    az: np.ndarray
    ra: np.ndarray
    dec: np.ndarray
    distance_km: np.ndarray
    angular_diameter: np.ndarray
    illuminance_lux: np.ndarray
    enu: np.ndarray
    enu_unrefracted: np.ndarray
    extra: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def alt_deg(self) -> np.ndarray:
        return np.degrees(self.alt)

    @property
    def az_deg(self) -> np.ndarray:
        return np.degrees(self.az)

    @property
    def distance_au(self) -> np.ndarray:
        return self.distance_km / AU_KM

    def __getattr__(self, item: str) -> np.ndarray:
        extra = self.__dict__.get("extra", {})
        if item in extra:
            return extra[item]
        raise AttributeError(item)

    def as_dict(self, index: Any = ()) -> dict[str, Any]:
        """Plain dict (degrees, km, lux) of the values at ``index`` (default: a 0-d result)."""

        def pick(a):
            v = np.asarray(a)[index]
            return v.tolist() if isinstance(v, np.ndarray) else float(v)

        out = {
            "alt": pick(np.degrees(self.alt)),
            "alt_unrefracted": pick(np.degrees(self.alt_unrefracted)),
            "az": pick(np.degrees(self.az)),
            "ra": pick(np.degrees(self.ra)),
            "dec": pick(np.degrees(self.dec)),
            "distance_km": pick(self.distance_km),
            "angular_diameter": pick(np.degrees(self.angular_diameter)),
            "illuminance_lux": pick(self.illuminance_lux),
        }
        for k, v in self.extra.items():
            deg = k in ("phase_angle", "bright_limb_angle", "earth_phase_angle")
            out[k] = pick(np.degrees(v) if deg else v)
        return out


@dataclass
class SkyPositions:
    """Result of :meth:`Observer.sky`: the times and one :class:`BodyPosition` per body.

    ``sky["moon"]`` or ``sky.bodies["moon"]``; ``stars`` is a :class:`BodyPosition` whose
    arrays have an extra trailing star axis (``times.shape + (n_stars,)``), with
    ``extra["hip"]`` and ``extra["vmag"]``, or None.
    """

    time: Time
    bodies: dict[str, BodyPosition]
    stars: BodyPosition | None = None

    def __getitem__(self, name: str) -> BodyPosition:
        return self.bodies[name]

    def __iter__(self):
        return iter(self.bodies)


@dataclass(frozen=True)
class Observer:
    """A place on the WGS84 ellipsoid and its weather (for refraction).

    ``latitude`` (deg, geodetic, north positive), ``longitude`` (deg, east positive),
    ``elevation_m`` (metres above the ellipsoid), ``pressure_hPa`` and ``temperature_C``
    (used only for refraction; pressure 0 switches refraction off). Each may be an array
    that broadcasts against the times given to :meth:`sky`.
    """

    latitude: Any
    longitude: Any
    elevation_m: Any = 0.0
    pressure_hPa: Any = 1010.0
    temperature_C: Any = 10.0

    def __post_init__(self) -> None:
        checks = {
            "latitude": (-90.0, 90.0, "deg"),
            "longitude": (-360.0, 360.0, "deg"),
            "elevation_m": (-1000.0, 100000.0, "m"),
            "pressure_hPa": (0.0, 1200.0, "hPa"),
            "temperature_C": (-100.0, 70.0, "C"),
        }
        for name, (lo, hi, unit) in checks.items():
            object.__setattr__(self, name, _check_array(name, getattr(self, name), lo, hi, unit))

    # ------------------------------------------------------------------ geometry

    def _geometry(self, t: Time) -> dict[str, np.ndarray]:
        """Per-time matrices and vectors shared by all bodies (flattened times)."""
        jd = t.jd_tt.ravel()
        shape = t.shape
        lat = np.broadcast_to(np.radians(self.latitude), shape).ravel()
        lon = np.broadcast_to(np.radians(self.longitude), shape).ravel()
        h = np.broadcast_to(np.asarray(self.elevation_m, float), shape).ravel()
        eps_a = frames.mean_obliquity(jd)
        dpsi, deps = frames.nutation_angles(jd)
        ecl_to_true = frames.ecliptic_to_true_matrix_from_angles(eps_a, dpsi, deps)
        om = frames._fundamental_args(julian_centuries(jd))[4]
        eqeq = dpsi * np.cos(eps_a) + (0.00264 * np.sin(om) + 0.000063 * np.sin(2 * om)) * ARCSEC
        gast = gmst(t.jd_ut1.ravel(), jd) + eqeq
        r_itrs = frames.geodetic_to_geocentric_km(lat, lon, h)  # (N, 3) km
        c, s = np.cos(gast), np.sin(gast)
        x = c * r_itrs[:, 0] - s * r_itrs[:, 1]
        y = s * r_itrs[:, 0] + c * r_itrs[:, 1]
        r_obs = np.stack([x, y, r_itrs[:, 2]], axis=-1) / AU_KM  # au, true equator of date
        v_obs = np.stack([-y, x, np.zeros_like(x)], axis=-1) / AU_KM * _OMEGA_RAD_PER_DAY
        earth, v_earth = sun.earth_heliocentric_state(jd)  # au, au/day; ecliptic of date
        v_total = np.einsum("nij,nj->ni", ecl_to_true, v_earth) + v_obs
        enu_m = frames.equatorial_to_enu_matrix(gast + lon, lat)
        return {
            "jd": jd,
            "ecl_to_true": ecl_to_true,
            "r_obs": r_obs,
            "v_total": v_total,
            "v_earth_ecl": v_earth,
            "earth": earth,
            "sun_to_obs": np.einsum("nij,nj->ni", ecl_to_true, earth) + r_obs,  # au, true eq.
            "enu": enu_m,
            "pressure": np.broadcast_to(np.asarray(self.pressure_hPa, float), shape).ravel(),
            "temperature": np.broadcast_to(np.asarray(self.temperature_C, float), shape).ravel(),
        }

    def _place(
        self, geo: dict[str, np.ndarray], name: str, geo_ecl: np.ndarray, deflect: bool = False
    ) -> dict:
        """Topocentric apparent direction of a geocentric astrometric ecliptic vector (au).

        ``deflect``: apply the Sun's gravitational light deflection (for the planets; the
        geometric ``topo`` vector and distance are returned undeflected).
        """
        geo_true = np.einsum("nij,nj->ni", geo["ecl_to_true"], geo_ecl)
        topo = geo_true - geo["r_obs"]
        dist = frames.norm3(topo)
        seen = frames.deflect_by_sun(topo, geo["sun_to_obs"]) if deflect else topo
        u = seen / frames.norm3(seen)[:, None]
        u = frames.aberrate(u, geo["v_total"])
        return self._horizontal(geo, u, dist, topo)

    @staticmethod
    def _horizontal(geo, u, dist, topo) -> dict:
        ra, dec, _ = frames.cartesian_to_spherical(u)
        enu0 = np.einsum("nij,n...j->n...i", geo["enu"], u)
        alt0, az = frames.enu_to_horizontal(enu0)
        p, tc = geo["pressure"], geo["temperature"]
        if enu0.ndim == 3:
            p, tc = p[:, None], tc[:, None]
        refr = frames.refraction_saemundsson(np.degrees(alt0), p, tc) * ARCMIN_RAD
        alt = alt0 + refr
        return {
            "alt": alt,
            "alt_unrefracted": alt0,
            "az": az,
            "ra": ra,
            "dec": dec,
            "distance_au": dist,
            "enu": frames.horizontal_to_enu(alt, az),
            "enu_unrefracted": enu0,
            "topo": topo,
        }

    # ------------------------------------------------------------------ public

    def sky(
        self,
        times: Any,
        bodies: tuple[str, ...] | list[str] | str = ("sun", "moon"),
        stars: bool = False,
        *,
        star_mag_limit: float = 6.5,
        delta_t: Any = None,
        ut1_utc: Any = None,
    ) -> SkyPositions:
        """Positions and photometry of ``bodies`` (and optionally the stars) at ``times``.

        ``times``: anything :func:`skydome.astro.time.to_time` accepts (arrays of any
        shape); ``bodies``: names from ``BODIES`` or star names known to
        :mod:`skydome.astro.stars`; ``stars``: also return every catalogue star brighter
        than ``star_mag_limit`` (V) in ``SkyPositions.stars``; ``delta_t`` (TT - UT1, s) and
        ``ut1_utc`` (s) override the built-in time tables.
        """
        if isinstance(bodies, str):
            bodies = tuple(b.strip() for b in bodies.split(",") if b.strip())
        t = to_time(times, delta_t=delta_t, ut1_utc=ut1_utc)
        fields = (
            self.latitude,
            self.longitude,
            self.elevation_m,
            self.pressure_hPa,
            self.temperature_C,
        )
        shape = np.broadcast_shapes(t.shape, *(np.shape(f) for f in fields))
        if shape != t.shape:  # observers given as arrays: broadcast the times against them
            t = Time(*(np.broadcast_to(a, shape) for a in (t.jd_utc, t.jd_ut1, t.jd_tt)))
        geo = self._geometry(t)
        names = [str(b).lower() if str(b).lower() in BODIES else str(b) for b in bodies]
        star_bodies = [b for b in names if b not in BODIES]
        star_infos = {b: _find_star(b) for b in star_bodies}  # raises for unknown names

        need_sun = any(b in ("sun", "moon") or b in planets.PLANETS for b in names)
        out: dict[str, BodyPosition] = {}
        sun_place = None
        if need_sun:
            sun_place = self._place(geo, "sun", -geo["earth"])
        for b in names:
            if b == "sun":
                out[b] = self._sun(sun_place, shape)
            elif b == "moon":
                out[b] = self._moon(geo, sun_place, shape)
            elif b in planets.PLANETS:
                out[b] = self._planet(geo, b, shape)
            else:
                out[b] = self._star(geo, star_infos[b], shape)
        star_pos = self._all_stars(geo, shape, star_mag_limit) if stars else None
        return SkyPositions(time=t, bodies=out, stars=star_pos)

    # ------------------------------------------------------------------ bodies

    @staticmethod
    def _body(name, place, shape, illum, extra=None, diameter=None) -> BodyPosition:
        def r(a):
            a = np.asarray(a)
            return a.reshape(shape + a.shape[1:])

        dist_km = place["distance_au"] * AU_KM
        return BodyPosition(
            name=name,
            alt=r(place["alt"]),
            alt_unrefracted=r(place["alt_unrefracted"]),
            az=r(place["az"]),
            ra=r(place["ra"]),
            dec=r(place["dec"]),
            distance_km=r(dist_km),
            angular_diameter=r(np.zeros_like(dist_km) if diameter is None else diameter),
            illuminance_lux=r(illum),
            enu=r(place["enu"]),
            enu_unrefracted=r(place["enu_unrefracted"]),
            extra={k: r(v) for k, v in (extra or {}).items()},
        )

    def _sun(self, place, shape) -> BodyPosition:
        d_au = place["distance_au"]
        extra = {"irradiance_w_m2": photometry.sun_irradiance_w_m2(d_au)}
        return self._body(
            "sun",
            place,
            shape,
            photometry.sun_illuminance_lux(d_au),
            extra,
            sun.sun_angular_diameter(d_au * AU_KM),
        )

    def _moon(self, geo, sun_place, shape) -> BodyPosition:
        jd = geo["jd"]
        tau0 = 384400.0 / frames.C_KM_PER_S / 86400.0  # mean light time, days
        lam, beta, dist_km = moon.moon_ecliptic_of_date(jd - tau0)
        m_ecl = frames.spherical_to_cartesian(lam, beta, dist_km / AU_KM)
        m_dist_au = frames.norm3(m_ecl)
        tau = m_dist_au / C_AU_PER_DAY
        # astrometric = Moon(t - tau) + E(t - tau) - E(t) ~ Moon(t - tau) - v_E tau
        geo_ecl = m_ecl - geo["v_earth_ecl"] * tau[:, None]
        place = self._place(geo, "moon", geo_ecl)
        d_au = place["distance_au"]
        i = moon.phase_angle(place["topo"], sun_place["topo"])
        sun_moon_au = frames.norm3(sun_place["topo"] - place["topo"])
        earth_phase = np.arccos(
            np.clip(
                -frames.dot3(m_ecl, geo["earth"]) / (m_dist_au * frames.norm3(geo["earth"])),
                -1.0,
                1.0,
            )
        )
        mag = photometry.moon_magnitude(i, d_au * AU_KM, sun_moon_au)
        extra = {
            "phase_angle": i,
            "illuminated_fraction": moon.illuminated_fraction(i),
            "bright_limb_angle": moon.bright_limb_position_angle(
                place["ra"], place["dec"], sun_place["ra"], sun_place["dec"]
            ),
            "earth_phase_angle": earth_phase,
            "magnitude": mag,
        }
        return self._body(
            "moon",
            place,
            shape,
            photometry.magnitude_to_lux(mag),
            extra,
            moon.moon_angular_diameter(d_au * AU_KM),
        )

    def _planet(self, geo, name, shape) -> BodyPosition:
        g_ecl, helio, _ = planets.planet_geocentric_ecliptic(name, geo["jd"], earth=geo["earth"])
        place = self._place(geo, name, g_ecl, deflect=True)
        delta = place["distance_au"]
        r = frames.norm3(helio)
        # phase angle at the planet between the Sun (-helio) and the observer (-topo)
        obs_ecl = np.einsum("nji,nj->ni", geo["ecl_to_true"], place["topo"])
        c = frames.dot3(helio, obs_ecl) / (r * delta)
        phase = np.arccos(np.clip(c, -1.0, 1.0))
        tilt = planets.saturn_ring_tilt(g_ecl, geo["jd"]) if name == "saturn" else 0.0
        mag = planets.planet_magnitude(name, r, delta, phase, tilt)
        extra = {"phase_angle": phase, "magnitude": mag, "illuminated_fraction": 0.5 * (1 + c)}
        if name == "saturn":
            extra["ring_tilt"] = tilt
        radius = _PLANET_RADIUS_KM[name]
        diam = 2.0 * np.arcsin(np.minimum(radius / (delta * AU_KM), 1.0))
        return self._body(name, place, shape, photometry.magnitude_to_lux(mag), extra, diam)

    def _star(self, geo, info, shape) -> BodyPosition:
        stars = importlib.import_module("skydome.astro.stars")
        u = stars.apparent_unit_vectors(geo["jd"], np.array([info.index]))[:, 0, :]
        v_obs = geo["v_total"] - np.einsum("nij,nj->ni", geo["ecl_to_true"], geo["v_earth_ecl"])
        u = frames.aberrate(u, v_obs)  # diurnal aberration (annual is in the stars module)
        inf = np.full(u.shape[0], np.inf)
        place = self._horizontal(geo, u, inf, u)
        n = u.shape[0]
        extra = {"magnitude": np.full(n, info.vmag)}
        lux = photometry.magnitude_to_lux(extra["magnitude"])
        return self._body(
            info.name or info.designation or f"HIP {info.hip}", place, shape, lux, extra
        )

    def _all_stars(self, geo, shape, mag_limit) -> BodyPosition:
        stars = importlib.import_module("skydome.astro.stars")
        cat = stars.catalog()
        mask = np.flatnonzero(cat.vmag <= mag_limit)
        u = stars.apparent_unit_vectors(geo["jd"], mask)  # (N, S, 3)
        v_obs = geo["v_total"] - np.einsum("nij,nj->ni", geo["ecl_to_true"], geo["v_earth_ecl"])
        u = frames.aberrate(u, v_obs[:, None, :])
        dist = np.full(u.shape[:2], np.inf)
        place = self._horizontal(geo, u, dist, u)
        vmag = np.broadcast_to(cat.vmag[mask], u.shape[:2])
        extra = {"vmag": vmag, "hip": np.broadcast_to(cat.hip[mask], u.shape[:2])}
        return self._body("stars", place, shape, photometry.magnitude_to_lux(vmag), extra)


# Equatorial radii (km), IAU WG on Cartographic Coordinates 2015 (Archinal et al. 2018).
_PLANET_RADIUS_KM = {
    "mercury": 2440.53,
    "venus": 6051.8,
    "mars": 3396.19,
    "jupiter": 71492.0,
    "saturn": 60268.0,
    "uranus": 25559.0,
    "neptune": 24764.0,
}


def _find_star(name: str):
    try:
        stars = importlib.import_module("skydome.astro.stars")
    except ImportError:
        raise ParameterError(
            f"unknown body {name!r}: expected one of {', '.join(BODIES)}"
        ) from None
    try:
        return stars.find_star(name)
    except ParameterError as exc:
        raise ParameterError(
            f"unknown body {name!r}: expected one of {', '.join(BODIES)} or a star name ({exc})"
        ) from None
