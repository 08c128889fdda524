"""The planets layer: Mercury to Neptune at their apparent places, as disks or points.

Positions and brightness come from ``skydome.astro`` (``Observer.sky``): the apparent
(refracted) and airless directions, the distance, the angular diameter from the IAU radii,
the phase angle, and the V magnitude of Mallama & Hilton (2018), turned into an illuminance
outside the atmosphere with ``photometry.magnitude_to_lux`` (the atmosphere layer applies
the extinction). Saturn's magnitude is that of its globe and rings together (their eq. 10);
the rings are not drawn, so the globe carries their light.

Colour: the solar spectrum times each planet's geometric albedo spectrum
(skydome.celestial.planet_colours: smooth curves fitted to the B, V and R albedos of
Mallama et al. 2017), through the frame's spectral basis.

A planet is drawn as a **disk** when its radius in the frame is at least
``DISK_MIN_RADIUS_PX`` pixels (the pixel size at the planet from
``render.projection.pixel_solid_angle``), otherwise as a **point** through the shared
point-source pass (skydome.celestial.point_sources, a Gaussian PSF of sigma 0.8 px). Both
integrate to the planet's illuminance, so the switch conserves the light.

The disk (``shaders/celestial/planet.glsl``) is a sphere lit by parallel sunlight from the
planet -> Sun direction, built from the phase angle of the astronomy and the Sun's direction:
the planet -> Sun vector has, across the line of sight, the component of the observer -> Sun
vector (the planet lies on the line of sight), and makes the phase angle with the planet ->
observer direction. Its radiance follows one of two laws, each normalised on the CPU by its
closed-form disk integral (exact for a sphere seen from far away; a planet's finite
distance changes it by the planet's angular radius in radians, < 3e-4;
skydome.celestial.surface_laws):

- **Lommel-Seeliger**, L = k mu0 / (mu0 + mu), for Mercury and Mars: the single-scattering
  law of a dark, porous regolith (Hapke 2012, "Theory of reflectance and emittance
  spectroscopy", eq. 9.4; the Moon layer's law), disk integral (Omega/2) Phi_LS(a) with
  Phi_LS(a) = 1 - sin(a/2) tan(a/2) ln(cot(a/4)) (Fairbairn 2005, JRASC 99, 92);
- **Lambert**, L = k mu0, for Venus and the giant planets: their bright cloud decks
  (geometric albedos 0.44-0.69 in V) scatter light many times, which brings the reflection
  towards the isotropic, limb-darkened Lambert surface (Minnaert's law with exponent 1; an
  approximation: measured limb darkening varies with wavelength and latitude), disk
  integral (2/3) Omega Phi_L(a) with Phi_L(a) = (sin a + (pi - a) cos a) / pi (Russell
  1916, ApJ 43, 173).

The Moon hides what lies behind its disk: the rays of a disk's pixels that meet the Moon
get nothing, and a point planet whose centre lies behind the Moon is not drawn (the point
pass also darkens its PSF's pixels on the Moon's disk).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skydome.astro.planets import PLANETS
from skydome.astro.time import Time
from skydome.celestial.planet_colours import planet_albedo
from skydome.celestial.point_sources import PointSources
from skydome.celestial.surface_laws import lambert_phase_function, lommel_seeliger_phase_function
from skydome.core.cameras import CameraInputs
from skydome.core.layer import DrawContext, Layer
from skydome.core.lights import Light, SkyState
from skydome.gpu.inputs import ShaderInputs
from skydome.physics.refraction import refract_enu

#: A planet whose disk has at least this radius in frame pixels is drawn as a disk.
DISK_MIN_RADIUS_PX = 1.0
#: The point-source PSF (Gaussian sigma, frame pixels), the stars' value.
PSF_SIGMA_PX = 0.8
#: The photometric law of each planet's disk (see the module docstring).
LAWS = {
    "mercury": "lommel-seeliger",
    "venus": "lambert",
    "mars": "lommel-seeliger",
    "jupiter": "lambert",
    "saturn": "lambert",
    "uranus": "lambert",
    "neptune": "lambert",
}
_LAW_DEFINE = {"lambert": 0, "lommel-seeliger": 1}


def disk_law_integral(law: str, phase_angle_rad: float, angular_radius_rad: float) -> float:
    """Integral (sr) over a sphere's disk of the law (``"lambert"``: mu0, or
    ``"lommel-seeliger"``: mu0 / (mu0 + mu)) for a sphere of angular radius
    ``angular_radius_rad`` lit at ``phase_angle_rad`` (its far-away limit)."""
    r = float(angular_radius_rad)
    omega = 4.0 * math.pi * math.sin(0.5 * r) ** 2  # 2 pi (1 - cos r)
    if law == "lambert":
        return 2.0 / 3.0 * omega * float(lambert_phase_function(phase_angle_rad))
    return 0.5 * omega * float(lommel_seeliger_phase_function(phase_angle_rad))


def planet_to_sun(direction_true, sun_direction_true, phase_angle_rad: float) -> np.ndarray:
    """Unit ENU vector from a planet towards the Sun: at the phase angle from the planet ->
    observer direction, towards the Sun's side across the line of sight (unit airless ENU
    directions of the planet and of the Sun from the observer)."""
    u = np.asarray(direction_true, dtype=np.float64)
    u = u / np.linalg.norm(u)
    s = np.asarray(sun_direction_true, dtype=np.float64)
    across = s - (s @ u) * u
    norm = float(np.linalg.norm(across))
    if norm < 1e-12:  # the Sun on the line of sight: any perpendicular will do
        across = np.cross(u, [0.0, 0.0, 1.0] if abs(u[2]) < 0.9 else [1.0, 0.0, 0.0])
        norm = float(np.linalg.norm(across))
    a = float(phase_angle_rad)
    return math.cos(a) * -u + math.sin(a) * across / norm


@dataclass(frozen=True)
class PlanetView(Light):
    """One planet as the observer sees it at one instant: a ``Light`` (ENU unit vectors,
    radians, lux) with its magnitude, phase angle and the unit vector towards the Sun."""

    magnitude: float = math.nan
    phase_angle_rad: float = 0.0
    to_sun: np.ndarray = None

    @property
    def illuminated_fraction(self) -> float:
        """Fraction of the disk's area that is sunlit, (1 + cos a) / 2."""
        return 0.5 * (1.0 + math.cos(self.phase_angle_rad))


def planet_views(observer, time, sun_direction_true) -> list[PlanetView]:
    """The seven planets seen by ``observer`` at one ``time`` (a skydome.astro Time), lit
    from the airless Sun direction ``sun_direction_true``."""
    nodes = _PlanetNodes(observer, time, 1, 0.0)
    return nodes.views(float(np.asarray(time.jd_tt)), sun_direction_true)


#: While the time runs (a time-lapse, a viewer), the planets are computed in one vectorized
#: call at NODES_PER_BATCH instants NODE_MINUTES apart and interpolated between them: the
#: airless directions normalized-linearly (a planet moves <= 0.25 deg a minute along its
#: diurnal circle: < 0.1" off; tests/test_time_steps.py) and refracted as observer.sky does,
#: the photometry linearly. A batch of 61 costs ~3 single instants.
NODE_MINUTES = 1.0
NODES_PER_BATCH = 61
#: Consecutive instants further apart than this (minutes) are computed one by one.
BATCH_MAX_STEP_MINUTES = 10.0


class _PlanetNodes:
    """The planets at ``count`` instants ``step_days`` apart from ``time`` (one call)."""

    def __init__(self, observer, time, count: int, step_days: float):
        offsets = np.arange(count) * step_days
        times = Time(*(np.asarray(a, dtype=np.float64).reshape(()) + offsets for a in (
            time.jd_utc, time.jd_ut1, time.jd_tt)))  # fmt: skip
        sky = observer.sky(times, bodies=PLANETS)
        self.observer = observer
        self.weather = (float(observer.pressure_hPa), float(observer.temperature_C))
        self.jd_tt = float(np.asarray(time.jd_tt)) + offsets
        self.step = step_days
        self.data = {}
        for name in PLANETS:
            b = sky[name]
            self.data[name] = (
                np.asarray(b.enu, dtype=np.float64).reshape(count, 3),
                np.asarray(b.enu_unrefracted, dtype=np.float64).reshape(count, 3),
                np.stack([
                    np.asarray(v, dtype=np.float64).reshape(count)
                    for v in (b.distance_km, b.angular_diameter, b.illuminance_lux,
                              b.extra["magnitude"], b.extra["phase_angle"])
                ], axis=1),
            )  # fmt: skip

    def covers(self, observer, jd_tt: float) -> bool:
        """Whether ``jd_tt`` lies within the nodes (for ``observer``)."""
        return observer is self.observer and self.jd_tt[0] <= jd_tt <= self.jd_tt[-1]

    def views(self, jd_tt: float, sun_direction_true) -> list[PlanetView]:
        """The planets at ``jd_tt`` (a node, or interpolated between two)."""
        if len(self.jd_tt) == 1:
            i, f = 0, 0.0
        else:
            x = (jd_tt - self.jd_tt[0]) / self.step
            i = int(min(max(math.floor(x), 0), len(self.jd_tt) - 2))
            f = float(x - i)
        out = []
        for name in PLANETS:
            enu, true, values = self.data[name]
            if f == 0.0:
                seen, air, v = enu[i], true[i], values[i]
            else:
                air = true[i] + f * (true[i + 1] - true[i])
                air = air / np.linalg.norm(air)
                # Refracted anew (observer.sky's law): the law stops at -1.9 deg, where
                # two nodes' refracted directions would interpolate across its step.
                seen = refract_enu(air, *self.weather)[0]
                v = values[i] + f * (values[i + 1] - values[i])
            phase = float(v[4])
            out.append(
                PlanetView(
                    name=name,
                    direction=seen,
                    direction_true=air,
                    distance_km=float(v[0]),
                    angular_radius_rad=0.5 * float(v[1]),
                    illuminance_lux=float(v[2]),
                    magnitude=float(v[3]),
                    phase_angle_rad=phase,
                    to_sun=planet_to_sun(air, sun_direction_true, phase),
                )
            )
        return out


def _samples_per_axis(radius_px: float, phase_angle_rad: float) -> int:
    """Rays per pixel along each axis for a disk of this radius (frame pixels) at this phase:
    enough for the disk (32 / radius) and for the lit part's width across the terminator,
    radius (1 + cos a) (12 / width), at most 32. Measured on Venus at phase angles 117 and
    150 deg, 1.5 to 7.5 px in radius: the disk's total is within 1.5 % of the closed form;
    thinner crescents (a > ~160 deg, narrower than ~0.2 px) alias, by up to tens of %."""
    if not math.isfinite(radius_px):
        return 1
    r = max(radius_px, 1e-6)
    width = max(r * (1.0 + math.cos(phase_angle_rad)), 1e-6)
    return int(min(32, max(1, math.ceil(max(32.0 / r, 12.0 / width)))))


@dataclass(frozen=True)
class PlanetInputs(ShaderInputs):
    """``celestial/planet.glsl``: a resolved planet's disk (airless centre, angular size,
    the Sun's direction from it), the Moon's disk that may hide it, the photometric law's
    scale (lx per unit integral), its colour, the samples per pixel axis, the refraction
    factor."""

    u_planet_direction_true: tuple[float, float, float]
    u_sin_angular_radius: float
    u_planet_to_sun: tuple[float, float, float]
    u_moon_direction_true: tuple[float, float, float]
    u_moon_sin_radius: float
    u_scale: float
    u_colour: tuple[float, float, float, float]
    u_samples: int
    u_refraction_scale: float


class PlanetsLayer(Layer):
    """Mercury to Neptune: disks when at least ``DISK_MIN_RADIUS_PX`` in radius, else points.

    Draws nothing in the abstract mode (no place or time)."""

    name = "planets"
    stage = "space"
    shader = "celestial/planet.glsl"

    def __init__(self, *, enabled: bool = True):
        super().__init__(enabled=enabled)
        self._key = None
        self._views: list[PlanetView] = []
        self._colours: dict = {}  # basis id -> {planet: colour (4,)}
        self._moon = None
        self._refraction = 0.0
        self._points = None
        self._drawn_as_disk: dict[str, bool] = {}
        self._nodes: _PlanetNodes | None = None  # while the time runs: batched instants

    # ------------------------------------------------------------------ update

    def update(self, state: SkyState) -> None:
        if state.observer is None or state.time is None:
            self._key, self._views, self._moon = None, [], None
            return
        key = (id(state.observer), float(np.asarray(state.time.jd_tt)), id(state.sun))
        self._moon = state.moon
        self._refraction = state.refraction_scale
        if key == self._key:
            return
        jd = key[1]
        running = self._key is not None and self._key[0] == key[0] and (
            0.0 < abs(jd - self._key[1]) <= BATCH_MAX_STEP_MINUTES / 1440.0
        )  # fmt: skip
        sun = state.sun.direction_true
        if running:
            if self._nodes is None or not self._nodes.covers(state.observer, jd):
                step = NODE_MINUTES / 1440.0
                start = jd if jd > self._key[1] else jd - (NODES_PER_BATCH - 1) * step
                offset = start - jd  # the first node from this instant (days)
                t = state.time
                first = Time(*(float(np.asarray(a)) + offset for a in (
                    t.jd_utc, t.jd_ut1, t.jd_tt)))  # fmt: skip
                self._nodes = _PlanetNodes(state.observer, first, NODES_PER_BATCH, step)
            self._views = self._nodes.views(jd, sun)
        else:  # one instant: computed exactly
            self._views = planet_views(state.observer, state.time, sun)
        self._key = key

    def views(self) -> list[PlanetView]:
        """The planets of the last update."""
        return list(self._views)

    def colour(self, basis, planet: str) -> np.ndarray:
        """Output channels per cd/m^2 of ``planet``'s light in ``basis`` (cached)."""
        table = self._colours.get(id(basis))
        if table is None or table[0] is not basis:
            wl = basis.wavelengths_nm
            table = (basis, {p: basis.colour(planet_albedo(p, wl)) for p in PLANETS})
            self._colours[id(basis)] = table
        return table[1][planet]

    # ------------------------------------------------------------------ draw

    def radius_px(self, frame: DrawContext, view: PlanetView) -> float:
        """The planet's angular radius in frame pixels where it lies (inf for cameras with
        no forward mapping, e.g. a DirectionsCamera: those always get the disk)."""

        if not frame.camera.has_projection:
            return math.inf
        w, h = frame.frame_size
        pixel_sr = float(frame.camera.solid_angle(view.direction, w, h))
        return view.angular_radius_rad / math.sqrt(pixel_sr) if pixel_sr > 0 else math.inf

    def draw(self, frame: DrawContext) -> None:
        if not self._views:
            return
        points, channels = [], []
        for view in self._views:
            if view.illuminance_lux <= 0.0:
                continue
            colour = self.colour(frame.basis, view.name)
            r_px = self.radius_px(frame, view)
            disk = r_px >= DISK_MIN_RADIUS_PX
            self._drawn_as_disk[view.name] = disk
            if disk:
                self._draw_disk(frame, view, colour, r_px)
            elif not self._behind_moon(view):
                points.append(view.direction)
                channels.append(colour * view.illuminance_lux)
        if points:
            if self._points is None:
                self._points = PointSources(frame.ctx)
            occluder = None
            if self._moon is not None:
                occluder = [(self._moon.direction, self._moon.angular_radius_rad)]
            self._points.draw(
                frame,
                np.array(points),
                np.array(channels),
                psf_sigma_px=PSF_SIGMA_PX,
                occluder=occluder,
            )

    def _behind_moon(self, view: PlanetView) -> bool:
        """Whether a point planet's centre lies behind the Moon's disk (then it gives no
        light at all; the point pass's occluder only darkens the pixels on the Moon)."""
        moon = self._moon
        if moon is None:
            return False
        u = np.asarray(moon.direction_true, dtype=np.float64)
        return bool(
            u @ view.direction_true > 0.0
            and np.linalg.norm(np.cross(u, view.direction_true)) < math.sin(moon.angular_radius_rad)
        )

    def _draw_disk(self, frame: DrawContext, view: PlanetView, colour, radius_px: float):
        law = LAWS[view.name]
        integral = disk_law_integral(law, view.phase_angle_rad, view.angular_radius_rad)
        if not integral > 0.0:
            return  # a new planet: nothing lit faces the observer
        fpass = self.full_screen_pass(
            frame.ctx, self.shader, (CameraInputs, PlanetInputs), frame.camera,
            {"LAW": _LAW_DEFINE[law]},
        )  # fmt: skip
        moon = self._moon
        inputs = PlanetInputs(
            u_planet_direction_true=tuple(float(v) for v in view.direction_true),
            u_sin_angular_radius=math.sin(view.angular_radius_rad),
            u_planet_to_sun=tuple(float(v) for v in view.to_sun),
            u_moon_direction_true=(
                tuple(float(v) for v in moon.direction_true) if moon else (0.0, 0.0, 1.0)
            ),
            u_moon_sin_radius=math.sin(moon.angular_radius_rad) if moon else 0.0,
            u_scale=view.illuminance_lux / integral,
            u_colour=tuple(float(v) for v in colour),
            u_samples=_samples_per_axis(radius_px, view.phase_angle_rad),
            u_refraction_scale=self._refraction,
        )
        # The apparent disk lies within its true radius of the apparent centre (refraction
        # only flattens it); 10 % spare, and draw_small adds 2 pixels for the pixel footprint.
        self.draw_small(
            frame,
            fpass,
            (frame.view, inputs),
            view.direction,
            1.1 * view.angular_radius_rad,
        )

    # ------------------------------------------------------------------ reports

    def info(self) -> dict:
        if not self._views:
            return {}
        return {
            "planets": {
                v.name: {
                    "magnitude": v.magnitude,
                    "elevation_deg": v.elevation_deg,
                    "disk": self._drawn_as_disk.get(v.name, False),
                }
                for v in self._views
            }
        }

    def release(self) -> None:
        super().release()
        if self._points is not None:
            self._points.release()
            self._points = None
