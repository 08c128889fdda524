"""The Moon layer: the lunar disk beyond the atmosphere, phased, mapped and earthlit.

Photometry (``shaders/celestial/moon.glsl``): each point of the visible hemisphere has the
radiance L = k A(lon, lat) mu0 / (mu0 + mu), the Lommel-Seeliger law (mu0, mu the cosines
of incidence and emission; Hapke 2012, "Theory of reflectance and emittance spectroscopy",
eq. 9.4, as the single-scattering limit of a dark regolith), with A the albedo map
(skydome.celestial.moon_albedo) turned by the libration. The constant k is set for each
instant so that the disk integrates to the Moon's illuminance of the astronomy, Allen's
phase law (skydome.astro.photometry.moon_magnitude): the shape of the lit disk is the
law's, its total is the measured phase curve's. The integral is taken on the CPU by
Gauss-Legendre quadrature over the lit, visible part of the sphere (:func:`disk_integrals`),
with the same geometry and map as the shader.

Earthshine: the Earth lights the night side from the observer's direction (phase ~0), so
that side is drawn as a full Moon of illuminance E_full * E_earth / E_sun, E_earth the
Earth's illuminance at the Moon (skydome.scene.state.earthshine_lux) and E_full the full
Moon of Allen's law at the same distances.

Colour: the solar spectrum times the Moon's spectral albedo (Velikodsky et al. 2011),
through the frame's spectral basis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from skydome.astro.photometry import magnitude_to_lux, moon_magnitude
from skydome.celestial.moon_albedo import albedo_at, moon_albedo_map, moon_spectral_albedo
from skydome.celestial.surface_laws import lommel_seeliger_law
from skydome.core.cameras import CameraInputs, disk_samples, disk_scissor
from skydome.core.layer import DrawContext, Layer
from skydome.core.lights import SkyState
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.shared import SharedResource
from skydome.physics.constants import AU_KM
from skydome.physics.geometry import horizon_dip_rad
from skydome.physics.packing import mat3
from skydome.spectra import SRGB_LUMINANCE
from skydome.spectra.colour import conversion_matrix

#: Gauss-Legendre nodes per dimension of each piece of the CPU disk integral (6 ms a call).
#: With the albedo map, against a 3000 x 3000 ray-traced grid at phase angles 6, 83, 128 and
#: 151 deg, the sunlit integral is within 0.09 % and the opposition one within 0.27 % (the
#: map's texels alias; 96 nodes: 0.09 % both, at 3x the time). With a uniform albedo the
#: sunlit integral matches the closed form to 1.5e-7 (1.4e-6 for a 170 deg crescent).
NODES = 64
#: The disk is not drawn (nor its integrals taken) while its apparent elevation is below
#: -HIDDEN_BELOW_DEG (deg), or below the horizon's dip + HIDDEN_MARGIN_DEG from a camera
#: high enough for the dip to matter (over SMALLEST_PLANET_RADIUS_KM: Mars, the smallest
#: preset, the largest dip): the ground hides all of it (a disk of <= 0.28 deg radius).
HIDDEN_BELOW_DEG = 18.0
HIDDEN_MARGIN_DEG = 2.0
SMALLEST_PLANET_RADIUS_KM = 3389.5


def _gauss_legendre_01(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def disk_integrals(
    moon_dir: np.ndarray,
    sin_radius: float,
    to_sun: np.ndarray,
    enu_to_moon: np.ndarray,
    nodes: int = NODES,
    use_map: bool = True,
) -> tuple[float, float]:
    """Integrals over the Moon's disk (sr) of A mu0/(mu0+mu) (the sunlit law) and of A/2
    (the law at opposition, mu0 = mu), for a sphere of angular radius asin(sin_radius) towards
    ``moon_dir`` lit by parallel sunlight from ``to_sun`` (unit ENU vectors), with the map
    turned by ``enu_to_moon`` (3x3, ENU -> Moon-fixed; ``use_map=False``: a uniform albedo 1).

    The geometry is the shader's: the observer at a finite distance sees the cap within
    90 deg - alpha of the sub-observer point, mu is the cosine of the emission angle of the
    ray to the observer, and a surface element dA of the sphere subtends mu dA / |p|^2.

    Quadrature in photometric coordinates on the sphere (latitude beta about the axis normal
    to the Sun-Moon-observer plane, longitude lambda from the sub-observer point towards the
    Sun): the sunlit visible region is lambda in [a - pi/2, lambda_v(beta)] (a the phase
    angle, cos(lambda_v) cos(beta) = sin(alpha) the visible edge), so that the terminator
    and the limb are edges of the domain and Gauss-Legendre converges fast; the
    beta-integral is split where the terminator meets the limb and takes
    beta = beta_max - D s^2 where the chord closes like a square root. For a uniform albedo
    and alpha -> 0 the sunlit integral is (Omega/2) times the Lommel-Seeliger phase function
    1 - sin(a/2) tan(a/2) ln(cot(a/4)) (tested against it).
    """
    u = np.asarray(moon_dir, dtype=np.float64)
    u = u / np.linalg.norm(u)
    w = -u  # from the Moon's centre towards the observer
    s = np.asarray(to_sun, dtype=np.float64)
    s = s / np.linalg.norm(s)
    rho = float(sin_radius)  # the Moon's radius in units of its distance
    side = s - (s @ w) * w
    if np.linalg.norm(side) < 1e-12:  # Sun exactly behind the observer or the Moon
        side = np.cross(w, [0.0, 0.0, 1.0] if abs(w[2]) < 0.9 else [1.0, 0.0, 0.0])
    ex = side / np.linalg.norm(side)
    ey = np.cross(w, ex)
    a = math.atan2(float(s @ ex), float(s @ w))  # phase angle, [0, pi]
    beta_max = math.acos(rho)
    t, wt = _gauss_legendre_01(nodes)
    to_moon = np.asarray(enu_to_moon, dtype=np.float64)

    def strip(beta, dbeta, low, sunlit: bool) -> float:
        cb, sb = np.cos(beta)[:, None], np.sin(beta)[:, None]
        high = np.arccos(np.minimum(rho / cb[:, 0], 1.0))
        low = np.maximum(low(high), -high)
        span = np.maximum(high - low, 0.0)
        lam = low[:, None] + span[:, None] * t
        weight = span[:, None] * wt * dbeta[:, None]
        nw = cb * np.cos(lam)
        n = nw[..., None] * w + (cb * np.sin(lam))[..., None] * ex + sb[..., None] * ey
        p2 = 1.0 - 2.0 * rho * nw + rho * rho  # |u + rho n|^2, the squared distance
        mu = np.maximum((nw - rho) / np.sqrt(p2), 0.0)
        d_omega = mu * rho * rho * cb / p2 * weight
        if sunlit:
            mu0 = cb * np.cos(lam - a)
            law = lommel_seeliger_law(mu0, mu)
        else:
            law = 0.5
        albedo = 1.0
        if use_map:
            m = n @ to_moon.T
            lon = np.arctan2(m[..., 1], m[..., 0])
            albedo = albedo_at(lon, np.arctan2(m[..., 2], np.hypot(m[..., 0], m[..., 1])))
        return float(np.sum(albedo * law * d_omega))

    def both(beta, dbeta, low, sunlit: bool) -> float:
        return strip(beta, dbeta, low, sunlit) + strip(-beta, dbeta, low, sunlit)

    def outer(b0: float):  # [b0, beta_max], the chord closing like sqrt(beta_max - beta)
        d = beta_max - b0
        return beta_max - d * t * t, 2.0 * d * t * wt

    def chord(high):
        return -high

    def terminator(high):
        return np.full_like(high, a - 0.5 * math.pi)

    opposition = both(*outer(0.0), chord, False)
    if a < 0.5 * math.pi and math.sin(a) <= rho:  # the whole visible cap is lit
        return both(*outer(0.0), chord, True), opposition
    # |beta| < b_k: the terminator bounds the lit part; beyond, (a < 90 deg) the whole chord
    # is lit, or (a > 90 deg) nothing is.
    b_k = math.acos(min(rho / math.sin(a), 1.0))
    sunlit = both(b_k * t, b_k * wt, terminator, True)
    if a < 0.5 * math.pi:
        sunlit += both(*outer(b_k), chord, True)
    return sunlit, opposition


#: Tolerances of the disk integrals' cache (MoonLayer._integrals): 0.05 deg of the Sun's and
#: the observer's directions seen from the Moon, 1e-4 of the disk's angular size.
CACHE_RAD = math.radians(0.05)
CACHE_SIZE = 1e-4


@dataclass(frozen=True)
class MoonInputs(ShaderInputs):
    """``celestial/moon.glsl``: the disk's airless centre and angular size, the Sun's
    direction from the Moon, the ENU -> Moon-fixed matrix (column-major), the scales of the
    sunlit and earthlit photometric laws, the Moon's colour, the refraction factor, the
    albedo map, the points a pixel averages per side (``disk_samples``)."""

    u_moon_direction_true: tuple[float, float, float]
    u_sin_angular_radius: float
    u_moon_to_sun: tuple[float, float, float]
    u_enu_to_moon: tuple[float, ...]
    u_sunlit_scale: float
    u_earthlit_scale: float
    u_colour: tuple[float, float, float, float]
    u_refraction_scale: float
    u_albedo_map: object
    u_disk_samples: float = 1.0


@dataclass(frozen=True)
class LunarEclipseInputs(ShaderInputs):
    """``celestial/moon.glsl`` with LUNAR_ECLIPSE: the Sun's, the Earth's and the Moon's
    centres from the observer (km, ENU), the radii (km: the Moon's, the Earth's shadow-casting
    one, the Sun's), and the refracted light's table (output channels per cd/m^2 of
    uneclipsed moonlight at distances 0, step, 2 step... km from the shadow's axis)."""

    u_ecl_sun_km: tuple[float, float, float]
    u_ecl_earth_km: tuple[float, float, float]
    u_ecl_moon_km: tuple[float, float, float]
    u_ecl_radii_km: tuple[float, float, float]
    u_ecl_umbra_step_km: float
    u_ecl_umbra: list[float]


def umbra_channels(basis, eclipse, albedo) -> np.ndarray:
    """The refracted light of ``eclipse`` (a ``LunarEclipseView``) in ``basis``'s output
    channels per unit luminance of the uneclipsed Moon's light (spectral ``albedo`` at the
    basis's wavelengths): (N, 4)."""
    wl = basis.wavelengths_nm
    f = np.stack(
        [np.interp(wl, eclipse.wavelengths_nm, row) for row in eclipse.umbra_light]
    )  # (N, W)
    y = float(SRGB_LUMINANCE @ (conversion_matrix(wl, "rgbs") @ albedo)[:3])
    return (f * albedo) @ basis.to_output.T / y


class MoonLayer(Layer):
    """The Moon's disk. ``earthshine=False`` leaves the night side black; ``albedo_map=False``
    draws a uniform grey Moon of the same brightness."""

    name = "moon"
    stage = "space"
    shader = "celestial/moon.glsl"

    def __init__(self, *, earthshine: bool = True, albedo_map: bool = True, enabled=True):
        super().__init__(enabled=enabled)
        self.earthshine = bool(earthshine)
        self.albedo_map = bool(albedo_map)
        self._texture = None
        self._holder: SharedResource | None = None  # the albedo map, shared with fresh() copies
        self._donor: SharedResource | None = None
        self._inputs: MoonInputs | None = None
        self._key = None
        self._info: dict = {}
        self._colour = None
        self._cache = None  # the last disk integrals and the geometry they were taken for
        self._pending = None  # what the disk's scales need, until a draw that sees it
        self._moon = None
        self._eclipse: LunarEclipseInputs | None = None

    def prepare(self, graph) -> None:
        super().prepare(graph)
        ctx = graph.ctx
        donor, self._donor = self._donor, None
        if donor is not None and donor.serves(ctx):  # Sky.at: the map of the sky it came from
            self._holder, self._texture = donor, donor.take()
            return
        a = moon_albedo_map() if self.albedo_map else np.ones((2, 4), np.float32)
        h, w = a.shape
        self._texture = ctx.texture((w, h), 1, np.ascontiguousarray(a, "f4").tobytes(), dtype="f4")
        self._texture.filter = (ctx.LINEAR, ctx.LINEAR)
        self._texture.repeat_x, self._texture.repeat_y = True, False
        self._holder = SharedResource(self._texture, ctx)

    def update(self, state: SkyState) -> None:
        key = (id(state), id(self.graph.basis))
        if key == self._key:
            return
        self._key = key
        moon, view = state.moon, state.moon_view
        if moon is None or view is None:
            self._inputs, self._info, self._pending = None, {}, None
            return
        self._moon = moon
        sin_r = math.sin(moon.angular_radius_rad)
        enu_to_moon = view.frame.T if self.albedo_map else np.eye(3)
        u = np.asarray(moon.direction_true, dtype=np.float64)
        # The disk's scales need its integrals (~6 ms): taken at the first draw that can see
        # the disk (_scaled), not for a Moon under the ground.
        self._pending = (u, sin_r, view.to_sun, enu_to_moon, state)
        basis = self.graph.basis
        if self._colour is None or self._colour[0] is not basis:
            self._colour = (basis, basis.colour(moon_spectral_albedo(basis.wavelengths_nm)))
        self._inputs = MoonInputs(
            u_moon_direction_true=tuple(float(v) for v in u),
            u_sin_angular_radius=sin_r,
            u_moon_to_sun=tuple(float(v) for v in view.to_sun),
            u_enu_to_moon=mat3(enu_to_moon),
            u_sunlit_scale=0.0,
            u_earthlit_scale=0.0,
            u_colour=tuple(float(v) for v in self._colour[1]),
            u_refraction_scale=state.refraction_scale,
            u_albedo_map=self._texture,
        )
        self._info = {
            "moon_illuminated_fraction": view.illuminated_fraction,
            "moon_earthshine_lux": view.earthshine_lux,
        }
        self._eclipse = None
        ecl = state.lunar_eclipse
        if ecl is not None:
            albedo = moon_spectral_albedo(basis.wavelengths_nm)
            table = umbra_channels(basis, ecl, albedo)
            q = ecl.umbra_distances_km
            self._eclipse = LunarEclipseInputs(
                u_ecl_sun_km=tuple(float(v) for v in ecl.sun_km),
                u_ecl_earth_km=tuple(float(v) for v in ecl.earth_km),
                u_ecl_moon_km=tuple(float(v) for v in u * moon.distance_km),
                u_ecl_radii_km=(
                    moon.distance_km * sin_r,
                    float(ecl.earth_radius_km),
                    state.sun.distance_km * math.sin(state.sun.angular_radius_rad),
                ),
                u_ecl_umbra_step_km=float(q[1] - q[0]),
                u_ecl_umbra=table.ravel().tolist(),
            )
            self._info["moon_eclipse_factor"] = ecl.moon_light_factor

    def hidden(self, altitude_m: float) -> bool:
        """Whether the ground hides the whole disk from a camera at ``altitude_m``: its
        apparent elevation below -max(HIDDEN_BELOW_DEG, the horizon's dip over the smallest
        planet of the presets + HIDDEN_MARGIN_DEG)."""
        if self._moon is None:
            return True
        r_km = SMALLEST_PLANET_RADIUS_KM + max(float(altitude_m), 0.0) / 1000.0
        dip = math.degrees(horizon_dip_rad(r_km, SMALLEST_PLANET_RADIUS_KM))
        return self._moon.elevation_deg < -max(HIDDEN_BELOW_DEG, dip + HIDDEN_MARGIN_DEG)

    def _scaled(self, altitude_m: float) -> bool:
        """Set the disk's scales from its integrals (once per update) unless the disk is
        hidden from ``altitude_m``; False when it is (nothing to draw)."""
        if self._pending is None:
            return True
        if self.hidden(altitude_m):
            return False
        u, sin_r, to_sun, enu_to_moon, state = self._pending
        moon, view = state.moon, state.moon_view
        sunlit, opposition = self._integrals(u, sin_r, to_sun, enu_to_moon)
        # Allen's law at the true distances: the phase law, and its full Moon for earthshine.
        sun_moon_au = state.sun.distance_km / AU_KM  # the Sun-Moon distance is the Sun's +- 0.3 %
        e_full = float(magnitude_to_lux(moon_magnitude(0.0, moon.distance_km, sun_moon_au)))
        sunlit_scale = moon.illuminance_lux / sunlit if sunlit > 0 else 0.0
        earthlit_scale = 0.0
        if self.earthshine:
            earthlit_scale = (
                0.5 * e_full / opposition * view.earthshine_lux / state.sun.illuminance_lux
            )
        self._inputs = replace(
            self._inputs, u_sunlit_scale=sunlit_scale, u_earthlit_scale=earthlit_scale
        )
        self._pending = None
        return True

    def _integrals(self, u, sin_r, to_sun, enu_to_moon) -> tuple[float, float]:
        """disk_integrals, reused while the geometry that decides them has not moved: the
        directions to the Sun and to the observer in the Moon's own frame (a turn of the
        whole configuration, as the sky turns, changes nothing) within CACHE_RAD, and the
        disk's size within CACHE_SIZE (the integrals scale as its solid angle). In a
        time-lapse at 1-minute steps that is about every 6th step; the phase law changes by
        0.13 % over CACHE_RAD (Allen: 0.026 mag/deg)."""
        m_sun = enu_to_moon @ np.asarray(to_sun, dtype=np.float64)
        m_obs = enu_to_moon @ -u
        if self._cache is not None:
            c_sun, c_obs, c_sin, values = self._cache
            if (
                np.max(np.abs(m_sun - c_sun)) < CACHE_RAD
                and np.max(np.abs(m_obs - c_obs)) < CACHE_RAD
                and abs(sin_r / c_sin - 1.0) < CACHE_SIZE
            ):
                scale = (sin_r / c_sin) ** 2
                return values[0] * scale, values[1] * scale
        values = disk_integrals(u, sin_r, to_sun, enu_to_moon, use_map=self.albedo_map)
        self._cache = (m_sun, m_obs, sin_r, values)
        return values

    def draw(self, frame: DrawContext) -> None:
        if self._inputs is None:
            return
        rects = disk_scissor(
            frame.camera,
            *frame.frame_size,
            self._moon.direction,
            1.1 * self._moon.angular_radius_rad,
        )
        if rects == [] or not self._scaled(frame.altitude_m):
            return  # out of the frame (then its integrals wait for a frame that shows it)
        samples = disk_samples(
            frame.camera, *frame.frame_size, self._moon.angular_radius_rad, rects
        )
        moon = replace(self._inputs, u_disk_samples=float(samples))
        if self._eclipse is None:
            fpass = self.full_screen_pass(
                frame.ctx, self.shader, (CameraInputs, MoonInputs), frame.camera
            )
            inputs = (frame.view, moon)
        else:
            samples = len(self._eclipse.u_ecl_umbra) // 4
            fpass = self.full_screen_pass(
                frame.ctx, self.shader, (CameraInputs, MoonInputs, LunarEclipseInputs),
                frame.camera, {"LUNAR_ECLIPSE": 1, "UMBRA_SAMPLES": samples},
            )  # fmt: skip
            inputs = (frame.view, moon, self._eclipse)
        self.draw_in_rects(frame, fpass, inputs, rects)

    def fresh(self) -> MoonLayer:
        """A new layer with this one's arguments and its last disk integrals (they hold for
        the geometry they were taken for, whichever sky asks: ``Sky.at``) that, prepared on
        the same context, shares this one's albedo map (uploaded once for a sky and its
        ``Sky.at`` copies; freed with the last of them)."""
        layer = super().fresh()
        layer._cache = self._cache
        layer._donor = self._holder
        return layer

    def info(self) -> dict:
        return dict(self._info)

    def release(self) -> None:
        super().release()
        if self._holder is not None:
            self._holder.drop()
        self._holder = self._texture = None
