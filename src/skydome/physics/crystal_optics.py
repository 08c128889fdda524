"""Ray optics of ice crystals (and, as a check, of spheres): Monte Carlo ray tracing.

Cirrus crystals are tens to hundreds of micrometres across, so their light is the rays'
(van de Hulst 1957, ch. 12) plus a diffraction peak within a degree or two of the light,
which the renderer counts as unscattered. A hexagonal prism refracts the light through
faces at 60 deg to each other (side face to alternate side face: the 22 deg halo and, for
horizontal plates, the sun dogs) and at 90 deg (a base to a side: the 46 deg halo, the
circumzenithal arc), and reflects it (the parhelic circle, the pillars); where the crystals
float in order (plates with their bases horizontal, columns with their axes horizontal) the
light they scatter depends on the light's elevation and gathers in arcs (Tape 1994,
"Atmospheric Halos"; Greenler 1980, "Rainbows, Halos and Glories").

:func:`trace` follows each ray through a convex body: at every face the Fresnel shares (each
polarisation's, about that face's plane of incidence: exact for a sphere, whose plane stays
one; the usual approximation for a prism) leave or stay inside, and the ray's remaining
light goes on by internal reflection until less than ``min_weight`` of it is left (counted as
``residual``). Every ray's light is accounted for: what leaves, what the ice absorbs along the
chords (Beer-Lambert) and the residual add up to 1.

Ice's refractive index is Warren & Brandt (2008)'s compilation (J. Geophys. Res. 113,
D14220; tabulated by refractiveindex.info, CC0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from skydome.errors import ParameterError
from skydome.physics.interfaces import interface_reflectance, tabulated_index

__all__ = [
    "HexagonalPrism",
    "ICE_INDEX",
    "ICE_INDEX_NM",
    "Orientation",
    "Scattered",
    "Sphere",
    "Traced",
    "ice_index",
    "orientations",
    "scatter",
    "trace",
]

#: Ice Ih's real refractive index at -7 C (Warren & Brandt 2008) at wavelengths (nm); its
#: absorption is negligible here (k < 1.4e-7: under 1e-4 of the light over a millimetre).
ICE_INDEX_NM = (350.0, 390.0, 400.0, 420.0, 440.0, 460.0, 480.0, 500.0, 520.0, 540.0, 560.0,
                580.0, 600.0, 620.0, 640.0, 660.0, 680.0, 700.0, 720.0, 740.0, 760.0, 780.0,
                800.0)  # fmt: skip
ICE_INDEX = (1.3249, 1.3203, 1.3194, 1.3177, 1.3163, 1.3151, 1.3140, 1.3130, 1.3121, 1.3114,
             1.3106, 1.3100, 1.3094, 1.3088, 1.3083, 1.3078, 1.3073, 1.3069, 1.3065, 1.3060,
             1.3057, 1.3053, 1.3049)  # fmt: skip


def ice_index(wavelength_nm) -> np.ndarray:
    """Ice's refractive index (real part) at ``wavelength_nm`` (350-800 nm, linear between
    Warren & Brandt's nodes)."""
    return tabulated_index(wavelength_nm, ICE_INDEX_NM, ICE_INDEX, "ice")


def _refracted(d, normal, cos_i, cos_t, m):
    """The direction of light along ``d`` refracted into relative index ``m`` through a face
    whose ``normal`` points against it (cos_i = -normal . d > 0)."""
    return d / m[:, None] + (cos_i / m - cos_t)[:, None] * normal


@dataclass(frozen=True)
class HexagonalPrism:
    """A hexagonal ice prism: its c-axis along z, its corners at radius 1 from it (at
    azimuths 0, 60, ... deg) and ``aspect`` = its length over its width across the corners
    (plates ~0.1-0.3, columns ~1-3)."""

    aspect: float

    def __post_init__(self):
        if not 0.01 <= float(self.aspect) <= 100.0:
            raise ParameterError(f"a prism's aspect ratio must be 0.01-100, got {self.aspect}")

    @property
    def half_height(self) -> float:
        return float(self.aspect)

    def faces(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(outward unit normals (8, 3), their planes' distances from the centre (8,), the
        faces' areas (8,)): six sides (normals at azimuths 30, 90, ... deg), then the two
        bases (+z, -z)."""
        azimuth = np.radians(30.0 + 60.0 * np.arange(6))
        sides = np.stack([np.cos(azimuth), np.sin(azimuth), np.zeros(6)], axis=1)
        normals = np.concatenate([sides, [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]])
        h = self.half_height
        offsets = np.array([math.sqrt(3.0) / 2.0] * 6 + [h, h])
        areas = np.array([2.0 * h] * 6 + [1.5 * math.sqrt(3.0)] * 2)
        return normals, offsets, areas

    def projected_area(self, d: np.ndarray) -> np.ndarray:
        """The prism's cross-section (radius-1 units) seen along directions ``d`` (N, 3)."""
        normals, _, areas = self.faces()
        return 0.5 * np.abs(d @ normals.T) @ areas

    def entry(self, d: np.ndarray, u: np.ndarray):
        """Points where rays along ``d`` (N, 3) meet the prism, spread evenly over its
        cross-section by the uniform numbers ``u`` (N, 4) in [0, 1), and the faces' outward
        normals there."""
        normals, offsets, areas = self.faces()
        lit = np.maximum(-(d @ normals.T), 0.0) * areas  # each face's share of the shadow
        cumulative = np.cumsum(lit, axis=1)
        pick = (u[:, 0] * cumulative[:, -1])[:, None]
        face = np.minimum((cumulative < pick).sum(axis=1), 7)
        n = normals[face]
        point = n * offsets[face][:, None]
        side = face < 6
        # a side: a rectangle 1 wide (its edge between two corners) and 2h long
        tangent = np.stack([-n[:, 1], n[:, 0], np.zeros(len(d))], axis=1)
        across, along = u[:, 1] - 0.5, (u[:, 2] - 0.5) * 2.0 * self.half_height
        point[side] += tangent[side] * across[side, None]
        point[side, 2] += along[side]
        # a base: one of its six equal triangles (centre and two corners), evenly
        base = ~side
        k = np.minimum((u[base, 3] * 6.0).astype(int), 5)
        a, b = np.radians(60.0 * k), np.radians(60.0 * (k + 1))
        s, t = u[base, 1], u[base, 2]
        flip = s + t > 1.0
        s, t = np.where(flip, 1.0 - s, s), np.where(flip, 1.0 - t, t)
        point[base, 0] = s * np.cos(a) + t * np.cos(b)
        point[base, 1] = s * np.sin(a) + t * np.sin(b)
        return point, n

    def exit(self, p: np.ndarray, d: np.ndarray):
        """The distance along ``d`` from ``p`` (inside) to the prism's surface and the
        outward normal of the face met."""
        normals, offsets, _ = self.faces()
        along = d @ normals.T
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(along > 1e-12, (offsets - p @ normals.T) / along, np.inf)
        face = np.argmin(t, axis=1)
        return np.maximum(t[np.arange(len(p)), face], 0.0), normals[face]


@dataclass(frozen=True)
class Sphere:
    """A sphere of radius 1 (a water drop's geometry: :func:`trace` on it reproduces
    :func:`skydome.physics.sphere_optics.geometric_phase`)."""

    def projected_area(self, d: np.ndarray) -> np.ndarray:
        return np.full(len(d), math.pi)

    def entry(self, d: np.ndarray, u: np.ndarray):
        # impact parameter b = sqrt(u): even over the disk; the point on the lit hemisphere
        b = np.sqrt(u[:, 0])
        phi = u[:, 1] * 2.0 * math.pi
        helper = np.where(np.abs(d[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        e1 = np.cross(d, helper)
        e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
        e2 = np.cross(d, e1)
        across = e1 * (b * np.cos(phi))[:, None] + e2 * (b * np.sin(phi))[:, None]
        point = across - d * np.sqrt(np.maximum(1.0 - b * b, 0.0))[:, None]
        return point, point

    def exit(self, p: np.ndarray, d: np.ndarray):
        t = np.maximum(-2.0 * np.einsum("ij,ij->i", p, d), 0.0)
        q = p + d * t[:, None]
        return t, q / np.linalg.norm(q, axis=1, keepdims=True)


@dataclass(frozen=True)
class Traced:
    """What :func:`trace` found for N rays: the light leaving the body, as M rays
    (``directions`` (M, 3), ``weights`` (M,) of the ray's light, ``ray`` (M,) the index of
    the incident ray each came from, ``chords`` (M,) the internal paths each crossed: 0 for
    the external reflection), and per incident ray the light ``absorbed`` and the
    ``residual`` left inside when tracing stopped (N,)."""

    directions: np.ndarray
    weights: np.ndarray
    ray: np.ndarray
    chords: np.ndarray
    absorbed: np.ndarray
    residual: np.ndarray


def trace(body, directions, index, uniforms, *, absorption: float = 0.0,
          min_weight: float = 1e-7, max_chords: int = 60) -> Traced:  # fmt: skip
    """Trace rays travelling along ``directions`` (N, 3, unit, in the body's frame) into
    ``body`` (:class:`HexagonalPrism` or :class:`Sphere`) of refractive ``index`` (scalar or
    (N,)), unpolarised, entering where the uniform numbers ``uniforms`` (N, 4) in [0, 1)
    put them (evenly over its cross-section: rays sharing numbers and direction enter at the
    same point). ``absorption``: the ice's
    absorption coefficient times the body's unit length (its corner radius). Rays are
    followed until under ``min_weight`` of their light is inside, or ``max_chords``."""
    d = np.asarray(directions, dtype=float)
    n_rays = len(d)
    m = np.broadcast_to(np.asarray(index, dtype=float), (n_rays,)).copy()
    ray = np.arange(n_rays)
    p, normal = body.entry(d, np.asarray(uniforms, dtype=float))
    cos_i = -np.einsum("ij,ij->i", d, normal)
    r_s, r_p, cos_t = interface_reflectance(cos_i, m)
    out_dir = [d + 2.0 * cos_i[:, None] * normal]
    out_w = [0.5 * (r_s + r_p)]
    out_ray = [ray]
    out_chords = [np.zeros(n_rays, dtype=np.int32)]
    absorbed = np.zeros(n_rays)
    residual = np.zeros(n_rays)
    d = _refracted(d, normal, cos_i, cos_t, m)
    w_s, w_p = 0.5 * (1.0 - r_s), 0.5 * (1.0 - r_p)
    for chord in range(1, max_chords + 1):
        t, normal = body.exit(p, d)
        p = p + d * t[:, None]
        if absorption > 0.0:
            kept = np.exp(-absorption * t)
            np.add.at(absorbed, ray, (w_s + w_p) * (1.0 - kept))
            w_s, w_p = w_s * kept, w_p * kept
        cos_i = np.einsum("ij,ij->i", d, normal)
        r_s, r_p, cos_t = interface_reflectance(cos_i, 1.0 / m)
        leaving = w_s * (1.0 - r_s) + w_p * (1.0 - r_p)
        going = leaving > 0.0
        out_dir.append(_refracted(d, -normal, cos_i, cos_t, 1.0 / m)[going])
        out_w.append(leaving[going])
        out_ray.append(ray[going])
        out_chords.append(np.full(int(going.sum()), chord, dtype=np.int32))
        w_s, w_p = w_s * r_s, w_p * r_p
        d = d - 2.0 * cos_i[:, None] * normal
        alive = w_s + w_p >= min_weight
        if chord == max_chords:
            alive[:] = False
        np.add.at(residual, ray[~alive], (w_s + w_p)[~alive])
        if not alive.any():
            break
        d, p, m, ray, w_s, w_p = d[alive], p[alive], m[alive], ray[alive], w_s[alive], w_p[alive]
    return Traced(
        np.concatenate(out_dir), np.concatenate(out_w), np.concatenate(out_ray),
        np.concatenate(out_chords), absorbed, residual,
    )  # fmt: skip


# ---------------------------------------------------------------------------- orientations


@dataclass(frozen=True)
class Orientation:
    """How a population of crystals floats: ``kind`` "random" (every orientation equally),
    "plates" (the c-axis vertical: plates falling flat) or "columns" (the c-axis horizontal,
    at any azimuth and any rotation about it), its axis tilted from that by a Gaussian of
    ``tilt_deg`` (rms per direction)."""

    kind: str
    tilt_deg: float = 0.5

    def __post_init__(self):
        if self.kind not in ("random", "plates", "columns"):
            raise ParameterError(
                f"crystal orientation must be random, plates or columns, got {self.kind!r}"
            )
        if not 0.0 <= float(self.tilt_deg) <= 90.0:
            raise ParameterError(f"crystal tilt must be 0-90 deg, got {self.tilt_deg}")


def _rotation_z(angle):
    c, s = np.cos(angle), np.sin(angle)
    z, o = np.zeros_like(angle), np.ones_like(angle)
    return np.stack([np.stack([c, -s, z], -1), np.stack([s, c, z], -1),
                     np.stack([z, z, o], -1)], -2)  # fmt: skip


def _rotation_y(angle):
    c, s = np.cos(angle), np.sin(angle)
    z, o = np.zeros_like(angle), np.ones_like(angle)
    return np.stack([np.stack([c, z, s], -1), np.stack([z, o, z], -1),
                     np.stack([-s, z, c], -1)], -2)  # fmt: skip


def orientations(orientation: Orientation, count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` rotation matrices (count, 3, 3) taking a crystal's frame (c-axis z) to the
    sky's (x, y horizontal, z up) for ``orientation``."""
    if orientation.kind == "random":
        q = rng.normal(size=(count, 4))
        q /= np.linalg.norm(q, axis=1, keepdims=True)
        w, x, y, z = q.T
        return np.stack([
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ], -2)  # fmt: skip
    # the axis tilted by a 2D Gaussian (Rayleigh-distributed angle) towards a random azimuth
    tilt = np.radians(orientation.tilt_deg) * np.sqrt(-2.0 * np.log1p(-rng.random(count)))
    spin = rng.random(count) * 2.0 * math.pi  # about the c-axis
    azimuth = rng.random(count) * 2.0 * math.pi
    if orientation.kind == "plates":
        return _rotation_z(azimuth) @ _rotation_y(tilt) @ _rotation_z(spin)
    lean = rng.random(count) * 2.0 * math.pi  # which way the axis tilts off the horizontal
    horizontal = _rotation_y(np.full(count, math.pi / 2.0))  # the c-axis to x
    return (_rotation_z(azimuth) @ horizontal @ _rotation_z(lean) @ _rotation_y(tilt)
            @ _rotation_z(spin))  # fmt: skip


@dataclass(frozen=True)
class Scattered:
    """The light a population of crystals scatters, as seen by an observer: for each outgoing
    ray the direction it comes from (``elevation_deg``, ``azimuth_deg`` from the light's
    azimuth, -180 to 180), the index of its incident ray's wavelength in the caller's list
    (``wavelength``) and its ``weight`` (share of the population's scattered light: the weights
    add up to 1 per wavelength less what was absorbed and left inside)."""

    elevation_deg: np.ndarray
    azimuth_deg: np.ndarray
    wavelength: np.ndarray
    weight: np.ndarray


def scatter(body, orientation: Orientation, light_elevation_deg: float, wavelengths_nm,
            rays: int, seed: int = 0, *, index=None, min_weight: float = 1e-7) -> Scattered:  # fmt: skip
    """Monte Carlo scattering of light from ``light_elevation_deg`` (at azimuth 0) by crystals
    of shape ``body`` floating as ``orientation``: ``rays`` crystals and entry points, each
    traced at every one of ``wavelengths_nm`` (ice's index there unless ``index`` gives one
    per wavelength: the same rays in every colour, so that the colours differ by the
    dispersion and not by the sampling's noise), weighted by the crystal's cross-section
    along the light (a crystal presenting more area intercepts more)."""
    rng = np.random.default_rng(seed)
    wl = np.atleast_1d(np.asarray(wavelengths_nm, dtype=float))
    n = ice_index(wl) if index is None else np.atleast_1d(np.asarray(index, dtype=float))
    e = math.radians(light_elevation_deg)
    towards_light = np.array([math.cos(e), 0.0, math.sin(e)])
    rotation = orientations(orientation, rays, rng)
    incident = -np.einsum("nji,j->ni", rotation, towards_light)  # R^T (-s), the crystal's frame
    uniforms = rng.random((rays, 4))
    area = body.projected_area(incident)
    which = np.repeat(np.arange(wl.size), rays)  # wavelength-major copies of the rays
    traced = trace(body, np.tile(incident, (wl.size, 1)), n[which], np.tile(uniforms, (wl.size, 1)),
                   min_weight=min_weight)  # fmt: skip
    crystal = traced.ray % rays
    # back to the sky's frame; the observer sees the light from where it comes: -direction
    seen = -np.einsum("nij,nj->ni", rotation[crystal], traced.directions)
    weight = traced.weights * (area / area.mean())[crystal] / rays
    return Scattered(
        np.degrees(np.arcsin(np.clip(seen[:, 2], -1.0, 1.0))),
        np.degrees(np.arctan2(seen[:, 1], seen[:, 0])),
        which[traced.ray],
        weight,
    )
