"""Sky-view tables: the sky from one camera position tabulated by view direction, per light.

A frame then costs two bilinear fetches per pixel and light instead of six fetches from the
4D tables (and the ground's spectral lighting). The tables hold phase-free values, so the
phase functions are still evaluated exactly per pixel (shaders/atmosphere/sky_view_mapping.glsl).
Aerial-perspective tables add the distance along each ray as a third coordinate, for frames
with a depth image (two trilinear fetches per pixel instead of two 4D lookups and more).
All are kept between frames and redrawn only when the camera altitude or a light's
direction changes: turning the camera costs one frame pass.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from skydome.atmosphere.inputs import LookupInputs
from skydome.core.services import AerialInputs
from skydome.errors import ParameterError
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.textures import copy_array_to_3d, linear_clamped, release_all, release_unbound

#: Default table size (azimuth from the light over [0, 180] deg, elevation), texels.
DEFAULT_SKY_VIEW_SIZE = (256, 256)
#: Aerial-perspective tables (azimuth, elevation, distance), texels: 6.3 MB per light. 128
#: elevations: with 64, in dense haze the light scattered in front of a target near the
#: horizon missed the sky beside it by ~1 % of it (Koschmieder's 2 % contrast read 0.8-3.9 %;
#: tests/test_atmosphere_knobs.py); 48 distances (were 64) keep the redraw at 64 ms on
#: llvmpipe (49 ms before; 79 ms with 64), within the same accuracy against the 4D tables.
AERIAL_SIZE = (32, 128, 48)


#: A light's sky-view table is kept for a new instant while the light's elevation moved by
#: at most REAIM_HIGH_DEG with the light at or above REAIM_HIGH_ABOVE_DEG at both instants,
#: REAIM_LOW_DEG otherwise; a move in azimuth alone never re-aims (the tables are by the
#: azimuth *from* the light). Measured, `earth`, the sky above the horizon of a table kept
#: vs one re-aimed (max relative difference): 0.1 deg at 20 deg 0.28 %, at 30 deg 0.16 %,
#: at 60 deg 0.11 %; 0.002 deg in twilight (-6 to -4 deg, where the sky changes fastest,
#: ~1.3 % per 0.01 deg) <= 0.3 %, at 5 deg 0.07 %. In table texels of 128 (256) azimuths:
#: 0.07 (0.14) and 0.0014 (0.0028). A Moon high in the sky, a Sun near noon: most frames
#: of a viewer whose time runs keep their tables.
REAIM_HIGH_DEG = 0.1
REAIM_HIGH_ABOVE_DEG = 20.0
REAIM_LOW_DEG = 0.002


def _elevation_deg(direction: tuple[float, float, float]) -> float:
    """Elevation (deg) of an ENU direction."""
    x, y, z = direction
    return math.degrees(math.atan2(z, math.hypot(x, y)))


def check_sky_view_size(size) -> tuple[int, int]:
    """(azimuth, elevation) texels of sky-view tables: at least 2, and an even elevation
    count of at least 4 (two halves)."""
    try:
        w, h = (int(v) for v in size)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(f"sky-view size must be two integers, got {size!r}") from None
    if w < 2 or h < 4 or h % 2:
        raise ParameterError(f"sky-view size must be (>= 2, even >= 4) texels, got {size}")
    return w, h


@dataclass(frozen=True)
class SkyViewTableInputs(ShaderInputs):
    """``atmosphere/sky_view_mapping.glsl`` and the table passes: the sky-view tables' size,
    the camera's radius (km), the aerial tables' size, the light a table is drawn for."""

    u_sky_view_size: tuple[float, float]
    u_view_radius: float
    u_aerial_size: tuple[float, float, float]
    u_light_direction: tuple[float, float, float]


class SkyViewTables:
    """Sky-view tables of a precomputed atmosphere, one pair of textures per light slot.

    Args:
        ctx: the moderngl context of the atmosphere tables.
        defines: the lookup shader's defines (``PrecomputedAtmosphere.defines()``).
        size: (azimuth, elevation) texels; the elevation count must be even (two halves).
    """

    def __init__(
        self, ctx, defines: dict[str, object], size: tuple[int, int] = DEFAULT_SKY_VIEW_SIZE
    ):
        w, h = check_sky_view_size(size)
        self.ctx = ctx
        self.size = (w, h)
        inputs = (LookupInputs, SkyViewTableInputs)
        lut = "atmosphere/sky_view_lut.glsl"
        self._passes = (
            FullscreenPass(ctx, lut, defines, inputs=inputs),  # the upper half: sky
            FullscreenPass(ctx, lut, {**defines, "GROUND_HALF": 1}, inputs=inputs),
        )
        self._defines = defines
        self._aerial_pass = None  # compiled on first use
        self._slots: dict[str, tuple[list, object, tuple | None]] = {}
        self.draws = 0  # table passes drawn (a cache-hit counter for tests and benchmarks)

    def mapping(self, radius_km: float, light_direction=(0.0, 0.0, 1.0)) -> SkyViewTableInputs:
        """The tables' mappings for a camera at ``radius_km`` from the planet's centre (and
        the light a table pass draws for)."""
        return SkyViewTableInputs(
            u_sky_view_size=tuple(float(v) for v in self.size),
            u_view_radius=float(radius_km),
            u_aerial_size=tuple(float(v) for v in AERIAL_SIZE),
            u_light_direction=tuple(float(v) for v in light_direction),
        )

    def aerial(self, radius_km: float, lights, lookup: ShaderInputs) -> AerialInputs:
        """The aerial-perspective tables of the Sun and (when it lights the air) the second
        light of ``lights`` (``AirLights``) from ``radius_km``, redrawn if stale."""
        sun = self.aerial_textures("sun", radius_km, lights.sun_direction, lookup)
        moon = (None, None)
        if lights.has_moon:
            moon = self.aerial_textures("light2", radius_km, lights.moon_direction, lookup)
        m = self.mapping(radius_km)
        return AerialInputs(m.u_sky_view_size, m.u_view_radius, m.u_aerial_size, *sun, *moon)

    def textures(
        self,
        slot: str,
        radius_km: float,
        light_direction: tuple[float, float, float],
        lookup: ShaderInputs,
    ) -> tuple[object, object]:
        """The (scattering, single Mie) textures of light ``slot`` ("sun" or "light2"),
        redrawn if stale. ``lookup`` holds the atmosphere tables (they do not change for
        one set of tables, so only the radius and the direction decide whether to redraw).
        """
        light = tuple(float(v) for v in light_direction)
        key = (float(radius_km), light)
        if slot not in self._slots:
            texs = [
                linear_clamped(self.ctx.texture(self.size, 4, dtype="f4"), self.ctx)
                for _ in range(2)
            ]
            self._slots[slot] = (texs, self.ctx.framebuffer(color_attachments=texs), None)
        texs, fbo, drawn = self._slots[slot]
        if not self.still_aimed(drawn, key):
            w, h = self.size
            mapping = self.mapping(key[0], key[1])
            for half, fpass in zip((1, 0), self._passes, strict=True):
                fbo.viewport = (0, half * h // 2, w, h // 2)
                fpass.draw(fbo, lookup, mapping)
            self._slots[slot] = (texs, fbo, key)
            self.draws += 1
        return texs[0], texs[1]

    def still_aimed(self, drawn: tuple | None, key: tuple) -> bool:
        """Whether a table drawn for ``drawn`` = (radius km, light direction) serves ``key``:
        the same radius and a light whose elevation moved by at most REAIM_HIGH_DEG or
        REAIM_LOW_DEG (see there). The tables hold the sky by the azimuth *from* the light
        over a spherically symmetric planet (sky_view_mapping.glsl; the ground is uniform),
        so a light that turned in azimuth alone needs no new table at all."""
        if drawn is None or drawn[0] != key[0]:
            return False
        if drawn[1] == key[1]:
            return True
        a, b = _elevation_deg(drawn[1]), _elevation_deg(key[1])
        high = min(a, b) >= REAIM_HIGH_ABOVE_DEG
        return abs(a - b) <= (REAIM_HIGH_DEG if high else REAIM_LOW_DEG)

    def aerial_textures(
        self,
        slot: str,
        radius_km: float,
        light_direction: tuple[float, float, float],
        lookup: ShaderInputs,
    ) -> tuple[object, object]:
        """Sampler name -> 3D texture of light ``slot``'s aerial-perspective tables, redrawn if
        stale: drawn into texture arrays (one layer per distance), copied on the GPU into
        linearly filtered 3D textures, and the arrays released (6.3 MB kept per light)."""
        key = (float(radius_km), tuple(float(v) for v in light_direction))
        name = f"{slot}_aerial"
        w, h, d = AERIAL_SIZE
        if name not in self._slots:
            volumes = [
                linear_clamped(self.ctx.texture3d((w, h, d), 4, dtype="f4"), self.ctx)
                for _ in range(2)
            ]
            self._slots[name] = (volumes, None, None)
        volumes, _, drawn = self._slots[name]
        if drawn != key:
            if self._aerial_pass is None:
                self._aerial_pass = FullscreenPass(
                    self.ctx, "atmosphere/aerial_view_lut.glsl", self._defines,
                    inputs=(LookupInputs, SkyViewTableInputs), layered=True,
                )  # fmt: skip
            layers = [self.ctx.texture_array((w, h, d), 4, dtype="f4") for _ in range(2)]
            fbo = self.ctx.framebuffer(color_attachments=layers)
            try:
                fbo.viewport = (0, 0, w, h)
                self._aerial_pass.draw(fbo, lookup, self.mapping(key[0], key[1]), layers=(0, d))
                for array, volume in zip(layers, volumes, strict=True):
                    copy_array_to_3d(self.ctx, array, volume)
            finally:
                for obj in (fbo, *layers):
                    release_unbound(obj)
            self._slots[name] = (volumes, None, key)
            self.draws += 1
        return volumes[0], volumes[1]

    def release(self) -> None:
        for texs, fbo, _ in self._slots.values():
            release_all(fbo, *texs)
        self._slots.clear()
        for fpass in (*self._passes, self._aerial_pass):
            if fpass is not None:
                fpass.release()
