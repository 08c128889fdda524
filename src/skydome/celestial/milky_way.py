"""The Milky Way layer: the diffuse light of the Galaxy beyond the atmosphere.

Map
---
``skydome/data/milky_way.npz``, built by ``tools/build_milky_way.py`` from ESA's Gaia EDR3
all-sky map ((c) ESA/Gaia/DPAC, CC BY-SA 3.0 IGO; see ``milky_way.txt``): the light of all
stars and of the diffuse galactic light, with the catalogue's own stars
(skydome.astro.stars.catalog(), drawn as points by the stars layer) removed, calibrated in S10
(one V = 10 star per square degree) so that map + catalogue stars give the published totals:
31 S10 at the galactic poles (Pioneer 10, Leinert et al. 1998 Table 34) and 100 S10 averaged
over the sky (Roach & Gordon 1973). Grid: equirectangular in galactic coordinates, column i
centred on l = 180 - 360 (i + 0.5) / W deg (l increases to the left), row j on
b = 90 - 180 (j + 0.5) / H deg.

Luminance
---------
S10 become cd/m^2 through the issue's conversion L = 10.8e4 10^(-0.4 m) cd/m^2 for m in V
mag/arcsec^2, with 1 S10 = 27.78 mag/arcsec^2 (:data:`S10_CD_M2` = 8.33e-7 cd/m^2).

Colour
------
The light's spectral shape is a Planck spectrum at 4840 K, the colour temperature of the
Milky Way's integrated light (Licquia, Newman & Brinchmann 2015, ApJ 809, 96, from Milky Way
analogue galaxies; B-V = 0.96 by Ballesteros 2012's relation), through the frame's spectral
basis. The map's own colour is not used (luminance only).

Orientation
-----------
Galactic -> ICRS: the IAU 1958 system as realised in the ICRS (Hipparcos vol. 1 sec. 1.5.3;
pole RA 192.85948, Dec 27.12825 deg, l of the NCP 122.93192 deg). ICRS -> true equator and
equinox of date: precession (IAU 2006) and nutation (IAU 1980), skydome.astro.frames, the
chain the star catalogue uses (frame bias < 0.02" neglected). -> ENU with the local apparent
sidereal time (skydome.astro.time.gast + east longitude). Annual aberration (<= 20.5") is left
out: the map's pixels are 0.18 deg. The shader gets one mat3 (ENU -> galactic) per update
and looks up each pixel's airless direction (refraction from a table over the sine of the
apparent elevation, skydome.physics.refraction).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from skydome.astro import frames, photometry
from skydome.astro.time import gast, to_time
from skydome.core.cameras import CameraInputs
from skydome.core.layer import DrawContext, Layer
from skydome.core.lights import SkyState
from skydome.core.refraction_table import AirlessTableInputs, RefractionTable
from skydome.errors import ParameterError
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.shared import SharedResource
from skydome.io.packaged import read_packaged_npz
from skydome.physics.packing import mat3
from skydome.spectra.blackbody import planck_relative
from skydome.spectra.tables import solar_irradiance

__all__ = [
    "S10_MAG_ARCSEC2",
    "S10_CD_M2",
    "COLOUR_TEMPERATURE_K",
    "MilkyWayLayer",
    "milky_way_map",
    "milky_way_meta",
    "galactic_to_icrs_matrix",
    "enu_to_galactic_matrix",
    "luminance_galactic",
    "luminance_enu",
    "spectral_shape",
]

#: Surface brightness of 1 S10 (one V = 10 star per square degree), V mag/arcsec^2.
S10_MAG_ARCSEC2 = photometry.S10_MAG_ARCSEC2
#: Luminance of 1 S10, cd/m^2, by the issue's conversion L = 10.8e4 10^(-0.4 m) cd/m^2.
S10_CD_M2 = float(photometry.s10_to_luminance(1.0))
#: Colour temperature of the Galaxy's integrated light (Licquia, Newman & Brinchmann 2015).
COLOUR_TEMPERATURE_K = 4840.0

# IAU 1958 galactic system in the ICRS (Hipparcos vol. 1 sec. 1.5.3), degrees.
NGP_RA_DEG, NGP_DEC_DEG, L_NCP_DEG = 192.85948, 27.12825, 122.93192

_MAP_FILE = "milky_way.npz"
_FORMAT_VERSION = 1


@functools.cache
def _map_and_meta() -> tuple[np.ndarray, dict]:
    q, meta = read_packaged_npz(
        _MAP_FILE, "s10_u16", _FORMAT_VERSION, "Milky Way map", "tools/build_milky_way.py"
    )
    lo, hi = meta["log10_s10_min"], meta["log10_s10_max"]
    s10 = 10.0 ** (lo + q.astype(np.float64) * ((hi - lo) / 65535.0))
    s10 = np.ascontiguousarray(s10.astype(np.float32))
    s10.setflags(write=False)
    return s10, meta


def milky_way_map() -> np.ndarray:
    """The map (H, W) float32, S10, read-only (grid in the module docstring)."""
    return _map_and_meta()[0]


def milky_way_meta() -> dict:
    """The map's metadata: source, calibration constants and statistics."""
    return dict(_map_and_meta()[1])


@functools.cache
def _galactic_to_icrs() -> np.ndarray:
    a, d = math.radians(NGP_RA_DEG), math.radians(NGP_DEC_DEG)
    z = np.array([math.cos(d) * math.cos(a), math.cos(d) * math.sin(a), math.sin(d)])
    ncp = np.array([0.0, 0.0, 1.0])
    in_plane = ncp - (ncp @ z) * z  # the NCP's direction projected on the galactic plane
    in_plane /= np.linalg.norm(in_plane)  # at galactic longitude L_NCP
    ahead = np.cross(z, in_plane)  # at L_NCP + 90 deg
    lam = math.radians(L_NCP_DEG)
    x = math.cos(lam) * in_plane - math.sin(lam) * ahead  # l = 0
    y = np.cross(z, x)  # l = 90 deg
    m = np.stack([x, y, z], axis=1)  # columns: the galactic axes in ICRS
    m.setflags(write=False)
    return m


def galactic_to_icrs_matrix() -> np.ndarray:
    """3x3 rotation taking galactic unit vectors to ICRS ones (columns: the galactic x, y, z
    axes, i.e. (l, b) = (0, 0), (90, 0) deg and the north galactic pole, in ICRS)."""
    return _galactic_to_icrs().copy()


def _unit(lon_rad, lat_rad) -> np.ndarray:
    lon, lat = np.broadcast_arrays(np.asarray(lon_rad, float), np.asarray(lat_rad, float))
    c = np.cos(lat)
    return np.stack([c * np.cos(lon), c * np.sin(lon), np.sin(lat)], axis=-1)


def enu_to_galactic_matrix(observer, time) -> np.ndarray:
    """3x3 rotation taking airless ENU directions of ``observer`` (skydome.astro.Observer) at
    one ``time`` (a skydome.astro Time or anything to_time takes) to galactic unit vectors."""

    t = to_time(time)
    if t.shape != ():
        raise ParameterError(f"one instant is needed; got times of shape {t.shape}")
    jd_tt, jd_ut1 = float(t.jd_tt), float(t.jd_ut1)
    return _enu_from_galactic(jd_tt, jd_ut1, observer).T


def _enu_from_galactic(jd_tt: float, jd_ut1: float, observer, np_matrix=None) -> np.ndarray:

    if np_matrix is None:
        np_matrix = np.asarray(frames.nutation_matrix(jd_tt) @ frames.precession_matrix(jd_tt))
    lat = math.radians(float(observer.latitude))
    lst = float(gast(jd_ut1, jd_tt)) + math.radians(float(observer.longitude))
    enu = np.asarray(frames.equatorial_to_enu_matrix(lst, lat))
    return enu @ np_matrix.reshape(3, 3) @ _galactic_to_icrs()


def _texcoords(lon_rad, lat_rad, width: int, height: int):
    """Texel-space coordinates (u, v) of the map (texel centres at integers)."""
    s = np.mod(0.5 - np.asarray(lon_rad, float) / (2.0 * math.pi), 1.0)
    t = 0.5 - np.asarray(lat_rad, float) / math.pi
    return s * width - 0.5, t * height - 0.5


def luminance_galactic(lon_rad, lat_rad, *, scale: float = 1.0) -> np.ndarray:
    """Luminance (cd/m^2, float64) of the map at galactic longitude and latitude (rad),
    bilinear between texel centres, wrapping in l and clamping at the poles: the float64
    twin of the shader's base-level texture lookup."""
    m = milky_way_map().astype(np.float64)
    h, w = m.shape
    u, v = _texcoords(lon_rad, lat_rad, w, h)
    i0, j0 = np.floor(u), np.floor(v)
    fu, fv = u - i0, v - j0
    i0 = i0.astype(int)
    j0 = j0.astype(int)
    i1 = np.mod(i0 + 1, w)
    i0 = np.mod(i0, w)
    j1 = np.clip(j0 + 1, 0, h - 1)
    j0 = np.clip(j0, 0, h - 1)
    top = m[j0, i0] * (1.0 - fu) + m[j0, i1] * fu
    bottom = m[j1, i0] * (1.0 - fu) + m[j1, i1] * fu
    return (top * (1.0 - fv) + bottom * fv) * (S10_CD_M2 * float(scale))


def luminance_enu(directions, observer, time, *, scale: float = 1.0) -> np.ndarray:
    """Luminance (cd/m^2) of the map towards airless ENU ``directions`` (..., 3) seen by
    ``observer`` at ``time`` (one instant)."""
    d = np.asarray(directions, dtype=np.float64)
    d = d / np.linalg.norm(d, axis=-1, keepdims=True)
    g = d @ enu_to_galactic_matrix(observer, time).T
    lon = np.arctan2(g[..., 1], g[..., 0])
    lat = np.arctan2(g[..., 2], np.hypot(g[..., 0], g[..., 1]))
    return luminance_galactic(lon, lat, scale=scale)


def spectral_shape(wavelengths_nm) -> np.ndarray:
    """Relative spectral radiance of the Galaxy's light: a Planck spectrum at
    COLOUR_TEMPERATURE_K, 1 at 550 nm."""
    wl = np.asarray(wavelengths_nm, dtype=np.float64)
    shape = planck_relative(wl, COLOUR_TEMPERATURE_K)[:, 0].reshape(wl.shape)
    return shape / planck_relative(550.0, COLOUR_TEMPERATURE_K)[0, 0]


@dataclass(frozen=True)
class MilkyWayInputs(ShaderInputs):
    """``celestial/milky_way.glsl``: the ENU -> galactic matrix (column-major), the map's
    colour per S10, its texels per radian (log2, for the level of detail), the map."""

    u_enu_to_galactic: tuple[float, ...]
    u_colour: tuple[float, float, float, float]
    u_log2_texels_per_rad: float
    u_milky_way: object


class MilkyWayLayer(Layer):
    """The Milky Way's diffuse light (space stage). ``scale`` multiplies its brightness
    (1 = the calibrated map; 0 to 100)."""

    name = "milky_way"
    #: No detail below a texel of the 2048-px map (0.176 deg): the frame graph may draw it
    #: at 1/f the resolution when the camera's pixels are f times finer (scene.graph).
    smooth_deg = 0.18
    stage = "space"
    shader = "celestial/milky_way.glsl"

    def __init__(self, *, scale: float = 1.0, enabled: bool = True):
        super().__init__(enabled=enabled)
        scale = float(scale)
        if not (0.0 <= scale <= 100.0):
            raise ParameterError(f"Milky Way scale = {scale!r} must lie in [0, 100]")
        self.scale = scale
        self._texture = None
        self._holder: SharedResource | None = None  # the texture, shared with fresh() copies
        self._donor: SharedResource | None = None
        self._inputs: MilkyWayInputs | None = None
        self._key = None
        self._np_cache: tuple[int, np.ndarray] | None = None
        self._colour = None
        self._info: dict = {}
        self._refraction = 0.0
        self._refraction_table = RefractionTable()
        self._log2_texels_per_rad = 0.0

    def prepare(self, graph) -> None:
        super().prepare(graph)
        ctx = graph.ctx
        m = milky_way_map()
        h, w = m.shape
        donor, self._donor = self._donor, None
        if donor is not None and donor.serves(ctx):  # Sky.at: the map of the sky it came from
            self._holder, self._texture = donor, donor.take()
        else:
            self._texture = ctx.texture((w, h), 1, np.ascontiguousarray(m).tobytes(), dtype="f4")
            self._texture.build_mipmaps()
            self._texture.filter = (ctx.LINEAR_MIPMAP_LINEAR, ctx.LINEAR)
            self._texture.repeat_x, self._texture.repeat_y = True, False
            self._holder = SharedResource(self._texture, ctx)
        self._log2_texels_per_rad = math.log2(w / (2.0 * math.pi))

    def fresh(self) -> MilkyWayLayer:
        """A new layer with this one's arguments that, prepared on the same context, shares
        this one's map texture (uploaded and mipmapped once for a sky and its ``Sky.at``
        copies; freed with the last of them) and its precession-nutation of the day."""
        layer = super().fresh()
        layer._donor = self._holder
        layer._np_cache = self._np_cache
        return layer

    def update(self, state: SkyState) -> None:
        key = (id(state), id(self.graph.basis), self.scale)
        if key == self._key:
            return
        self._key = key
        if state.observer is None or state.time is None:
            self._inputs, self._info = None, {}
            return
        jd_tt, jd_ut1 = float(state.time.jd_tt), float(state.time.jd_ut1)
        # Precession-nutation moves the map by < 0.2" a day: computed once per day (TT).
        day = math.floor(jd_tt)
        if self._np_cache is None or self._np_cache[0] != day:
            self._np_cache = (
                day,
                np.asarray(frames.nutation_matrix(day) @ frames.precession_matrix(day)),
            )
        enu_from_gal = _enu_from_galactic(jd_tt, jd_ut1, state.observer, self._np_cache[1])
        gal_from_enu = enu_from_gal.T
        basis = self.graph.basis
        if self._colour is None or self._colour[0] is not basis:
            wl = basis.wavelengths_nm
            self._colour = (basis, basis.colour(spectral_shape(wl) / solar_irradiance(wl)))
        self._inputs = MilkyWayInputs(
            u_enu_to_galactic=mat3(gal_from_enu),
            u_colour=tuple(float(v) for v in self._colour[1] * (S10_CD_M2 * self.scale)),
            u_log2_texels_per_rad=self._log2_texels_per_rad,
            u_milky_way=self._texture,
        )
        self._refraction = state.refraction_scale
        gc = enu_from_gal[:, 0]
        self._info = {
            "milky_way_centre_elevation_deg": math.degrees(math.asin(max(-1.0, min(1.0, gc[2])))),
            "milky_way_centre_azimuth_deg": math.degrees(math.atan2(gc[0], gc[1])) % 360.0,
        }

    def draw(self, frame: DrawContext) -> None:
        if self._inputs is None or self.scale == 0.0:
            return
        fpass = self.full_screen_pass(
            frame.ctx, self.shader, (CameraInputs, MilkyWayInputs, AirlessTableInputs),
            frame.camera,
        )  # fmt: skip
        airless = self._refraction_table.inputs(frame.ctx, self._refraction)
        fpass.draw(frame.fbo, frame.view, self._inputs, airless)

    def info(self) -> dict:
        return dict(self._info)

    def release(self) -> None:
        super().release()
        if self._holder is not None:
            self._holder.drop()
        self._holder = self._texture = None
        self._refraction_table.release()
