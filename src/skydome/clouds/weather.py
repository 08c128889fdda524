"""Weather maps for volumetric clouds: where clouds are, of which type, raining, and cirrus.

A :class:`WeatherMap` is an (H, W, 4) float32 array over a square tile of ``tile_km`` km
that repeats in both directions. Channels, all in [0, 1]:

- R: coverage (0 clear, 1 overcast);
- G: cloud type (0 stratus, 1/3 stratocumulus, 2/3 cumulus, 1 cumulonimbus; the cloud layer
  interpolates its height profiles by it);
- B: precipitation;
- A: cirrus coverage (a thin high sheet).

Rows run south to north and columns west to east: texel [j, i] covers east
x = (i + 0.5) / W * tile and north y = (j + 0.5) / H * tile, the way an OpenGL texture
stores them (texture coordinate s east, t north). Images are the other way up (their first
row is the north edge) and are flipped on reading.

:class:`AnimatedWeather` draws the map at a time (``shaders/clouds/weather_animate.glsl``):
moved by the wind, advected by a divergence-free flow (the curl noise of
:mod:`skydome.clouds.noise`) with a flow-map scheme, and evolving slowly; every frame is a
pure function of its time.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import moderngl
import numpy as np

from skydome.clouds import lattice_noise
from skydome.clouds.noise import check_seed, render_curl
from skydome.errors import ParameterError, check_range
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.io.images import read_user_image

#: Default tile of a generated map (km): 32 km at 512 texels is 62.5 m per texel.
DEFAULT_TILE_KM = 32.0
#: Largest weather-map image read, pixels a side: the largest map ``generate`` makes. Over
#: the CLI's 40 km tile that is ~10 m a texel; the map is a 64 MiB RGBA8 texture on the GPU
#: and about 0.6 GB on the host while it is read (float32 copies). A bigger file is refused
#: from its header, before any pixel is decoded.
MAX_IMAGE_SIDE = 4096
#: Largest weather-map file read, bytes: MAX_IMAGE_SIDE^2 pixels of 16-bit RGBA (8 bytes,
#: the widest pixel PNG/TIFF hold here) stored without compression, plus 16 MiB of headers.
MAX_IMAGE_BYTES = MAX_IMAGE_SIDE**2 * 8 + 16 * 2**20
#: Cloud type values of the four named types (G channel).
CLOUD_TYPES = {"stratus": 0.0, "stratocumulus": 1 / 3, "cumulus": 2 / 3, "cumulonimbus": 1.0}

# Generation: the soft edge of the coverage (width of the ramp from 0 to 1 in the raw
# field) and of the cirrus sheet.
_EDGE = 0.25
_CIRRUS_EDGE = 0.3
# The flow map's z-period of the evolution noise, as in weather_animate.glsl.
_EVOLUTION_Z_PERIOD = 256.0


def _check_tile(tile_km) -> float:
    try:
        t = float(tile_km)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(f"tile_km must be a number, got {tile_km!r}") from None
    if not (math.isfinite(t) and t > 0):
        raise ParameterError(f"tile_km = {tile_km} must be a finite number of km > 0")
    return t


def _fraction(name: str, value) -> float:
    return check_range(name, value, 0.0, 1.0)


@dataclass(frozen=True, eq=False)
class WeatherMap:
    """A repeating weather map (see the module docstring for channels and orientation).

    Attributes:
        data: (H, W, 4) float32, values in [0, 1].
        tile_km: side of the square tile it covers, km.
    """

    data: np.ndarray
    tile_km: float

    def __post_init__(self):
        _check_tile(self.tile_km)
        a = self.data
        if not (isinstance(a, np.ndarray) and a.ndim == 3 and a.shape[2] == 4):
            raise ParameterError("WeatherMap data must be an (H, W, 4) array")

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) in texels."""
        return self.data.shape[1], self.data.shape[0]

    @property
    def coverage(self) -> np.ndarray:
        return self.data[..., 0]

    @property
    def cloud_type(self) -> np.ndarray:
        return self.data[..., 1]

    @property
    def precipitation(self) -> np.ndarray:
        return self.data[..., 2]

    @property
    def cirrus(self) -> np.ndarray:
        return self.data[..., 3]

    @classmethod
    def from_array(cls, array, tile_km: float, *, cloud_type: float = 2 / 3) -> WeatherMap:
        """A map from an array: (H, W) or (H, W, 1) coverage, (H, W, 2) coverage and type,
        (H, W, 3) plus precipitation, or (H, W, 4) all channels; values in [0, 1], rows south
        to north. Missing channels: type ``cloud_type``, no precipitation, no cirrus."""
        tile_km = _check_tile(tile_km)
        cloud_type = _fraction("cloud_type", cloud_type)
        try:
            a = np.asarray(array)
            if a.dtype != np.float32:  # float32 is kept (half the memory of a big map)
                a = a.astype(np.float64)
        except (TypeError, ValueError, OverflowError):
            raise ParameterError("a weather map must be a numeric array") from None
        if a.ndim == 2:
            a = a[..., None]
        if a.ndim != 3 or not 1 <= a.shape[2] <= 4 or min(a.shape[:2]) < 2:
            raise ParameterError(
                f"a weather map must have shape (H, W) or (H, W, 1-4) with H, W >= 2, "
                f"got {np.shape(array)}"
            )
        if not np.isfinite(a).all():
            raise ParameterError("a weather map contains NaN or infinite values")
        lo, hi = float(a.min()), float(a.max())
        if lo < 0.0 or hi > 1.0:
            raise ParameterError(
                f"weather map values must lie in [0, 1], got values from {lo:g} to {hi:g}"
            )
        h, w, c = a.shape
        data = np.zeros((h, w, 4), dtype=np.float32)
        data[..., 1] = cloud_type
        data[..., :c] = a
        return cls(data, tile_km)

    @classmethod
    def from_image(cls, path: str | os.PathLike, tile_km: float) -> WeatherMap:
        """A map from a PNG, JPEG or TIFF file (the first row is the north edge): RGBA gives
        all channels, RGB the first three (no cirrus), greyscale the coverage (cumulus type);
        8-bit values are divided by 255, 16-bit by 65535, float images are taken as they are.

        The file is opened with :func:`skydome.io.images.read_user_image`: a regular file of
        at most :data:`MAX_IMAGE_SIDE` pixels a side (and :data:`MAX_IMAGE_BYTES`), checked
        from its header before decoding. Anything else (a FIFO, a directory, a text file, a
        truncated image, a decompression bomb) raises ParameterError naming the file.
        """

        tile_km = _check_tile(tile_km)
        img = read_user_image(
            path,
            what="weather map image",
            max_pixels=MAX_IMAGE_SIDE**2,
            max_side=MAX_IMAGE_SIDE,
            max_bytes=MAX_IMAGE_BYTES,
        )
        with img:
            # float32 (not float64): a 4096^2 RGBA map is 256 MiB as it is
            mode = img.mode
            f4 = np.float32
            if mode in ("I;16", "I;16B", "I;16L", "I"):
                a = np.asarray(img, dtype=f4) / f4(65535.0)
            elif mode == "F":
                a = np.asarray(img, dtype=f4)
            elif mode in ("L", "1"):
                a = np.asarray(img.convert("L"), dtype=f4) / f4(255.0)
            elif mode in ("RGB", "RGBA"):
                a = np.asarray(img, dtype=f4) / f4(255.0)
            elif mode == "LA":
                a = np.asarray(img, dtype=f4)[..., 0] / f4(255.0)
            else:  # palette, CMYK, ...
                a = np.asarray(img.convert("RGBA"), dtype=f4) / f4(255.0)
        return cls.from_array(a[::-1], tile_km)

    @classmethod
    def generate(
        cls,
        seed: int = 1,
        *,
        tile_km: float = DEFAULT_TILE_KM,
        size: int = 512,
        coverage: float = 0.5,
        cloud_type: float = 2 / 3,
        precipitation: float = 0.0,
        cirrus: float = 0.0,
        clouds: int = 48,
        cloud_size: tuple[float, float] = (0.04, 0.12),
    ) -> WeatherMap:
        """A random seamless map, after the generator of seed 000 (ch. 5.3): ``clouds``
        ellipses with semi-major axes between ``cloud_size`` (fractions of the tile), random
        aspect and orientation, each filled with tileable noise that fades towards its edge,
        placed with wrap-around so the map repeats (the instanced copies of the original).
        Adapted so that the mean of R equals ``coverage``: the field (ellipses over a faint
        noise background, which fills the gaps at high coverage) is remapped through a soft
        threshold chosen by bisection; ``coverage=0`` gives R = 0 everywhere, 1 gives 1.
        G = ``cloud_type``; B = ``precipitation`` * R; A = a streaky noise sheet thresholded
        the same way to a mean of ``cirrus``.

        The generation is NumPy, not GLSL: a weather map is host data made once per seed and
        parameters (512^2 in 2 s on 2 CPU cores), and the threshold is a global search over the
        whole array. Its noise is the float64 twin of the shaders' (same hash and lattice).
        """
        seed = check_seed(seed)
        tile_km = _check_tile(tile_km)
        if isinstance(size, bool) or not isinstance(size, (int, np.integer)):
            raise ParameterError(f"size must be an integer, got {size!r}")
        if not 8 <= int(size) <= 4096:
            raise ParameterError(f"size = {size} is outside the valid range [8, 4096] texels")
        size = int(size)
        coverage = _fraction("coverage", coverage)
        cloud_type = _fraction("cloud_type", cloud_type)
        precipitation = _fraction("precipitation", precipitation)
        cirrus = _fraction("cirrus", cirrus)
        if isinstance(clouds, bool) or not isinstance(clouds, (int, np.integer)) or clouds < 0:
            raise ParameterError(f"clouds must be an integer >= 0, got {clouds!r}")
        try:
            lo, hi = (float(v) for v in cloud_size)
        except (TypeError, ValueError, OverflowError):
            raise ParameterError(
                f"cloud_size must be two numbers (min, max), fractions of the tile in "
                f"(0, 0.5], got {cloud_size!r}"
            ) from None
        if not 0 < lo <= hi <= 0.5:
            raise ParameterError(f"cloud_size must satisfy 0 < min <= max <= 0.5, got {cloud_size}")

        c = (np.arange(size) + 0.5) / size
        x, y = np.meshgrid(c, c)  # [j, i]: y north (rows), x east (columns)
        u3 = np.stack([x, y, np.zeros_like(x)], axis=-1)
        texture = 0.5 + lattice_noise.perlin_fbm(
            u3, 8, 4, seed, 200
        )  # inside the clouds, ~[0.1, 0.9]
        background = np.clip(0.5 + 1.5 * lattice_noise.perlin_fbm(u3, 4, 4, seed, 210), 0.0, 1.0)

        rng = np.random.default_rng([seed, 0x57EA])
        field = 0.45 * background
        for _ in range(int(clouds)):
            cx, cy = rng.random(2)
            a = rng.uniform(lo, hi)
            b = a * rng.uniform(0.5, 1.0)
            angle = rng.uniform(0.0, math.pi)
            dx = (x - cx + 0.5) % 1.0 - 0.5  # the nearest copy of the ellipse (wrap-around)
            dy = (y - cy + 0.5) % 1.0 - 0.5
            along = dx * math.cos(angle) + dy * math.sin(angle)
            across = -dx * math.sin(angle) + dy * math.cos(angle)
            r = np.sqrt((along / a) ** 2 + (across / b) ** 2)
            # The noise frays the outline and shades the inside; 0 beyond the ellipse.
            fade = 1.0 - _smoothstep(0.3, 1.0, r + 0.8 * (0.5 - texture))
            field = np.maximum(field, fade * (0.2 + 0.8 * texture) * (r < 1.0))

        data = np.zeros((size, size, 4), dtype=np.float32)
        data[..., 0] = _threshold_to_mean(field, coverage, _EDGE)
        data[..., 1] = cloud_type
        data[..., 2] = precipitation * data[..., 0]
        if cirrus > 0:
            # Streaks: the noise stretched 4:1 along x (periods 2 and 8 cells per tile).
            p = np.stack([x * 2, y * 8, np.zeros_like(x)], axis=-1)
            sheet = lattice_noise.perlin_noise(p, (2, 8, 1), lattice_noise.noise_salt(seed, 220))
            sheet += 0.5 * lattice_noise.perlin_noise(
                2 * p, (4, 16, 1), lattice_noise.noise_salt(seed, 221)
            )
            data[..., 3] = _threshold_to_mean(sheet, cirrus, _CIRRUS_EDGE)
        return cls(data, tile_km)


def _smoothstep(e0: float, e1: float, x: np.ndarray) -> np.ndarray:
    t = np.clip((x - e0) / (e1 - e0), 0.0, 1.0)
    return t * t * (3 - 2 * t)


def _threshold_to_mean(field: np.ndarray, mean: float, edge: float) -> np.ndarray:
    """clip((field - t) / edge, 0, 1) with t chosen (bisection, 60 steps) so that its mean is
    ``mean``; exactly 0 for mean 0 and exactly 1 for mean 1 (the mean falls monotonically
    and continuously from 1 at t = min - edge to 0 at t = max)."""
    if mean <= 0.0:
        return np.zeros_like(field)
    if mean >= 1.0:
        return np.ones_like(field)
    lo, hi = float(field.min()) - edge, float(field.max())
    for _ in range(60):
        t = 0.5 * (lo + hi)
        if np.clip((field - t) / edge, 0.0, 1.0).mean() > mean:
            lo = t
        else:
            hi = t
    return np.clip((field - 0.5 * (lo + hi)) / edge, 0.0, 1.0)


def _pair(name: str, value) -> tuple[float, float]:
    try:
        east, north = (float(v) for v in value)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(f"{name} must be two numbers (east, north) in m/s") from None
    if not (math.isfinite(east) and math.isfinite(north)):
        raise ParameterError(f"{name} = {value} must be finite")
    return east, north


@dataclass(frozen=True)
class WeatherInputs(ShaderInputs):
    """``clouds/weather_animate.glsl``: the map's size (texels), the wind's offset (tiles),
    the flow's reach (tiles) and its two phases, the evolution's coordinate and switch, the
    seed, the source map and the flow field (textures)."""

    u_size: tuple[float, float]
    u_wind_offset: tuple[float, float]
    u_flow_reach: float
    u_phase: tuple[float, float]
    u_evolution_z: float
    u_evolution_on: float
    u_seed: int
    u_weather: object
    u_flow: object


class AnimatedWeather:
    """A weather map on the GPU at any time: moved, advected and evolving.

    Args:
        ctx: moderngl context.
        weather_map: the map at the reference time t = 0.
        wind_m_s: (east, north) wind, m/s: the map moves by wind * t (wrapping around).
        flow_m_s: peak speed of the flow field (curl noise, divergence-free) that churns the
            map in the frame moving with the wind, m/s; 0 for none. A flow map distorts the
            map locally, it does not carry clouds across the tile: each of two phases drifts
            along the flow and fades out before it restarts (their weighted displacements
            cancel), so features swirl within about flow_m_s * flow_period_s / 2 of where
            they started. The wind does the transport.
        flow_period_s: the flow map's cycle, s: each of its two phases displaces by up to
            flow_m_s * flow_period_s / 2 before it fades out and restarts.
        evolution_s: time over which the clouds grow and decay noticeably, s (the noise that
            scales the coverage decorrelates over about this time); None for none.
        seed: seed of the flow field and of the evolution noise.
        flow_size: texels per side of the flow field's texture (power of two).

    At t = 0 the texture equals the map (to float precision), with or without flow.
    """

    def __init__(
        self,
        ctx,
        weather_map: WeatherMap,
        *,
        wind_m_s: tuple[float, float] = (0.0, 0.0),
        flow_m_s: float = 1.0,
        flow_period_s: float = 3600.0,
        evolution_s: float | None = 1800.0,
        seed: int = 1,
        flow_size: int = 128,
    ):
        if not isinstance(weather_map, WeatherMap):
            raise ParameterError(
                f"weather_map must be a WeatherMap, got {type(weather_map).__name__}"
            )
        self.ctx = ctx
        self.weather_map = weather_map
        self.wind_m_s = _pair("wind_m_s", wind_m_s)
        self.flow_m_s = check_range("flow_m_s", flow_m_s, 0.0, 1000.0, "m/s")
        self.flow_period_s = check_range("flow_period_s", flow_period_s, 1e-3, 1e9, "s")
        if evolution_s is not None:
            evolution_s = check_range("evolution_s", evolution_s, 1e-3, 1e12, "s")
        self.evolution_s = evolution_s
        self.seed = check_seed(seed)
        w, h = weather_map.size
        self._map = self._texture(weather_map.data, 4)
        #: The flow field's texels (flow_size, flow_size, 2), [j, i, (east, north)], in [-1, 1].
        self.flow_texels = render_curl(ctx, self.seed, flow_size)
        self._flow = self._texture(self.flow_texels, 2)
        # 8-bit normalised (every channel lies in [0, 1]): a CPU rasterizer filters it several
        # times faster than float32 in the clouds' march, which reads it at every step
        self._out = self._texture(None, 4, size=(w, h), dtype="f1")
        self._fbo = ctx.framebuffer(color_attachments=[self._out])
        self._pass = FullscreenPass(ctx, "clouds/weather_animate.glsl", inputs=(WeatherInputs,))
        self._time: float | None = None
        self.draws = 0  # passes drawn (a cache-hit counter for tests)

    def _texture(self, data, components: int, size=None, dtype: str = "f4"):
        if data is not None:
            h, w = data.shape[:2]
            data = np.ascontiguousarray(data, np.float32)
        else:
            w, h = size
        tex = self.ctx.texture((w, h), components, data, dtype=dtype)
        tex.repeat_x = tex.repeat_y = True
        tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
        return tex

    def inputs(self, time_s: float) -> WeatherInputs:
        """The animation shader's inputs at ``time_s``, every periodic term reduced in
        float64 first (so that long time-lapses keep float32 precision)."""
        tile_m = self.weather_map.tile_km * 1000.0
        offset = tuple(float((v * time_s / tile_m) % 1.0) for v in self.wind_m_s)
        cycle = time_s / self.flow_period_s
        evolution_z = 0.0 if self.evolution_s is None else time_s / self.evolution_s
        return WeatherInputs(
            u_size=tuple(float(v) for v in self.weather_map.size),
            u_wind_offset=offset,
            u_flow_reach=self.flow_m_s * self.flow_period_s / tile_m,
            u_phase=(float((cycle + 0.5) % 1.0), float(cycle % 1.0)),
            u_evolution_z=float(evolution_z % _EVOLUTION_Z_PERIOD),
            u_evolution_on=0.0 if self.evolution_s is None else 1.0,
            u_seed=self.seed,
            u_weather=self._map,
            u_flow=self._flow,
        )

    def texture_at(self, time_s: float) -> moderngl.Texture:
        """The map at ``time_s`` seconds from the reference time: an RGBA8 (normalised)
        texture, repeat wrap, linear filter. The same texture object is redrawn for each new time (the same
        time returns it without drawing)."""
        try:
            t = float(time_s)
        except (TypeError, ValueError, OverflowError):
            raise ParameterError(f"time_s must be a number of seconds, got {time_s!r}") from None
        if not math.isfinite(t):
            raise ParameterError(f"time_s = {time_s} must be finite")
        if self._time != t:
            w, h = self.weather_map.size
            self._fbo.viewport = (0, 0, w, h)
            self._pass.draw(self._fbo, self.inputs(t))
            self._time = t
            self.draws += 1
        return self._out

    def array_at(self, time_s: float) -> np.ndarray:
        """The map at ``time_s`` read back: (H, W, 4) float32 in steps of 1/255, rows south
        to north."""
        w, h = self.weather_map.size
        tex = self.texture_at(time_s)
        texels = np.frombuffer(tex.read(), dtype=np.uint8).reshape(h, w, 4)
        return texels.astype(np.float32) / np.float32(255.0)

    def release(self) -> None:
        for obj in (self._fbo, self._out, self._map, self._flow, self._pass):
            obj.release()
