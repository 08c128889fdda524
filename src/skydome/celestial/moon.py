"""The Moon layer: the lunar disk beyond the atmosphere, phased, mapped and earthlit.

Photometry (``shaders/celestial/moon.glsl``): each point of the visible hemisphere has the
radiance L = k A(lon, lat) mu0 / (mu0 + mu), the Lommel-Seeliger law (mu0, mu the cosines
of incidence and emission; Hapke 2012, "Theory of reflectance and emittance spectroscopy",
eq. 9.4, as the single-scattering limit of a dark regolith), with A the albedo map
(skydome.celestial.moon_albedo) turned by the libration. The constant k is set for each
instant so that the disk integrates to the Moon's illuminance of the astronomy, Allen's
phase law (skydome.astro.photometry.moon_magnitude): the shape of the lit disk is the
law's, its total is the measured phase curve's. The integral is taken on the CPU over a
grid of the disk (:func:`disk_integrals`), with the same normals and map as the shader.

Earthshine: the Earth lights the night side from the observer's direction (phase ~0), so
that side is drawn as a full Moon of illuminance E_full * E_earth / E_sun, E_earth the
Earth's illuminance at the Moon (skydome.scene.state.earthshine_lux) and E_full the full
Moon of Allen's law at the same distances.

Colour: the solar spectrum times the Moon's spectral albedo (Velikodsky et al. 2011),
through the frame's spectral basis.
"""

from __future__ import annotations

import math

import numpy as np

from skydome.astro.photometry import magnitude_to_lux, moon_magnitude
from skydome.celestial.moon_albedo import albedo_at, moon_albedo_map, moon_spectral_albedo
from skydome.scene.layer import DrawContext, Layer
from skydome.scene.state import AU_KM, SkyState, refraction_scale

#: Grid of the CPU disk integral: GRID x GRID cells over the disk's bounding square (the
#: disk's ~7200 cells sum Allen's law to 0.1 %, measured against 4x finer grids).
GRID = 96


def disk_integrals(
    moon_dir: np.ndarray,
    sin_radius: float,
    to_sun: np.ndarray,
    enu_to_moon: np.ndarray,
    grid: int = GRID,
    use_map: bool = True,
) -> tuple[float, float]:
    """Integrals over the Moon's disk (sr) of A mu0/(mu0+mu) (the sunlit law) and of A/2
    (the law at opposition, mu0 = mu), for a disk of angular radius asin(sin_radius) towards
    ``moon_dir`` lit from ``to_sun`` (unit ENU vectors), with the map turned by
    ``enu_to_moon`` (3x3, ENU -> Moon-fixed; ``use_map=False``: a uniform albedo of 1). Cells of the tangent plane at unit distance,
    each of solid angle dx dy / (1 + x^2 + y^2)^(3/2)."""
    u = moon_dir / np.linalg.norm(moon_dir)
    e1 = np.cross(u, [0.0, 0.0, 1.0] if abs(u[2]) < 0.9 else [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    # Tangent-plane half-width tan(alpha) covers the disk; cell centres.
    half = sin_radius / math.sqrt(1.0 - sin_radius**2)
    c = (np.arange(grid) + 0.5) / grid * 2.0 - 1.0
    x, y = np.meshgrid(c * half, c * half)
    cell = (2.0 * half / grid) ** 2 / (1.0 + x * x + y * y) ** 1.5
    d = u + x[..., None] * e1 + y[..., None] * e2
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    s2 = np.sum(np.cross(d, u) ** 2, axis=-1)
    inside = (s2 < sin_radius**2) & (d @ u > 0)
    d, s2, cell = d[inside], s2[inside], cell[inside]
    t = d @ u - np.sqrt(np.maximum(sin_radius**2 - s2, 0.0))
    n = (t[:, None] * d - u) / sin_radius
    mu = np.maximum(-np.sum(n * d, axis=-1), 0.0)
    mu0 = n @ to_sun
    m = n @ enu_to_moon.T
    lon, lat = np.arctan2(m[:, 1], m[:, 0]), np.arcsin(np.clip(m[:, 2], -1.0, 1.0))
    albedo = albedo_at(lon, lat) if use_map else np.ones_like(lon)
    law = np.where(mu0 > 0, mu0 / np.maximum(mu0 + mu, 1e-12), 0.0)
    return float(np.sum(albedo * law * cell)), float(np.sum(albedo * 0.5 * cell))


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
        self._uniforms: dict | None = None
        self._key = None
        self._info: dict = {}
        self._colour = None

    def prepare(self, graph) -> None:
        super().prepare(graph)
        ctx = graph.ctx
        a = moon_albedo_map() if self.albedo_map else np.ones((2, 4), np.float32)
        h, w = a.shape
        self._texture = ctx.texture((w, h), 1, np.ascontiguousarray(a, "f4").tobytes(), dtype="f4")
        self._texture.filter = (ctx.LINEAR, ctx.LINEAR)
        self._texture.repeat_x, self._texture.repeat_y = True, False

    def update(self, state: SkyState) -> None:
        key = (id(state), id(self.graph.basis))
        if key == self._key:
            return
        self._key = key
        moon, view = state.moon, state.moon_view
        if moon is None or view is None:
            self._uniforms, self._info = None, {}
            return
        self._moon = moon
        sin_r = math.sin(moon.angular_radius_rad)
        enu_to_moon = view.frame.T if self.albedo_map else np.eye(3)
        u = np.asarray(moon.direction_true, dtype=np.float64)
        sunlit, opposition = disk_integrals(
            u, sin_r, view.to_sun, enu_to_moon, use_map=self.albedo_map
        )
        # Allen's law at the true distances: the phase law, and its full Moon for earthshine.
        sun_moon_au = state.sun.distance_km / AU_KM  # the Sun-Moon distance is the Sun's +- 0.3 %
        e_full = float(magnitude_to_lux(moon_magnitude(0.0, moon.distance_km, sun_moon_au)))
        sunlit_scale = moon.illuminance_lux / sunlit if sunlit > 0 else 0.0
        earthlit_scale = 0.0
        if self.earthshine:
            earthlit_scale = (
                0.5 * e_full / opposition * view.earthshine_lux / state.sun.illuminance_lux
            )
        basis = self.graph.basis
        if self._colour is None or self._colour[0] is not basis:
            self._colour = (basis, basis.colour(moon_spectral_albedo(basis.wavelengths_nm)))
        self._uniforms = {
            "u_moon_direction_true": tuple(float(v) for v in u),
            "u_sin_angular_radius": sin_r,
            "u_moon_to_sun": tuple(float(v) for v in view.to_sun),
            # GLSL mat3 is column-major: the columns of enu_to_moon one after the other.
            "u_enu_to_moon": tuple(np.asarray(enu_to_moon).T.ravel()),
            "u_sunlit_scale": sunlit_scale,
            "u_earthlit_scale": earthlit_scale,
            "u_colour": tuple(float(v) for v in self._colour[1]),
            "u_refraction_scale": refraction_scale(state),
        }
        self._info = {
            "moon_illuminated_fraction": view.illuminated_fraction,
            "moon_earthshine_lux": view.earthshine_lux,
        }

    def draw(self, frame: DrawContext) -> None:
        if self._uniforms is None:
            return
        fpass = self.full_screen_pass(frame.ctx, self.shader, frame.camera)
        self.draw_small(
            frame,
            fpass,
            {**self._uniforms, **frame.uniforms},
            {**frame.textures, "u_albedo_map": self._texture},
            self._moon.direction,
            1.1 * self._moon.angular_radius_rad,
        )

    def info(self) -> dict:
        return dict(self._info)

    def release(self) -> None:
        super().release()
        if self._texture is not None:
            self._texture.release()
            self._texture = None
