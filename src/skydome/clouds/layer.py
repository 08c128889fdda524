"""The cloud layer: a volume layer of the scene's frame graph drawn after the atmosphere.

Two passes per tile (shaders/clouds/): ``clouds_march.glsl`` marches every pixel's ray
through the main layer's shell and the cirrus sheet's, lit by the key light (the Sun, or the
Moon once the Sun is well down) and the sky, into the clouds' own radiance, transmittance and
mean distance; ``clouds_composite.glsl`` puts them over what lies behind (the atmosphere and
the space layers), seen through the air in front of them, and takes the direct light off the
ground in their shadows. The atmosphere's tables give the light: the Sun's and the Moon's
irradiance at each cloud, the sky's, and the aerial perspective. Once per time and light,
``cloud_light_map.glsl`` draws the light map (skydome.clouds.light_map) from which the
full-quality march reads the key light's way through the clouds from the air under them.
"""

from __future__ import annotations

import math
from dataclasses import replace
from fractions import Fraction
from functools import partial
from math import lcm

import numpy as np

from skydome.clouds.direction_table import (
    ICE_TABLE_SCALE,
    TABLE_SIZE,
    table_directions,
    table_frame,
)
from skydome.clouds.halos import halo_table
from skydome.clouds.inputs import (
    CloudDataInputs,
    CloudInputs,
    CloudTextures,
    ColumnInputs,
    CompositeInputs,
    DepthInputs,
    LightMapInputs,
    QueryInputs,
    TemporalInputs,
    UpsampleInputs,
)
from skydome.clouds.light_map import (
    LIGHT_MAP_MIN_ELEVATION_DEG,
    LIGHT_MAP_MIN_MARCH_TEXELS,
    LIGHT_MAP_TEXELS,
    LIGHT_MAP_WARP_KM,
    LIGHT_PATH_STEPS,
    light_map_centre,
)
from skydome.clouds.ms_table import load_ms_table
from skydome.clouds.noise import cloud_noise
from skydome.clouds.params import (
    CIRRUS_EXTINCTION_PER_M,
    CLOUD_TYPES,
    WATER_NORMALIZATION,
    Clouds,
)
from skydome.clouds.phase import (
    CLOUD_R_EFF_UM,
    MIE_PHASE,
    RAIN_PEAK_FRACTION,
    RENDER_PHASE_TEXELS,
    TabulatedPhase,
    droplet_channel_phases,
    rain_channel_phases,
)
from skydome.clouds.probe import SkyProbe
from skydome.clouds.weather import AnimatedWeather, WeatherMap
from skydome.core.cameras import CameraInputs, DirectionsCamera, EquirectCamera
from skydome.core.layer import BehindInputs, DrawContext, Layer, LayerHost
from skydome.core.services import (
    AerialInputs,
    AirLights,
    AirService,
    LightInputs,
    SkyLightService,
    VolumeInputs,
)
from skydome.errors import ParameterError
from skydome.gpu.textures import linear_clamped, release_unbound
from skydome.physics.constants import J2000_JD
from skydome.physics.geometry import elevation_deg

#: Ray-march settings per quality: ``march`` = (the view step as a fraction of the
#: distance, most samples per shell, shortest step km); ``light_km`` = lengths (km) of the
#: march towards the light and across the local slab; ``scale``: the march's resolution is
#: 1/scale of the frame's; ``steps`` = (samples of the light march, a sample's light
#: computed afresh every n view steps); ``coarse``: view steps one step through clear air
#: spans; ``split``: in dense cloud a step shrinks to an optical depth of 1, down to 1/split
#: of its length (the light is taken where the light is scattered: without it a dense
#: cloud's shaded side shows the pixels' ordered offsets).
QUALITY = {
    "best": {"march": (0.006, 256.0, 0.025), "light_km": (6.0, 4.0), "scale": 1,
             "steps": (6, 1), "coarse": 4.0, "split": 8.0},
    # seed 000 (ch. 5.4) marches its clouds at half the resolution too
    "full": {"march": (0.008, 256.0, 0.03), "light_km": (6.0, 4.0), "scale": 2,
             "steps": (6, 1), "coarse": 4.0, "split": 3.0},
    "interactive": {"march": (0.025, 48.0, 0.08), "light_km": (4.0, 3.0), "scale": 8,
                    "steps": (4, 3), "coarse": 6.0, "split": 1.0},
}  # fmt: skip
#: Repeat lengths (km) of the shape and detail noises.
SHAPE_TILE_KM = 6.0
DETAIL_TILE_KM = 0.8
#: How far the detail noise erodes the shapes' edges (Schneider 2015's 0.2-0.4).
DETAIL_EROSION = 0.35
#: The light shafts' pass runs at 1/SHAFT_SCALE of the resolution (1/INTERACTIVE_SHAFT_SCALE
#: in the interactive mode: shadows in the air are smooth) over the first SHAFT_KM (km)
#: of each ray below the clouds' tops (a Sun 5 deg up casts a 3 km top's shadow 34 km).
SHAFT_SCALE = 8
INTERACTIVE_SHAFT_SCALE = 16
SHAFT_KM = 60.0
#: Still frames the interactive mode accumulates before a window may keep its image.
SETTLE_FRAMES = 16
#: The fraction of a fog's depth over which its top thins to nothing (a fog's top is not a
#: plane: its droplets thin over tens of metres).
FOG_TOP_FADE = 0.2
#: The census behind frame.info's optical depths: columns a side, and a cloudy column's
#: least optical depth as a fraction of the nominal.
CENSUS_GRID = 64
CLOUDY_FRACTION = 0.01
#: The census behind the seed's water correction: columns a side over the tile.
SEED_CENSUS_GRID = 64
#: The water correction of each seed measured so far (CloudLayer._seed_correction).
_SEED_CORRECTION: dict[tuple[int, float], tuple[float, ...]] = {}
#: The sky probe: its equirectangular map's size, and its height above the ground (m).
PROBE_SIZE = (64, 32)
PROBE_ALTITUDE_M = 2.0
#: Samples of each shell crossing of CloudLayer.light_transmittance's paths (by default).
SHADOW_QUERY_STEPS = 8
#: Below this Sun elevation (deg) the Moon, when up, lights the clouds instead.
MOON_KEY_BELOW_DEG = -8.0


class CloudLayer(Layer):
    """The clouds of a ``Clouds`` description (see skydome.clouds.params).

    Args:
        clouds: a ``Clouds`` or a preset name.
        quality: "full" (still frames: the march at half the resolution, as seed 000 does,
            read bilinearly), "best" (every pixel marched, finer steps: about 4x the cost) or
            "interactive" (a coarser march at an eighth of the resolution accumulated over
            frames, for the viewer; once a still view has settled, ``refine`` draws it
            once at full quality and keeps that).
        phase: the droplets' phase function, a ``TabulatedPhase`` or ``LobePhase`` of
            skydome.clouds.phase (default: their Mie phase function, MIE_PHASE); its
            forward peak is taken out (``delta_truncated``) and the rest tabulated for the
            march.
        shafts: light shafts: the air in the clouds' shadow scatters no sunlight (the
            atmosphere's shadow-length input). None (the default): on, but in the
            interactive mode's accumulating frames (there they would double a CPU
            rasterizer's frame time).
        refine: in the interactive mode, replace a still view's accumulated image by one
            full-quality march once SETTLE_FRAMES frames have gone into it (no blocks in
            a view that has settled; on a CPU rasterizer that frame takes about a second).
    """

    name = "clouds"
    stage = "volume"

    def __init__(self, clouds: Clouds | str = "fair", *, quality: str = "full", phase=None,
                 shafts: bool | None = None, refine: bool = True,
                 enabled: bool = True):  # fmt: skip
        super().__init__(enabled=enabled)
        self.clouds = Clouds(clouds) if isinstance(clouds, str) else clouds
        if not isinstance(self.clouds, Clouds):
            raise ParameterError(f"clouds must be a Clouds or a preset name, got {clouds!r}")
        if quality not in QUALITY:
            raise ParameterError(f"cloud quality {quality!r} must be one of {', '.join(QUALITY)}")
        self.quality = quality
        self.refine = bool(refine)
        #: The quality the passes being drawn use (the interactive mode's refined frame
        #: marches at "full").
        self._pass_quality = quality
        #: What the refined frame kept in its march target was drawn for (None: none kept).
        self._refined_key = None
        self.shafts = quality != "interactive" if shafts is None else bool(shafts)
        #: The interactive mode's refined frame draws the shafts a still frame would.
        self._refined_shafts = shafts is None
        if phase is None:
            phase = MIE_PHASE
        #: The phase function the march uses (tabulated) and the factor on the extinction:
        #: the droplets' diffraction peak taken out (``delta_truncated``), its light counted as
        #: unscattered (it leaves within a few degrees of its direction).
        self.phase, peak = phase.delta_truncated()
        if not isinstance(self.phase, TabulatedPhase) or self.phase.values.size != (
            RENDER_PHASE_TEXELS
        ):
            self.phase = TabulatedPhase.of(self.phase)
        self.extinction_scale = 1.0 - peak
        self.noise = None
        self.weather = None
        self._targets: dict = {}
        self._static = None  # (the multiple-scattering table, the phase table): textures
        self._frame_index = 0
        self._settled = 0  # still frames blended into the interactive history
        self._history_key = self._history_camera = self._history_time = None
        self._state = None
        self._census = None
        self._probe = None
        self._table = None  # (key, radiance, data, u_table_frame): a fog alone's march
        self._halo = None  # (the halo table, its texture): the cirrus crystals' light
        self._fog = None  # the fog droplets' phase function by channel (their own radius)
        self._under_ratio = (1.0, 1.0, 1.0, 1.0)  # the clouds' sky light on what is under them
        self._light_map = None  # (key, texture, framebuffer): the key light through the clouds
        self._interactive_sky = None  # the sky of the interactive mode's last frame
        self._outputs: dict = {}
        self.air: AirService | None = None
        #: Seconds since J2000 (2000-01-01 12:00 UTC) of the last update: the clouds are a pure
        #: function of the time (0 in the abstract mode, which has none).
        self.time_s = 0.0

    # ------------------------------------------------------------------ stages

    def _air(self) -> AirService:
        """The atmosphere's service (its tables and lights)."""
        if self.air is None:
            raise ParameterError("the cloud layer is not in a frame graph yet")
        return self.air

    def prepare(self, host: LayerHost) -> None:
        super().prepare(host)
        if host.find_service(AirService) is None:
            raise ParameterError("clouds need an atmosphere layer in the same sky")
        self.air = host.service(AirService)
        self.clouds.check_atmosphere(self.air.top_radius_m - self.air.bottom_radius_m)

    def _noise_and_weather(self) -> None:
        """The noise textures and the animated weather map (on first use)."""
        if self.noise is not None:
            return

        self.noise = cloud_noise(self.graph.ctx, self.clouds.seed)
        self.weather = AnimatedWeather(
            self.graph.ctx,
            weather_map_for(self.clouds),
            wind_m_s=self.clouds.wind_m_s,
            seed=self.clouds.seed,
        )

    def update(self, state) -> None:
        self._state = state
        air = self._air()
        self.clouds.check_atmosphere(air.top_radius_m - air.bottom_radius_m - self.ground_m)
        jd = state.julian_day_utc
        self.time_s = 0.0 if jd is None else (jd - J2000_JD) * 86400.0

    # ------------------------------------------------------------------ uniforms

    @property
    def ground_m(self) -> float:
        """Height (m) of the place's ground above the atmosphere's: the clouds' base and
        top, and the shadow query's points, are above it (0 in the abstract mode)."""
        return 0.0 if self._state is None else self._state.ground_m

    def _shell_radii_km(self, bottom_km: float) -> tuple[float, float, float, float]:
        """Radii (km) of the main layer's bottom and top and of the cirrus sheet's (an empty
        layer is a shell of no thickness)."""
        c, ground_km = self.clouds, bottom_km + self.ground_m / 1e3
        top = c.base_m + (c.thickness_m if c.coverage > 0 else 0.0)
        cirrus_top = c.cirrus_base_m + (c.cirrus_thickness_m if c.cirrus > 0 else 0.0)
        return (ground_km + c.base_m / 1e3, ground_km + top / 1e3,
                ground_km + c.cirrus_base_m / 1e3, ground_km + cirrus_top / 1e3)  # fmt: skip

    def _ground_layer_km(self, bottom_km: float) -> tuple[float, float, float, float]:
        """Radii (km) of the ground and of the tops of the fog and of the precipitation (the
        main layer's base; the ground without any), and the depth (km) over which the fog's
        top thins (FOG_TOP_FADE of its depth)."""
        c, ground_km = self.clouds, bottom_km + self.ground_m / 1e3
        rain_top = c.base_m / 1e3 if c.precipitation_extinction_per_m > 0 else 0.0
        return (ground_km, ground_km + c.fog_top_m / 1e3, ground_km + rain_top,
                FOG_TOP_FADE * c.fog_top_m / 1e3)  # fmt: skip

    def services(self) -> tuple:
        return (_CloudySkyLight(self),)

    def key_light(self, lights: AirLights) -> tuple[tuple, tuple]:
        """(direction, per-channel scale relative to the tables' Sun) of the light that lights
        the clouds: the Sun, or the Moon when the Sun is below MOON_KEY_BELOW_DEG and the
        Moon is up."""
        sun = tuple(float(v) for v in lights.sun_direction)
        moon = lights.moon_direction
        if moon is not None and elevation_deg(sun) < MOON_KEY_BELOW_DEG and moon[2] > -0.05:
            return tuple(float(v) for v in moon), tuple(float(s) for s in lights.moon_scale)
        return sun, (float(lights.sun_scale),) * 4

    def light_inputs(self, frame: DrawContext) -> LightInputs:
        """The air's lights as the march reads them, for ``frame``'s camera."""
        air = self._air()
        return air.lights().inputs(air.camera_position_km(frame.altitude_m), air.solar_scale)

    def cloud_inputs(self, **changes) -> CloudInputs:
        """The clouds' own uniforms at the last update (``changes``: fields set otherwise,
        e.g. a frame's jitter or a test's uniform extinction)."""
        air = self._air()
        lights = air.lights()
        solar = air.solar_scale
        c = self.clouds
        key_dir, key_scale = self.key_light(lights)
        q = QUALITY[self._pass_quality]
        g = float(self.phase.asymmetry)
        f = float(self.phase.second_moment)
        # How far the wind has carried the noise, reduced (in float64) modulo a length over
        # which every noise it moves repeats: float32 keeps its metres.
        period = self._offset_period_km()
        offset_km = tuple(float(v) * self.time_s / 1e3 % period for v in c.wind_m_s) + (0.0,)
        # the rain's extinction less its forward peak (RAIN_PEAK_FRACTION), the snow's as the
        # droplets'; u_rain_share: the rain's part of what remains
        rain_scaled = c.rain_fraction * (1.0 - RAIN_PEAK_FRACTION)
        precipitation_scale = rain_scaled + (1.0 - c.rain_fraction) * self.extinction_scale
        inputs = CloudInputs(
            u_light_direction=key_dir,
            u_light_scale=tuple(s * solar for s in key_scale),
            u_cloud_shell=self._shell_radii_km(air.bottom_radius_m / 1e3),
            u_ground_layer=self._ground_layer_km(air.bottom_radius_m / 1e3),
            u_ground_extinction=(
                c.fog_extinction_per_m * 1e3 * self.extinction_scale,
                c.precipitation_extinction_per_m * 1e3 * precipitation_scale,
                1.0 / c.precipitation if c.precipitation > 0 else 0.0,
            ),
            u_rain_share=rain_scaled / precipitation_scale,
            u_noise_tiles_km=(c.tile_km, SHAPE_TILE_KM, DETAIL_TILE_KM),
            u_cloud_offset_km=offset_km,
            u_type_extinction=tuple(e * self.extinction_scale for e in c.type_extinctions_per_km()),
            u_cirrus_extinction=CIRRUS_EXTINCTION_PER_M * 1e3 * self.extinction_scale,
            u_detail_erosion=DETAIL_EROSION,
            u_water_norm=changes.pop("u_water_norm", None) or self._water_norm(),
            u_cloud_moments=(g, f, (g - f) / (1.0 - f)),
            u_march=q["march"],
            u_light_march_km=q["light_km"],
            u_cloud_albedo_below=air.ground_albedo(),
            u_frame_jitter=0.0,
            u_peak_scale=self.extinction_scale,
            u_ms_norm_g=[float(g) for g in _ms_table().norm_g],
            u_uniform_extinction=(
                c.nominal_optical_depth / (c.thickness_m / 1e3) * self.extinction_scale
                if c.uniform else None
            ),
        )  # fmt: skip
        return replace(inputs, **changes) if changes else inputs

    def _water_norm(self, corrected: bool = True) -> list[float]:
        """WATER_NORMALIZATION flattened (type-major), each type's row times this seed's
        correction (:meth:`_seed_correction`) when ``corrected``."""
        factors = self._seed_correction() if corrected and not self.clouds.uniform else None
        out = []
        for i, t in enumerate(CLOUD_TYPES):
            out += [v * (1.0 if factors is None else factors[i]) for v in WATER_NORMALIZATION[t]]
        return out

    def _seed_correction(self) -> tuple[float, ...]:
        """Per cloud type, the factor that brings this seed's closed deck to its nominal
        water: WATER_NORMALIZATION is the mean over seeds 1-3, and one seed's noise tile
        holds a few per cent more or less (up to 13 % for cumulus). Measured once per seed
        and layer thickness by a census of a closed deck of each type (SEED_CENSUS_GRID columns a side)."""
        seed = (self.clouds.seed, self.clouds.thickness_m)  # the noise's height span too
        if seed in _SEED_CORRECTION:
            return _SEED_CORRECTION[seed]
        ctx = self.graph.ctx
        self._noise_and_weather()
        table = self._water_norm(corrected=False)
        c = self.clouds
        factors = []
        for i, value in enumerate(CLOUD_TYPES.values()):
            texel = np.array([1.0, value, 0.0, 0.0], dtype=np.float32)
            weather = ctx.texture((1, 1), 4, texel.tobytes(), dtype="f4")
            try:
                textures = CloudTextures(
                    *self._static_textures(), weather, self.noise.shape, self.noise.detail,
                    self.noise.curl,
                )  # fmt: skip
                inputs = self.cloud_inputs(
                    u_water_norm=table, u_cloud_offset_km=(0.0, 0.0, 0.0),
                    u_cloud_shell=self._shell_radii_km(self._air().bottom_radius_m / 1e3)[:2]
                    + (0.0, 0.0),
                )  # fmt: skip
                tau = self._census_pass(inputs, textures, SEED_CENSUS_GRID)[..., 0]
            finally:
                release_unbound(weather)
            nominal = c.type_extinctions_per_km()[i] * c.thickness_m / 1e3
            factors.append(nominal / max(float(tau.mean()), 1e-9))
        _SEED_CORRECTION[seed] = tuple(factors)
        return _SEED_CORRECTION[seed]

    def _aerial(self, lights: LightInputs) -> AerialInputs | None:
        """The atmosphere's aerial-perspective tables for the air's lights seen from this
        camera, or None where there are none (a camera above the atmosphere: the march looks
        the 4D tables up instead)."""
        air = self._air()
        return air.aerial_perspective(float(lights.u_camera_position[2]), air.lights())

    def _offset_period_km(self) -> float:
        """The least common multiple (km, to the metre) of the repeat lengths of what the wind
        moves: the shape and detail noises and the cirrus's curl field (half the weather
        tile)."""

        lengths = [Fraction(round(v * 1000), 1000) for v in
                   (SHAPE_TILE_KM, DETAIL_TILE_KM, 0.5 * self.clouds.tile_km)]  # fmt: skip
        denominator = lcm(*(f.denominator for f in lengths))
        return lcm(*(int(f * denominator) for f in lengths)) / denominator

    def defines(self, frame: DrawContext, extra: tuple[str, ...] = ()) -> dict:
        air = self._air()
        q = QUALITY[self._pass_quality]
        light, every = q["steps"]
        d = {
            **air.lookup().defines,
            "CLOUD_PHASE_TEXELS": RENDER_PHASE_TEXELS,
            "LIGHT_STEPS": light,
            "LIGHT_EVERY": every,
            "COARSE": float(q["coarse"]),
            "STEP_SPLIT": float(q["split"]),
            "LIGHT_PATH_STEPS": LIGHT_PATH_STEPS,
        }
        if air.lights().has_moon:
            d["HAS_LIGHT2"] = 1
        if self.clouds.uniform:
            d["UNIFORM_CLOUD"] = 1
        elif not self.clouds.aloft:
            d["NO_ALOFT"] = 1
        if self._halos_drawn():
            d["HALOS"] = 1
            if self.clouds.fog_ice:
                d["FOG_ICE"] = 1
        if self._fog_droplets_own():
            d["FOG_PHASE"] = 1
        for name in extra:
            d[name] = 1
        return d

    def _own_defines(self) -> dict:
        """The defines of the passes that read only the clouds' density (no camera, no
        light model): the tables' and a uniform deck's."""
        d = dict(self._air().lookup().defines)
        if self.clouds.uniform:
            d["UNIFORM_CLOUD"] = 1
        return d

    def _static_textures(self) -> tuple:
        """(the multiple-scattering table, skydome.clouds.ms_table, as a 3D texture: x = 12
        blocks (the scattered direction's cosine) of 24 depths, y = the optical thickness,
        z = the light's cosine, RGB = the azimuth Fourier coefficients; the phase functions
        the march uses, tabulated at RENDER_PHASE_TEXELS angles uniform from 0 to 180 deg,
        linear filtering: the droplets' (the same function as its TabulatedPhase), and the
        rain's (for its drops' sizes) and the droplets' by output channel (RGBA:
        rain_channel_phases and droplet_channel_phases for the graph's basis))."""
        if self._static is None:
            c = self.clouds  # the rain's drops: its rate's, or one size
            radius_um = None if c.rain_drop_radius_mm is None else 1e3 * c.rain_drop_radius_mm
            rain = partial(rain_channel_phases, rain_mm_h=c.rain_mm_h, drop_radius_um=radius_um)
            j = np.asarray(_ms_table().J, dtype=np.float32)  # (tau, mu0, depth, mu, 3)
            nt, nm0, nd, nmu, _ = j.shape
            texels = np.zeros((nm0, nt, nmu * nd, 4), dtype=np.float32)
            texels[..., :3] = j.transpose(1, 0, 3, 2, 4).reshape(nm0, nt, nmu * nd, 3)
            ctx = self.graph.ctx
            ms = ctx.texture3d((nmu * nd, nt, nm0), 4, texels.tobytes(), dtype="f4")
            values = np.asarray(self.phase.values, dtype=np.float32)
            phase = ctx.texture((values.size, 1), 1, values.tobytes(), dtype="f4")
            basis = self.graph.basis
            channels = []
            for table in (rain, droplet_channel_phases):
                channels.append(self._channel_texture(table(basis.wavelengths_nm, basis.to_output)))
            self._static = (*(linear_clamped(t, ctx) for t in (ms, phase)), *channels)
        return self._static

    def _channel_texture(self, values: np.ndarray):
        """A phase function per output channel (4, RENDER_PHASE_TEXELS) as an RGBA texture one
        texel high, linear filtering, clamped."""
        texels = np.ascontiguousarray(np.asarray(values).T, dtype=np.float32)  # (texels, 4)
        ctx = self.graph.ctx
        tex = ctx.texture((texels.shape[0], 1), 4, texels.tobytes(), dtype="f4")
        return linear_clamped(tex, ctx)

    def _fog_droplets_own(self) -> bool:
        """Whether the fog's droplets scatter by their own phase function (their effective
        radius is not the clouds')."""
        c = self.clouds
        return c.fog_top_m > 0 and not c.fog_ice and c.fog_droplet_um != CLOUD_R_EFF_UM

    def _fog_texture(self):
        """The fog droplets' phase function per output channel (droplet_channel_phases for
        their effective radius), as the droplets' texture; made once."""
        if self._fog is None:
            basis = self.graph.basis
            self._fog = self._channel_texture(droplet_channel_phases(
                basis.wavelengths_nm, basis.to_output, self.clouds.fog_droplet_um
            ))  # fmt: skip
        return self._fog

    def _halos_drawn(self) -> bool:
        """Whether ice crystals scatter by their halo table: a cirrus, or diamond dust (an
        ice fog), of crystals."""
        c = self.clouds
        ice = c.cirrus > 0 or (c.fog_ice and c.fog_top_m > 0)
        return ice and c.halos != "none" and not c.uniform

    def _halo_texture(self):
        """The ice crystals' phase function (the cirrus's, diamond dust's) for the key light's
        elevation (skydome.clouds.halos.halo_table, per output channel of the graph's basis)
        as an RGBA texture: x the azimuth from the light (0-180 deg), y the elevation seen
        (-90 to 90), linear filtering; traced at the first frame at each elevation and kept."""
        key_dir, _ = self.key_light(self._air().lights())
        basis = self.graph.basis
        table = halo_table(self.clouds.halos, elevation_deg(key_dir), basis.wavelengths_nm,
                           basis.to_output)  # fmt: skip
        if self._halo is None or self._halo[0] is not table:
            if self._halo is not None:
                self._halo[1].release()
            texels = np.ascontiguousarray(np.moveaxis(table, 0, -1), dtype=np.float32)
            ctx = self.graph.ctx
            tex = ctx.texture((texels.shape[1], texels.shape[0]), 4, texels.tobytes(), dtype="f4")
            self._halo = (table, linear_clamped(tex, ctx))
        return self._halo[1]

    def texture_inputs(self, noise: bool = True) -> CloudTextures:
        """The clouds' textures: the multiple-scattering and phase tables and (with ``noise``) the
        weather map at the last update's time and the noises."""
        if not noise or self.clouds.uniform:
            return CloudTextures(*self._static_textures())
        self._noise_and_weather()
        ms, phase, rain, droplets = self._static_textures()
        return CloudTextures(
            u_cloud_ms_table=ms,
            u_cloud_phase_table=phase,
            u_rain_phase_table=rain,
            u_droplet_phase_table=droplets,
            u_weather=self.weather.texture_at(self.time_s),
            u_shape_noise=self.noise.shape,
            u_detail_noise=self.noise.detail,
            u_curl_noise=self.noise.curl,
            u_halo_table=self._halo_texture() if self._halos_drawn() else None,
            u_fog_phase_table=self._fog_texture() if self._fog_droplets_own() else None,
        )

    # ------------------------------------------------------------------ drawing

    def _make_target(self, w: int, h: int):
        """Two RGBA float textures (radiance, data), bilinear and clamped, and their framebuffer."""
        ctx = self.graph.ctx
        texs = [ctx.texture((w, h), 4, dtype="f4") for _ in range(2)]
        for t in texs:
            t.filter = (ctx.LINEAR, ctx.LINEAR)
            t.repeat_x = t.repeat_y = False
        return texs, ctx.framebuffer(color_attachments=texs)

    def _march_target(self, w: int, h: int):
        key = (w, h)
        if key not in self._targets:
            self._targets[key] = self._make_target(w, h)
        return self._targets[key]

    def march(self, frame: DrawContext, cloud: CloudInputs, textures: CloudTextures, extra=(),
              target=None):  # fmt: skip
        """Draw the march pass of ``frame``'s tile into this layer's two targets (or
        ``target``'s: textures and framebuffer); returns them (radiance, (transmittance,
        distance km, ground shadow, 1))."""
        _, _, tw, th = frame.tile
        (rad, data), fbo = target or self._march_target(tw, th)
        fbo.viewport = (0, 0, tw, th)
        lookup = self._air().lookup()
        lights = self.light_inputs(frame)
        inputs = [frame.view, lookup.inputs, lights, cloud, textures]
        if frame.depth_map is not None and "SKY_PROBE" not in extra:
            extra = (*extra, "HAS_DEPTH_MAP")
            inputs.append(DepthInputs(frame.depth_map))
        aerial = None if "CLOUDS_ALONE" in extra else self._aerial(lights)
        if aerial is not None:
            extra = (*extra, "AERIAL_TABLES")
            inputs.append(aerial)
        if not {"CLOUDS_ALONE", "SKY_PROBE"} & set(extra):
            light_map = self._light_map_inputs(
                cloud, textures, lights.u_camera_position[2], tw * th
            )
            if light_map is not None:
                extra = (*extra, "LIGHT_MAP")
                inputs.append(light_map)
        fpass = self.full_screen_pass(
            frame.ctx, "clouds/clouds_march.glsl", tuple(type(i) for i in inputs),
            frame.camera, self.defines(frame, extra),
        )  # fmt: skip
        fpass.draw(fbo, *inputs)
        return rad, data

    def _lowest_base_km(self, cloud: CloudInputs) -> float | None:
        """The radius (km) of the lowest base of the clouds' shells that hold any, or None."""
        shells = cloud.u_cloud_shell
        bases = [lo for lo, hi in (shells[:2], shells[2:]) if hi > lo]
        return min(bases) if bases else None

    def _light_map_inputs(self, cloud: CloudInputs, textures: CloudTextures,
                          camera_radius_km: float, texels: int) -> LightMapInputs | None:  # fmt: skip
        """The light map for a march of ``cloud`` over ``texels`` from a camera at
        ``camera_radius_km`` (planet-centred), or None where the march goes without it: at
        the "best" quality (the reference it is held to); for a march of fewer than
        LIGHT_MAP_MIN_MARCH_TEXELS at full quality (see there; whether a map is drawn
        already does not matter: a frame is the same whatever came before it); in the
        interactive mode at a sky's first frame, so
        while the sky changes from frame to frame (the time running: a map a frame would
        cost its small frames more than it saves them; a still sky's map serves every
        frame after its first); with a key light below LIGHT_MAP_MIN_ELEVATION_DEG (see
        there), without clouds aloft (or with a uniform test deck), or from a camera at or
        above their lowest base."""
        if self._pass_quality == "best" or self.clouds.uniform or not self.clouds.aloft:
            return None
        if self._pass_quality == "interactive" and self._interactive_sky != self._sky_key():
            return None
        base_km = self._lowest_base_km(cloud)
        low = cloud.u_light_direction[2] < math.sin(math.radians(LIGHT_MAP_MIN_ELEVATION_DEG))
        if base_km is None or low or camera_radius_km >= base_km:
            return None
        if self._pass_quality == "full" and texels < LIGHT_MAP_MIN_MARCH_TEXELS:
            return None
        return LightMapInputs(self._light_map_warp(cloud), self.light_map(cloud, textures))

    def _light_map_key(self, cloud: CloudInputs) -> tuple:
        """What the light map of ``cloud`` depends on."""
        return (self._sky_key(), cloud.u_cloud_shell, cloud.u_light_direction,
                cloud.u_cloud_offset_km, tuple(cloud.u_water_norm),
                self._light_map_warp(cloud))  # fmt: skip

    def _light_map_warp(self, cloud: CloudInputs) -> tuple[float, float, float, float]:
        """The light map's u_light_map_warp for ``cloud``: (the warp's length, the lowest
        base's radius, the centre's x, y; km)."""
        base_km = self._lowest_base_km(cloud)
        if base_km is None:
            raise ParameterError("the light map needs clouds in a shell")
        centre = light_map_centre(cloud.u_light_direction, base_km, cloud.u_ground_layer[0])
        return (LIGHT_MAP_WARP_KM, base_km, *centre)

    def light_map(self, cloud: CloudInputs, textures: CloudTextures):
        """The clouds' light map (clouds/cloud_light_map.glsl) for ``cloud`` and ``textures``:
        an R32F texture of LIGHT_MAP_TEXELS a side, bilinear, clamped; drawn when the time,
        the clouds or the lights change, and kept."""
        key = self._light_map_key(cloud)
        warp = key[-1]
        if self._light_map is not None and self._light_map[0] == key:
            return self._light_map[1]
        ctx = self.graph.ctx
        if self._light_map is None:
            n = LIGHT_MAP_TEXELS
            tex = linear_clamped(ctx.texture((n, n), 1, dtype="f4"), ctx)
            fbo = ctx.framebuffer(color_attachments=[tex])
        else:
            _, tex, fbo = self._light_map
        lookup = self._air().lookup()
        inputs = (lookup.inputs, cloud, textures, LightMapInputs(warp))
        fpass = self.full_screen_pass(
            ctx, "clouds/cloud_light_map.glsl", tuple(type(i) for i in inputs), None,
            {**self._own_defines(), "LIGHT_MAP_TEXELS": LIGHT_MAP_TEXELS,
             "LIGHT_PATH_STEPS": LIGHT_PATH_STEPS},
        )  # fmt: skip
        fbo.viewport = (0, 0, *tex.size)
        fpass.draw(fbo, *inputs)
        self._light_map = (key, tex, fbo)
        return tex

    def probe(self, camera, width: int, height: int, altitude_m: float, *,
              test_irradiance: float | None = None, uniform_extinction_per_m: float | None = None):  # fmt: skip
        """The march pass alone for a camera (the layer must be in a prepared sky): arrays
        (H, W, 4) of the clouds' radiance (cd/m^2, not yet seen through the air) and of
        (transmittance, distance km, ground shadow, 1), top row first. For tests:
        ``test_irradiance`` lights every point with that irradiance (lx, all channels) and no
        sky; ``uniform_extinction_per_m`` fills the main layer with a constant extinction (of the
        droplets, diffraction included: the march scales it by ``extinction_scale``);
        both march with the samples at the steps' middles (no jitter)."""
        frame = self._whole_frame(camera, width, height, altitude_m)
        changes: dict = {}
        extra = []
        if test_irradiance is not None:
            extra.append("CLOUDS_ALONE")
            changes["u_test_irradiance"] = (float(test_irradiance),) * 4
            changes["u_cloud_albedo_below"] = 0.0  # black ground below, as the references
        if uniform_extinction_per_m is not None:
            extra.append("UNIFORM_CLOUD")
            changes["u_uniform_extinction"] = (
                float(uniform_extinction_per_m) * 1e3 * self.extinction_scale
            )
        if extra:
            extra.append("NO_JITTER")
        textures = self.texture_inputs(noise=uniform_extinction_per_m is None)
        rad, data = self.march(frame, self.cloud_inputs(**changes), textures, tuple(extra))
        out = []
        for tex in (rad, data):
            a = np.frombuffer(tex.read(), dtype="f4").reshape(height, width, 4)
            out.append(a[::-1].copy())
        return out[0], out[1]

    def _whole_frame(self, camera, width: int, height: int, altitude_m: float) -> DrawContext:
        """A frame of the layer's own (one tile, nothing behind) for ``camera``."""
        return DrawContext(
            self.graph.ctx, camera, (width, height), (0, 0, width, height), None,
            camera.inputs(width, height), altitude_m, self.graph.basis,
        )  # fmt: skip

    def _sky_key(self) -> tuple:
        """What the clouds' look depends on besides the camera: the time, the clouds, the
        lights' directions and the ground's albedo."""
        air = self._air()
        lights = air.lights()
        return (self.time_s, self.clouds, tuple(lights.sun_direction), lights.moon_direction,
                air.ground_albedo())  # fmt: skip

    def sky_probe(self) -> SkyProbe:
        """The sky that is drawn, seen from the ground under the camera at the last update:
        the clouds marched over the clear sky of the atmosphere's tables (no Sun's disk)
        into a PROBE_SIZE equirectangular map (cd/m^2), and what it gives: the irradiance of
        a horizontal surface, the clear sky's, and the radiance's spherical harmonics. Kept
        until the time, the lights, the clouds or the march's quality change."""
        key = (*self._sky_key(), self._pass_quality)
        if self._probe is not None and self._probe[0] == key:
            return self._probe[1]
        w, h = PROBE_SIZE
        camera = EquirectCamera()
        frame = self._whole_frame(camera, w, h, PROBE_ALTITUDE_M)
        # The fog and the precipitation under the clouds are lit by the sky the clouds leave:
        # a first probe of the clouds alone measures it (their irradiance over the clear
        # sky's), and the probe is marched again with it on them.
        under = (1.0, 1.0, 1.0, 1.0)
        c = self.clouds
        if c.ground_layer_top_m > 0 and (c.coverage > 0 or c.cirrus > 0):
            inputs = self.cloud_inputs(u_ground_extinction=(0.0, 0.0, 0.0))
            under = self._probe_pass(frame, inputs).ratio
        self._under_ratio = under
        probe = self._probe_pass(frame, self.cloud_inputs(u_under_sky_ratio=under))
        self._probe = key, probe
        return probe

    def _probe_pass(self, frame, inputs: CloudInputs) -> SkyProbe:
        """One march of the probe's map with ``inputs``."""
        w, h = PROBE_SIZE
        rad, data = self.march(frame, inputs, self.texture_inputs(), ("SKY_PROBE",))
        radiance = np.frombuffer(rad.read(), dtype="f4").reshape(h, w, 4)[::-1]
        clear = np.frombuffer(data.read(), dtype="f4").reshape(h, w, 4)[::-1, :, 1:4]
        return SkyProbe.from_maps(radiance.astype(np.float64), clear.astype(np.float64))

    def light_transmittance(self, points_m, steps: int = SHADOW_QUERY_STEPS) -> np.ndarray:
        """The clouds' transmittance towards the key light (the Sun, or the Moon at night) at
        points of a user's scene: ``points_m`` (..., 3) in metres, east, north and up from the
        place's ground (the tangent plane: within tens of km the curvature is negligible
        here), at this layer's last time. Returns (...) in [0, 1]: 1 in full light, 0 in a
        cloud's full shadow (a shadow map for compositing a scene under the clouds).
        ``steps``: samples of each crossing of a shell (1-64; the march's light paths take
        LIGHT_PATH_STEPS)."""
        p = np.asarray(points_m, dtype=np.float64)
        if isinstance(steps, bool) or not (
            isinstance(steps, int | np.integer) and 1 <= steps <= 64
        ):
            raise ParameterError(f"steps = {steps!r} must be an integer in 1-64")
        if p.shape[-1:] != (3,) or not np.all(np.isfinite(p)):
            raise ParameterError("points_m must be finite (..., 3) east, north, up in metres")
        if self.graph is None or self._state is None:
            raise ParameterError("light_transmittance needs the layer in a sky with a time")
        if self.clouds.empty:
            return np.ones(p.shape[:-1])
        flat = p.reshape(-1, 3)
        n = flat.shape[0]
        bottom_km = self._air().bottom_radius_m / 1e3
        up_km = bottom_km + (self.ground_m + flat[:, 2]) / 1e3
        km = np.column_stack([flat[:, 0] / 1e3, flat[:, 1] / 1e3, up_km])
        width = min(n, 4096)
        height = -(-n // width)
        texels = np.zeros((height * width, 4), dtype=np.float32)
        texels[:n, :3] = km
        points = self.graph.ctx.texture((width, height), 4, texels.tobytes(), dtype="f4")
        try:
            inputs = (self._air().lookup().inputs, self.cloud_inputs(), self.texture_inputs(),
                      QueryInputs(points))  # fmt: skip
            t = self._data_pass("clouds/cloud_shadow_query.glsl", inputs, (width, height), 1,
                                {"QUERY_STEPS": int(steps)})  # fmt: skip
        finally:
            release_unbound(points)
        t = t.reshape(-1)[:n]
        return t.astype(np.float64).reshape(p.shape[:-1])

    def column_optical_depths(self, grid: int = 96) -> np.ndarray:
        """The optical depth of vertical columns through the clouds at the last update's time:
        (grid, grid, 2) for the main layer and the cirrus sheet, over a regular grid of the
        weather map's tile (row 0 in the south; the droplets' optical depth, diffraction
        peak included), from the same extinction field the march and the light see."""
        if self.graph is None:
            raise ParameterError("column_optical_depths needs the layer in a sky")
        grid = int(grid)
        if not 1 <= grid <= 1024:
            raise ParameterError(f"the census grid must be 1-1024 columns a side, got {grid}")
        return self._census_pass(self.cloud_inputs(), self.texture_inputs(), grid)

    def _census_pass(self, cloud: CloudInputs, textures: CloudTextures, grid: int) -> np.ndarray:
        """clouds/cloud_columns.glsl over a grid x grid census of the tile: (grid, grid, 2)."""
        spacing = self.clouds.tile_km / grid
        inputs = (self._air().lookup().inputs, cloud, textures, ColumnInputs((spacing, spacing)))
        tau = self._data_pass("clouds/cloud_columns.glsl", inputs, (grid, grid), 4)[..., :2]
        return tau.astype(np.float64) / self.extinction_scale

    def _data_pass(self, shader: str, inputs: tuple, size: tuple[int, int], components: int,
                   defines: dict | None = None):  # fmt: skip
        """Draw one of the layer's passes that read only the clouds' density (no camera;
        ``defines`` besides the layer's own) into a float texture of ``size`` and read it
        back: (h, w, components), row 0 first as GL stores it."""
        ctx = self.graph.ctx
        out = ctx.texture(size, components, dtype="f4")
        fbo = ctx.framebuffer(color_attachments=[out])
        try:
            fpass = self.full_screen_pass(
                ctx, shader, tuple(type(i) for i in inputs), None,
                {**self._own_defines(), **(defines or {})},
            )  # fmt: skip
            fbo.viewport = (0, 0, *size)
            fpass.draw(fbo, *inputs)
            data = np.frombuffer(out.read(), dtype=np.float32)
        finally:
            release_unbound(fbo)
            release_unbound(out)
        return data.reshape(size[1], size[0], components)

    def draw(self, frame: DrawContext) -> None:
        if self.clouds.empty:  # nothing to draw: what lies behind, as it is
            self._copy_behind(frame)
            return
        if self._tabled(frame):
            rad, data, table_frame = self._direction_table(frame)
            self._composite(frame, rad, data, (0.0, 0.0, 0.0, 0.0), table_frame)
            return
        # a camera of given directions has no neighbours to share a march texel with, nor has
        # a user's scene (its edges are the pixels')
        scene = frame.depth_map is not None
        scale = QUALITY[self.quality]["scale"] if frame.camera.has_projection and not scene else 1
        whole = frame.tile == (0, 0, *frame.frame_size)
        mode = None
        if self.quality == "interactive" and whole and scale > 1:
            mode, key = self._interactive_mode(frame)
        if mode == "kept":
            scale = QUALITY["full"]["scale"]
            w, h = frame.frame_size
            (rad, data), _ = self._march_target(math.ceil(w / scale), math.ceil(h / scale))
        else:
            if mode == "refine":
                self._pass_quality = "full"
            try:
                rad, data, scale = self._march_frame(frame, mode, scale)
            finally:
                self._pass_quality = self.quality
            self._refined_key = key if mode == "refine" else None
        # the march's texels cover scale x scale pixels (the last row and column may overhang)
        lw, lh = rad.size
        self._composite(frame, rad, data, (1.0 / (scale * lw), 1.0 / (scale * lh), 0.0, 0.0))
        if scene:
            self._outputs["transmittance"] = self._scene_transmittance(frame, data)

    def _composite(self, frame: DrawContext, rad, data, cloud_map, table_frame=None) -> None:
        """The march (``rad``, ``data``) over what lies behind: read per pixel at
        ``cloud_map``, or by direction in a direction table (``table_frame``: its frame and
        size, clouds/direction_table.glsl's uniforms)."""
        extra = () if table_frame is None else ("DIRECTION_TABLE",)
        composite = self.full_screen_pass(
            frame.ctx, "clouds/clouds_composite.glsl",
            (CameraInputs, BehindInputs, CompositeInputs), frame.camera,
            self.defines(frame, extra),
        )  # fmt: skip
        air = self._air()
        ground = (*air.camera_position_km(frame.altitude_m), air.bottom_radius_m / 1e3)
        composite.draw(
            frame.fbo, frame.view, self.behind_inputs(frame),
            CompositeInputs(rad, data, cloud_map, ground, *(table_frame or (None, None))),
        )  # fmt: skip

    def _tabled(self, frame: DrawContext) -> bool:
        """Whether ``frame`` draws the march from a direction table: a fog with no clouds
        over it (the same everywhere) and no user's scene (whose distances are the pixels')."""
        c = self.clouds
        return not c.aloft and not c.uniform and frame.depth_map is None

    def _direction_table(self, frame: DrawContext):
        """A fog alone marched for a table of view directions from the camera's height
        (skydome.clouds.direction_table; TABLE_SIZE by quality, ICE_TABLE_SCALE times finer for
        diamond dust's halos): its (radiance, data) textures
        and the table's (frame, size) (u_table_frame, u_table_size). Marched afresh only when the time, the lights,
        the clouds, the ground's albedo, the height or the quality change: a frame turned or
        of another camera reads the same table."""
        lights = self.light_inputs(frame)
        key = (*self._sky_key(), self._pass_quality, round(frame.altitude_m, 3), lights)
        if self._table is not None and self._table[0] == key:
            return self._table[1:]
        air = self._air()
        size = TABLE_SIZE[self._pass_quality]
        if self.clouds.fog_ice and self._halos_drawn():  # diamond dust: halos 0.5 deg sharp
            size = (size[0] * ICE_TABLE_SCALE, size[1] * ICE_TABLE_SCALE)
        radius_km = math.sqrt(sum(v * v for v in air.camera_position_km(frame.altitude_m)))
        key_direction, _ = self.key_light(air.lights())
        frame_uniform = table_frame(key_direction, radius_km, air.bottom_radius_m / 1e3)
        directions = table_directions(size, frame_uniform)
        ctx = frame.ctx
        direction_map = ctx.texture(size, 3, directions.astype("f4").tobytes(), dtype="f4")
        try:
            view = CameraInputs((float(size[0]), float(size[1])), u_direction_map=direction_map)
            table = DrawContext(
                ctx, DirectionsCamera(directions), size, (0, 0, *size), None, view,
                frame.altitude_m, frame.basis,
            )  # fmt: skip
            rad, data = self._march_frame(table, None, 1, self._table_target(size))[:2]
        finally:
            direction_map.release()
        self._table = (key, rad, data, (frame_uniform, (float(size[0]), float(size[1]))))
        return self._table[1:]

    def _table_target(self, size: tuple[int, int]):
        """The direction table's textures (bilinear, wrapping around in azimuth) and
        framebuffer."""
        key = ("direction_table", *size)
        if key not in self._targets:
            texs, fbo = self._make_target(*size)
            for t in texs:
                t.repeat_x = True
            self._targets[key] = (texs, fbo)
        return self._targets[key]

    def _scene_transmittance(self, frame: DrawContext, data):
        """The clouds' transmittance to a user's scene as an RGBA texture of the tile (the
        march's T, read back into frame.info["transmittance"] with the air's)."""
        _, _, tw, th = frame.tile
        key = ("scene_transmittance", tw, th)
        if key not in self._targets:
            tex = frame.ctx.texture((tw, th), 4, dtype="f4")
            self._targets[key] = ((tex,), frame.ctx.framebuffer(color_attachments=[tex]))
        (tex,), fbo = self._targets[key]
        fbo.viewport = (0, 0, tw, th)
        fpass = self.full_screen_pass(
            frame.ctx, "clouds/cloud_transmittance.glsl", (CloudDataInputs,), frame.camera
        )
        fpass.draw(fbo, CloudDataInputs(data))
        return tex

    def outputs(self) -> dict:
        """The transmittance to a user's scene of the last tile (with a depth map), then
        forgotten."""
        out, self._outputs = self._outputs, {}
        return out

    @staticmethod
    def _reduced(frame: DrawContext, scale: int) -> DrawContext:
        """``frame``'s tile at 1/scale of the resolution: the camera's uniforms for a frame of
        (w, h) / scale, the tile's offset scaled (the texels' centres fall on the centres of
        the scale x scale pixel blocks they cover)."""
        x0, y0, tw, th = frame.tile
        w, h = frame.frame_size
        lw, lh = max(1, math.ceil(tw / scale)), max(1, math.ceil(th / scale))
        view = frame.camera.inputs(
            w / scale, h / scale, (x0 / scale, y0 / scale), frame.view.u_direction_map
        )
        return DrawContext(
            frame.ctx, frame.camera, (w, h), (0, 0, lw, lh), None, view, frame.altitude_m,
            frame.basis,
        )  # fmt: skip

    def inputs(self, frame: DrawContext) -> VolumeInputs | None:
        """The light shafts: the shadow length (km) of each pixel's air in the clouds' shadow
        (clouds/cloud_shafts.glsl at 1/SHAFT_SCALE of the resolution, upsampled), for the
        atmosphere's HAS_SHADOW_MAP input; none without a sunlit cloud layer."""
        if not self.clouds.aloft:  # no clouds to shade the air (a fog alone: its own march)
            return None
        refined = self._refines(frame)
        if not self.shafts and not (self._refined_shafts and refined):
            return None
        lights = self.light_inputs(frame)
        if elevation_deg(lights.u_sun_direction) < -2.0:
            return None
        x0, y0, tw, th = frame.tile
        w, h = frame.frame_size
        k = (
            INTERACTIVE_SHAFT_SCALE
            if self.quality == "interactive" and not refined
            else SHAFT_SCALE
        )
        lw, lh = max(1, math.ceil(tw / k)), max(1, math.ceil(th / k))
        ctx = frame.ctx
        small, full = self._shaft_targets(lw, lh, tw, th)
        small[1].viewport = (0, 0, lw, lh)
        view = frame.camera.inputs(
            w / k, h / k, (x0 / k, y0 / k),
            frame.view.u_direction_map,
        )  # fmt: skip
        inputs = (
            view, self._air().lookup().inputs, lights, self.cloud_inputs(u_shaft_km=SHAFT_KM),
            self.texture_inputs(),
        )  # fmt: skip
        fpass = self.full_screen_pass(
            ctx, "clouds/cloud_shafts.glsl", tuple(type(i) for i in inputs), frame.camera,
            self.defines(frame),
        )  # fmt: skip
        fpass.draw(small[1], *inputs)
        up = self.full_screen_pass(ctx, "clouds/upsample.glsl", (UpsampleInputs,), frame.camera)
        full[1].viewport = (0, 0, tw, th)
        up.draw(full[1], UpsampleInputs((lw / tw, lh / th), small[0]))
        return VolumeInputs(shadow_map=full[0])

    def _shaft_targets(self, lw: int, lh: int, tw: int, th: int):
        key = ("shafts", lw, lh, tw, th)
        if key not in self._targets:
            ctx = self.graph.ctx
            pair = []
            for w, h in ((lw, lh), (tw, th)):
                tex = ctx.texture((w, h), 2, dtype="f4")  # the length and its first moment
                tex.filter = (ctx.LINEAR, ctx.LINEAR)
                tex.repeat_x = tex.repeat_y = False
                pair.append(([tex], ctx.framebuffer(color_attachments=[tex])))
            self._targets[key] = pair
        (small_tex, small_fbo), (full_tex, full_fbo) = self._targets[key]
        return (small_tex[0], small_fbo), (full_tex[0], full_fbo)

    def _interactive_mode(self, frame: DrawContext) -> tuple[str, tuple]:
        """How the interactive mode draws this frame, and the view's key: "accumulate" (a
        jittered low-resolution march into the history), "refine" (``refine``: the view has
        settled, one full-quality march of it) or "kept" (that march, still the view's)."""
        key = (frame.camera, frame.frame_size, round(frame.altitude_m, 1), self._sky_key())
        if self._refined_key is not None and self._refined_key == key:
            return "kept", key
        if self.refine and self._settled >= SETTLE_FRAMES and self._same_history(frame):
            return "refine", key
        return "accumulate", key

    def _refines(self, frame: DrawContext) -> bool:
        """Whether this frame is the interactive mode's refined one (drawn or kept)."""
        whole = frame.tile == (0, 0, *frame.frame_size)
        if self.quality != "interactive" or not whole or not frame.camera.has_projection:
            return False
        return self._interactive_mode(frame)[0] != "accumulate"

    def _march_frame(self, frame: DrawContext, mode: str | None, scale: int, target=None):
        """The march of ``frame`` at the pass's quality (into ``target``, or the layer's
        march target of its size): (radiance, data, the scale of its texels in pixels)."""
        probe = self.sky_probe()
        cloud = self.cloud_inputs(
            u_sky_light_ratio=probe.ratio,
            u_under_sky_ratio=self._under_ratio,
            u_ambient_radiance=probe.ambient_radiance(self._air().ground_albedo()),
        )
        textures = self.texture_inputs()
        if mode == "accumulate":
            return (*self._interactive(frame, cloud, textures), scale)
        if mode == "refine":
            scale = QUALITY["full"]["scale"]
        if scale > 1:
            return (*self.march(self._reduced(frame, scale), cloud, textures), scale)
        return (*self.march(frame, cloud, textures, target=target), 1)

    def _same_history(self, frame: DrawContext) -> bool:
        """Whether the interactive history holds this view at this time."""
        return (
            self._history_camera == frame.camera
            and self._history_time == self.time_s
            and self._history_key is not None
            and self._history_key[3] == round(frame.altitude_m, 1)
        )

    def _interactive(self, frame: DrawContext, cloud: CloudInputs, textures: CloudTextures):
        """The interactive mode: the march at 1/scale of the resolution with a new sub-pixel
        and step offset each frame, blended into a reprojected history (clouds_temporal.glsl).
        Returns the accumulated (radiance, data) textures at the reduced size."""
        w, h = frame.frame_size
        scale = QUALITY["interactive"]["scale"]
        lw, lh = max(1, math.ceil(w / scale)), max(1, math.ceil(h / scale))
        n = self._frame_index
        self._frame_index += 1
        # a 4-frame rotation of sub-pixel offsets (a quarter pixel either way) and step offsets
        sub = ((0.25, 0.25), (-0.25, -0.25), (0.25, -0.25), (-0.25, 0.25))[n % 4]
        view = frame.camera.inputs(lw, lh, sub, frame.view.u_direction_map)
        small = DrawContext(
            frame.ctx, frame.camera, (lw, lh), (0, 0, lw, lh), None, view, frame.altitude_m,
            frame.basis,
        )  # fmt: skip
        jittered = replace(cloud, u_frame_jitter=(n % 4) * 0.25 + 0.125)
        cur_rad, cur_data = self.march(small, jittered, textures)
        self._interactive_sky = self._sky_key()  # the next frame of this sky reads the map
        history = self._history_targets(lw, lh)
        prev, nxt = history[n % 2], history[(n + 1) % 2]
        key = (frame.camera.model, lw, lh, round(frame.altitude_m, 1))
        camera = frame.camera
        same_view = self._history_key == key and self._history_camera == camera
        if self._history_key != key or not (camera.model == 0 or same_view):
            blend = 1.0  # no usable history: a new size, altitude or a turned fisheye
        else:
            blend = 0.25 if same_view and self._history_time == self.time_s else 0.5
        prev_cam = self._history_camera if self._history_camera is not None else camera
        temporal = self.full_screen_pass(
            frame.ctx, "clouds/clouds_temporal.glsl", (CameraInputs, TemporalInputs), camera
        )
        before = prev_cam.inputs(lw, lh)
        (nrad, ndata), fbo = nxt
        fbo.viewport = (0, 0, lw, lh)
        temporal.draw(
            fbo,
            camera.inputs(lw, lh),
            TemporalInputs(
                u_blend=blend,
                u_prev_basis=before.u_camera_basis,
                u_prev_tan_half_fov=before.u_tan_half_fov,
                u_current_radiance=cur_rad, u_current_data=cur_data,
                u_history_radiance=prev[0][0], u_history_data=prev[0][1],
            ),
        )  # fmt: skip
        self._settled = 0 if blend >= 0.5 else self._settled + 1
        self._history_key, self._history_camera, self._history_time = key, camera, self.time_s
        return nrad, ndata

    @property
    def settling(self) -> bool:
        """The interactive mode's image of a still view is still changing: a window redraws
        it until SETTLE_FRAMES frames have gone into its history and (``refine``) its
        full-quality frame has been drawn."""
        if self.quality != "interactive" or not self.clouds.aloft:
            return False  # nothing accumulated (a fog alone is drawn from its direction table)
        return self._settled < SETTLE_FRAMES or (self.refine and self._refined_key is None)

    def _history_targets(self, w: int, h: int):
        """Two (textures, framebuffer) pairs of the interactive history, ping-ponged."""
        key = ("history", w, h)
        if key not in self._targets:
            self._targets[key] = [self._make_target(w, h), self._make_target(w, h)]
        return self._targets[key]

    def _copy_behind(self, frame: DrawContext) -> None:
        copy = self.full_screen_pass(frame.ctx, "scene/copy_behind.glsl", (BehindInputs,))
        copy.draw(frame.fbo, self.behind_inputs(frame))

    def deck_census(self) -> dict:
        """What the main layer holds at the last update's time, from the column census
        (:meth:`column_optical_depths`, 64 x 64 columns over the weather tile): the mean
        optical depth of all columns, the cloudy fraction (columns above 1 % of the nominal
        optical depth) and the mean of the cloudy columns."""
        key = (self.time_s, self.clouds)
        if self._census is None or self._census[0] != key:
            tau = self.column_optical_depths(CENSUS_GRID)[..., 0]
            cloudy = tau > CLOUDY_FRACTION * max(self.clouds.nominal_optical_depth, 1e-9)
            self._census = key, {
                "cloud_optical_depth_mean": float(tau.mean()),
                "cloud_fraction": float(cloudy.mean()),
                "cloud_optical_depth_cloudy": float(tau[cloudy].mean()) if cloudy.any() else 0.0,
            }  # fmt: skip
        return dict(self._census[1])

    def info(self) -> dict:
        c = self.clouds
        info = {
            "clouds": c.preset,
            "cloud_type": c.type_value,
            "coverage": c.coverage,
            "cloud_base_m": c.base_m,
            "cloud_top_m": c.base_m + c.thickness_m,
            "cirrus": c.cirrus,
            "cloud_optical_depth": c.nominal_optical_depth,
        }
        if c.coverage > 0 and self.graph is not None:
            info.update(self.deck_census())
        return info

    def release(self) -> None:
        super().release()
        for value in self._targets.values():
            for texs, fbo in value if isinstance(value, list) else [value]:
                fbo.release()
                for t in texs:
                    t.release()
        self._targets.clear()
        self._table = None
        self._history_key = None
        for tex in self._static or ():
            tex.release()
        self._static = None
        if self._halo is not None:
            self._halo[1].release()
            self._halo = None
        if self._fog is not None:
            self._fog.release()
            self._fog = None
        if self._light_map is not None:
            release_unbound(self._light_map[2])
            release_unbound(self._light_map[1])
            self._light_map = None
        if self.weather is not None:
            self.weather.release()
            self.weather = None
        self.noise = None  # shared (cloud_noise caches it per context)


def weather_map_for(clouds: Clouds):
    """The weather map of ``clouds``: its own (a ``WeatherMap``, an image path or an array,
    whose coverage channel ``clouds.coverage`` scales), or one generated from its seed with
    its coverage, type, precipitation and cirrus (skydome.clouds.weather.WeatherMap)."""

    w = clouds.weather
    if w is None:
        return WeatherMap.generate(
            clouds.seed, tile_km=clouds.tile_km, coverage=clouds.coverage,
            cloud_type=clouds.type_value, precipitation=clouds.precipitation,
            cirrus=clouds.cirrus,
        )  # fmt: skip
    if not isinstance(w, WeatherMap):
        if isinstance(w, np.ndarray):
            w = WeatherMap.from_array(w, clouds.tile_km, cloud_type=clouds.type_value)
        else:
            w = WeatherMap.from_image(w, clouds.tile_km)
    data = w.data.copy()
    data[..., 0] *= clouds.coverage
    return WeatherMap(data, w.tile_km)


def _ms_table():

    return load_ms_table()


class _CloudySkyLight(SkyLightService):
    """The cloud layer's probe as a SkyLightService."""

    def __init__(self, layer: CloudLayer):
        self._layer = layer

    def ambient_radiance(self) -> tuple[float, float, float, float]:
        layer = self._layer
        if layer.clouds.empty:
            return (0.0, 0.0, 0.0, 0.0)
        probe = layer.sky_probe()
        return tuple(float(v) for v in probe.ambient_radiance(layer._air().ground_albedo()))
