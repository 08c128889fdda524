"""The frame graph: the layers of a sky drawn into float textures in physical order.

For each tile of a frame (one tile up to TILE_SIZE on a side):

1. **space**: the layers of light from beyond the atmosphere (Sun, Moon, stars, planets)
   add their radiance, unattenuated, into target A; the smooth ones (airglow, zodiacal
   light, the Milky Way: ``Layer.smooth_deg``) into a target of 1/f the resolution when
   the camera's pixels are f times finer than their detail (f <= MAX_SMOOTH_FACTOR), read
   bilinearly by the first volume layer (or added by the graph);
2. **volume**: each volume layer (the atmosphere, later clouds) reads the light behind it
   and writes ``behind * transmittance + in-scattered`` into the other target (ping-pong);
3. **post** (whole frames): the GPU exposure pass, then the display passes: night vision
   (``display.night_vision``: what a dark-adapted eye sees, HDR to HDR, off by default),
   the tone map, and the overlays (``display.overlays``: lines, labels, a grid, drawn over
   the 8-bit image). The display passes change the image only, never ``Frame.data``.

``render`` reads the float frame back once (and, if asked, the tone-mapped image);
``draw`` tone-maps into a caller's framebuffer and reads nothing back. Every front end
(command line, notebook, viewer) runs this one graph.
"""

from __future__ import annotations

import contextlib
import math
import time
from dataclasses import dataclass

import numpy as np

from skydome.core.basis import SpectralBasis
from skydome.core.cameras import (
    MAX_SIDE,
    Camera,
    DirectionsCamera,
    EquirectCamera,
    FisheyeCamera,
    PerspectiveCamera,
    effective_altitude_m,
)
from skydome.core.frame import Frame
from skydome.core.layer import STAGES, DrawContext, Layer
from skydome.core.services import AirService, VolumeInputs
from skydome.core.tiles import (
    TILE_SIZE,
    block_mean,
    check_supersample,
    frame_tiles,
    input_image,
    input_texture,
    repeat_pixels,
)
from skydome.display.exposure import (
    DEFAULT_KEY,
    DEFAULT_METERING,
    check_metering,
    eye_key,
    metered_luminance,
    metering_weighting,
    scale_to_ev100,
)
from skydome.display.glare import DEFAULT_GLARE, GpuGlare, check_glare, eye_magnification
from skydome.display.gpu_exposure import GpuExposure
from skydome.display.gpu_tonemap import GpuToneMapper, gpu_tonemap, upload_frame
from skydome.display.night_vision import NightVision, leaves_frame
from skydome.display.overlays import Overlays, parse_overlays
from skydome.errors import ParameterError
from skydome.gpu import FullscreenPass, shared_context
from skydome.gpu.inputs import ShaderInputs
from skydome.gpu.textures import release_all
from skydome.physics.constants import M_PER_KM
from skydome.spectra.grids import wavelengths


@dataclass(frozen=True)
class SmoothInputs(ShaderInputs):
    """``scene/add_smooth.glsl``: the smooth space layers' light at a reduced resolution and
    where a tile's pixels fall in it (``common/behind.glsl``)."""

    u_behind_smooth: object
    u_smooth_map: tuple[float, float, float, float]


@dataclass
class TileInputs:
    """Per-pixel inputs of one tile, as textures of the tile's size (GL rows): the view
    directions of a DirectionsCamera, a user's scene distances (km) and a user's shadow
    lengths (km)."""

    direction_map: object = None
    depth_map: object = None
    shadow_map: object = None

    def textures(self) -> list:
        return [t for t in (self.direction_map, self.depth_map, self.shadow_map) if t is not None]


#: The largest reduction of the smooth space layers' resolution (per axis).
MAX_SMOOTH_FACTOR = 4
#: Frames with more pixels than this (4096 x 4096) are tone-mapped without glare: the pass
#: holds the whole frame and its pyramid (RGBA32F) on the GPU.
MAX_GLARE_PIXELS = 1 << 24


def smooth_factor(camera: Camera, frame_size: tuple[int, int], smooth_deg: float) -> int:
    """How many times coarser (per axis) light with no detail below ``smooth_deg`` may be
    drawn than the frame: the number of the frame's pixels (at its centre, where a
    perspective or equirect pixel is largest) that fit in ``smooth_deg``, 1 to
    MAX_SMOOTH_FACTOR. 1 for cube maps (faces that touch in the sky lie apart in the strip)
    and direction maps."""
    if not isinstance(camera, (PerspectiveCamera, FisheyeCamera, EquirectCamera)):
        return 1
    pixel_deg = math.degrees(camera.pixel_angle(*frame_size))
    return int(min(max(math.floor(smooth_deg / pixel_deg), 1), MAX_SMOOTH_FACTOR))


class FrameGraph:
    """Layers in drawing order within their stage, and the targets they draw into.

    Args:
        layers: the layers (space layers first, then volume layers from far to near; the
            order within a stage is the order given).
        ctx: a moderngl context (default: the shared headless one).
        basis: the output channels (default: the atmosphere layer's, else RGBS at the 16
            accurate wavelengths).
        solar_scale: the Sun's irradiance relative to the tabulated spectrum (default: the
            air's, ``AirService.solar_scale``, else 1).

    A graph is what its layers' ``prepare`` get (``skydome.core.layer.LayerHost``): the
    context, the spectral basis, and the services the layers offer one another.
    """

    def __init__(
        self,
        layers: list[Layer],
        *,
        ctx=None,
        basis: SpectralBasis | None = None,
        solar_scale: float | None = None,
    ):
        self.ctx = ctx or shared_context()
        self.make_current()
        names = [layer.name for layer in layers]
        if len(set(names)) != len(names):
            raise ParameterError(f"layer names must be unique, got {names}")
        for layer in layers:
            if layer.stage not in STAGES:
                raise ParameterError(f"layer {layer.name!r} has unknown stage {layer.stage!r}")
        self.layers = list(layers)
        self.solar_scale = 1.0 if solar_scale is None else float(solar_scale)
        self._targets: dict[tuple[int, int], tuple] = {}
        self._staging: dict[tuple[int, int], np.ndarray] = {}
        self._post = None
        self._exposure = None
        self._night_vision = None
        self._eye_colour = None
        self._glare = None
        self._overlays = None
        self._smooth_pass = None
        #: The exposure scale (m^2/cd) of the last :meth:`display_image`.
        self.last_display_scale: float | None = None
        #: Display settings (see :meth:`set_display`).
        self.night_vision = False
        self.night_vision_seed = 0
        self.overlays: tuple[str, ...] = ()
        #: None, or an object whose ``section(name)`` is a context manager wrapped around
        #: each pass of a frame (a layer's draw, the exposure, the display passes): the
        #: viewer's GPU timer queries (``viewer.frame_timer``).
        self.profiler = None
        #: Counts the changes of the targets' contents (a tile drawn, targets freed): a
        #: front end that keeps a drawn frame's texture (the viewer's static frames) knows it
        #: still holds that frame while the count has not moved.
        self.generation = 0
        self.basis = basis
        self._released = False
        for layer in self.layers:  # a volume layer may bring the spectral basis (its tables)
            layer.prepare(self)
        self.basis = basis or self._default_basis()
        if solar_scale is None:
            air = self.find_service(AirService)
            self.solar_scale = 1.0 if air is None else float(air.solar_scale)

    def _default_basis(self) -> SpectralBasis:
        for layer in self.layers:
            basis = getattr(layer, "spectral_basis", None)
            if basis is not None:
                return basis

        return SpectralBasis.for_wavelengths(wavelengths("accurate"))

    def find_service(self, kind: type):
        """The first service of type ``kind`` a layer of this graph offers, or None."""
        for layer in self.layers:
            for service in layer.services():
                if isinstance(service, kind):
                    return service
        return None

    def service(self, kind: type):
        """The service of type ``kind`` a layer of this graph offers; a ParameterError
        naming it when none does (e.g. clouds without an atmosphere)."""
        found = self.find_service(kind)
        if found is None:
            raise ParameterError(
                f"no layer of this sky offers {kind.__name__} (its layers: "
                f"{', '.join(la.name for la in self.layers)})"
            )
        return found

    def __getitem__(self, name: str) -> Layer:
        for layer in self.layers:
            if layer.name == name:
                return layer
        raise KeyError(name)

    def active(self, stage: str) -> list[Layer]:
        return [layer for layer in self.layers if layer.enabled and layer.stage == stage]

    # ------------------------------------------------------------------ targets

    def _target(self, w: int, h: int):
        """Two RGBA32F textures with framebuffers (sharing a depth buffer) for one tile size."""
        key = (w, h)
        if key not in self._targets:
            depth = self.ctx.depth_renderbuffer((w, h))
            texs = [self.ctx.texture((w, h), 4, dtype="f4") for _ in range(2)]
            fbos = [
                self.ctx.framebuffer(color_attachments=[t], depth_attachment=depth) for t in texs
            ]
            self._targets[key] = (texs, fbos, depth)
        return self._targets[key]

    # ------------------------------------------------------------------ drawing

    def _section(self, name: str):
        """The profiler's section ``name`` (a no-op context without a profiler)."""
        if self.profiler is None:
            return contextlib.nullcontext()
        return self.profiler.section(name)

    def release_targets(self, keep: tuple[int, int] | None = None) -> None:
        """Free the float targets of every tile size but ``keep`` (w, h), and the reduced
        targets of the smooth layers (made again at the next frame): a window that resizes
        keeps only its current size's."""
        self.generation += 1
        for key in [k for k in self._targets if k != keep]:
            texs, fbos, depth = self._targets.pop(key)
            release_all(*fbos, *texs, depth)
        for key in [k for k in self._staging if k != keep]:
            del self._staging[key]

    def make_current(self) -> None:
        """Make this graph's context the thread's current one. moderngl makes a context
        current when it is made, and GL calls go to the current one: after a context of
        its own (another sky's, a window's) a graph would otherwise draw into that one
        (a new sky's tables and passes made there drew a sky 500 times too dark). Nothing
        once the context itself is released."""
        if type(self.ctx.mglo).__name__ != "InvalidObject":
            self.ctx.__enter__()

    def update(self, state) -> None:
        self.make_current()
        for layer in self.layers:
            if layer.enabled:
                layer.update(state)

    def draw_tile(
        self,
        camera: Camera,
        frame_size: tuple[int, int],
        tile: tuple[int, int, int, int],
        altitude_m: float,
        inputs: TileInputs | None = None,
        pixel_scale: int = 1,
    ):
        """Draw every enabled layer into one tile; returns the texture holding it (GL rows).
        ``inputs``: the tile's per-pixel inputs (textures of this tile's size);
        ``pixel_scale``: a supersampled frame's n (``DrawContext.pixel_scale``)."""
        inputs = inputs or TileInputs()
        x0, y0, tw, th = tile
        self.generation += 1
        texs, fbos, _ = self._target(tw, th)
        view = camera.inputs(*frame_size, (x0, y0), inputs.direction_map)
        ctx = self.ctx

        def context(i: int, behind=None, volume: VolumeInputs | None = None) -> DrawContext:
            fbos[i].viewport = (0, 0, tw, th)
            return DrawContext(
                ctx, camera, frame_size, tile, fbos[i], view, altitude_m, self.basis, behind,
                volume_inputs=volume, target=texs[i], depth_map=inputs.depth_map,
                pixel_scale=pixel_scale,
            )  # fmt: skip

        current = 0
        fbos[current].clear(0.0, 0.0, 0.0, 0.0, depth=1.0, viewport=(0, 0, tw, th))
        space = self.active("space")
        # The smooth layers that this camera's pixels oversample, drawn together at the
        # smallest reduction any of them allows; the others at full resolution.
        factors = {
            la.name: smooth_factor(camera, frame_size, la.smooth_deg)
            for la in space
            if la.smooth_deg is not None
        }
        smooth_layers = [la for la in space if factors.get(la.name, 1) > 1]
        f = min((factors[la.name] for la in smooth_layers), default=1)
        ctx.enable(ctx.BLEND)
        ctx.blend_func = ctx.ONE, ctx.ONE
        try:
            for layer in space:
                if layer not in smooth_layers:
                    with self._section(layer.name):
                        layer.draw(context(current))
            smooth = self._draw_smooth(smooth_layers, f, camera, frame_size, tile, altitude_m)
            volume = self.active("volume")
            if smooth is not None and not (volume and volume[0].merges_smooth):
                self._add_smooth(fbos[current], (tw, th), *smooth)
                smooth = None
        finally:
            ctx.disable(ctx.BLEND)
            ctx.blend_func = ctx.ONE, ctx.ZERO
        # What the volume layers give one another for this tile (e.g. light shafts), over a
        # user's own shadow lengths.
        given = VolumeInputs(shadow_map=inputs.shadow_map)
        for layer in volume:
            offered = layer.inputs(context(current))
            if offered is not None:
                given = given.merge(offered)
        for i, layer in enumerate(volume):
            # A volume layer writes every pixel of its target (its light and what it lets
            # through from behind): no clear.
            nxt = 1 - current
            frame = context(nxt, behind=texs[current], volume=given)
            if i == 0 and smooth is not None:
                frame.behind_smooth, frame.smooth_map = smooth
            with self._section(layer.name):
                layer.draw(frame)
            current = nxt
        return texs[current]

    def _draw_smooth(self, layers, f: int, camera, frame_size, tile, altitude_m):
        """Draw the smooth space layers at 1/f of the resolution, with a margin of one
        texel around the tile (so bilinear reads at its edges see their neighbours);
        returns (texture, smooth_map) for common/behind.glsl, or None."""
        if not layers:
            return None
        w, h = frame_size
        x0, y0, tw, th = tile
        sw, sh = math.ceil(tw / f) + 2, math.ceil(th / f) + 2
        key = ("smooth", sw, sh)
        if key not in self._targets:
            tex = self.ctx.texture((sw, sh), 4, dtype="f4")
            tex.filter = (self.ctx.LINEAR, self.ctx.LINEAR)
            tex.repeat_x = tex.repeat_y = False
            self._targets[key] = ([tex], [self.ctx.framebuffer(color_attachments=[tex])], None)
        (tex,), (fbo,), _ = self._targets[key]
        fbo.clear(0.0, 0.0, 0.0, 0.0, viewport=(0, 0, sw, sh))
        fbo.viewport = (0, 0, sw, sh)
        # The reduced frame: u_resolution exactly 1/f of the frame's, so a reduced pixel's
        # centre sees the direction of the frame's point f times its coordinates.
        view = camera.inputs(w / f, h / f, (x0 / f - 1.0, y0 / f - 1.0))
        reduced = DrawContext(
            self.ctx, camera, (math.ceil(w / f), math.ceil(h / f)),
            (x0 // f - 1, y0 // f - 1, sw, sh), fbo, view, altitude_m, self.basis,
        )  # fmt: skip
        with self._section("smooth"):
            for layer in layers:
                layer.draw(reduced)
        # A tile pixel p (gl_FragCoord) lies at p / f + 1 texels in the reduced target.
        return tex, (1.0 / (f * sw), 1.0 / (f * sh), 1.0 / sw, 1.0 / sh)

    def _add_smooth(self, fbo, size, texture, smooth_map) -> None:
        """Add the reduced smooth light to ``fbo`` (blending ONE, ONE is on)."""
        if self._smooth_pass is None:
            self._smooth_pass = FullscreenPass(
                self.ctx, "scene/add_smooth.glsl", inputs=(SmoothInputs,)
            )
        fbo.viewport = (0, 0, *size)
        self._smooth_pass.draw(fbo, SmoothInputs(texture, smooth_map))

    def frame_texture(self, state, camera: Camera, width: int, height: int, *, altitude_m: float):
        """Draw a whole frame (one tile: at most TILE_SIZE on a side) and return the float
        texture holding it, still on the GPU (valid until the next draw of this size): for
        front ends that tone-map or measure it there (time-lapses, windows)."""
        self.make_current()
        w, h = camera.frame_size(width, height)
        if max(w, h) > TILE_SIZE or isinstance(camera, DirectionsCamera):
            raise ParameterError(
                f"a frame kept on the GPU must be one tile (at most {TILE_SIZE} pixels a side, "
                "not a DirectionsCamera); use render()"
            )
        self.update(state)
        return self.draw_tile(camera, (w, h), (0, 0, w, h), altitude_m)

    def render(
        self,
        state,
        camera: Camera,
        width: int,
        height: int,
        *,
        altitude_m: float,
        exposure: str | float | None = None,
        compensation_ev: float = 0.0,
        tonemap: str | None = None,
        depth_m=None,
        shadow_length_m=None,
        metering: str = DEFAULT_METERING,
        glare: str | None = DEFAULT_GLARE,
        supersample: int = 1,
    ) -> Frame:
        """Draw a whole frame and read it back: a Frame in cd/m^2.

        ``exposure``: None (no exposure chosen), ``"auto"`` (the GPU log-average, key 0.18)
        or an exposure scale (m^2/cd); with ``tonemap`` (an operator name) the frame also
        carries ``frame.image``, the uint8 sRGB image tone-mapped on the GPU.
        ``depth_m``: an (H, W) image of distances (m) to a user's scene along each ray
        (<= 0 or +inf where there is none): the frame holds the light scattered in front of
        it, and ``frame.info["transmittance"]`` the (H, W, 3) RGB transmittance to it
        (composite = scene * transmittance + frame). ``shadow_length_m``: an (H, W) image of
        the length (m) of each ray, from the camera, in an occluder's shadow (light shafts;
        +inf: in shadow all along).
        ``metering`` (``display.exposure.METERINGS``): how ``"auto"`` measures the frame;
        ``eye`` also shows a dark-adapted eye's colours (the mesopic blend of night vision,
        without its blur and noise) below 5 cd/m^2. ``glare`` ("off", "eye", "lens"): the
        point spread function on the image (``display.glare``); ``Frame.data`` is the same.
        ``supersample`` n > 1: n x n rays a pixel (the frame drawn at n times the size, each
        pixel the mean of its n x n: antialiased, n^2 times the work); the depth and shadow
        images stay one value a pixel.
        """
        self.make_current()
        metering = check_metering(metering)
        glare = check_glare(glare)
        n = check_supersample(supersample)
        if n > 1 and isinstance(camera, DirectionsCamera):
            raise ParameterError(
                "supersample needs a camera that makes its rays; a DirectionsCamera's are "
                "given one a pixel (pass more directions instead)"
            )
        w, h = camera.frame_size(width, height)
        used_altitude_m = effective_altitude_m(altitude_m)
        inputs = {}
        if isinstance(camera, DirectionsCamera):
            inputs["direction_map"] = camera.view_directions.astype(np.float32)
        if depth_m is not None:
            inputs["depth_map"] = input_image("depth_m", depth_m, (w, h), 1 / M_PER_KM)
        if shadow_length_m is not None:
            # +inf: the whole ray is in shadow (1e30 km is past the end of any ray).
            inputs["shadow_map"] = input_image(
                "shadow_length_m", shadow_length_m, (w, h), 1 / M_PER_KM, posinf=1e30
            )
        if n > 1:
            if max(w, h) * n > MAX_SIDE:
                raise ParameterError(
                    f"supersample {n} would draw {w * n}x{h * n} pixels, more than {MAX_SIDE} "
                    "a side: ask for fewer rays a pixel or a smaller frame"
                )
            inputs = {name: repeat_pixels(image, n) for name, image in inputs.items()}
            drawn = camera.frame_size(w * n, h * n)
            if drawn != (w * n, h * n):  # every camera scales so; a guard for new ones
                raise ParameterError(f"camera {camera.name} cannot draw {n}x its frame")
            w, h = drawn
        t0 = time.perf_counter()
        self.update(state)
        tile_side = min(TILE_SIZE, max(w, h))
        data = np.empty((h, w, 4), np.float32)
        outputs: dict[str, np.ndarray] = {}
        last = None
        tiles = list(frame_tiles(w, h, tile_side))
        for x0, y0, tw, th in tiles:
            rows = slice(h - y0 - th, h - y0)  # the tile's rows in the top-first frame
            tile_inputs = TileInputs(
                **{
                    name: input_texture(self.ctx, image[rows, x0 : x0 + tw])
                    for name, image in inputs.items()
                }
            )
            try:
                last = self.draw_tile(
                    camera, (w, h), (x0, y0, tw, th), altitude_m, tile_inputs, pixel_scale=n
                )
                data[rows, x0 : x0 + tw] = self._read_tile(last, tw, th)
                # a name several volume layers give is the product of theirs (the air's
                # and the clouds' transmittances to a user's scene)
                given: set[str] = set()
                for layer in self.active("volume"):
                    for name, tex in layer.outputs().items():
                        out = outputs.setdefault(name, np.empty((h, w, 4), np.float32))
                        tile = self._read_tile(tex, tw, th)
                        if name in given:
                            out[rows, x0 : x0 + tw] *= tile
                        else:
                            out[rows, x0 : x0 + tw] = tile
                        given.add(name)
            finally:
                for tex in tile_inputs.textures():
                    tex.release()
        if n > 1:
            data = block_mean(data, n)
            outputs = {name: block_mean(image, n) for name, image in outputs.items()}
            w, h = w // n, h // n
        # the frame as one drawn texture (its exposure measured there), or only as `data`
        last = last if len(tiles) == 1 and n == 1 else None
        render_ms = (time.perf_counter() - t0) * 1e3
        info = {
            "render_ms": render_ms,
            "layers": [la.name for la in self.layers if la.enabled],
            "camera": camera.name,
            "altitude_m": used_altitude_m,
        }
        if n > 1:
            info["supersample"] = n
        if used_altitude_m != float(altitude_m):  # raised to the lowest camera height
            info["altitude_requested_m"] = float(altitude_m)
        for layer in self.layers:
            if layer.enabled:
                info.update(layer.info())
        if "transmittance" in outputs:
            info["transmittance"] = outputs["transmittance"][..., :3]
        frame = Frame(data, info)
        weighting = metering_weighting(metering, _field_deg(camera))
        scale, adapted = self._exposure_scale(
            exposure, compensation_ev, last, data, metering, weighting
        )
        if tonemap is not None:
            if scale is None:
                raise ParameterError("a tone-mapped image needs an exposure ('auto' or a scale)")
            # The exposure pass has measured the frame already when it set an auto exposure.
            measured = exposure == "auto" and last is not None and weighting in ("average", "eye")
            if glare != "off" and w * h > MAX_GLARE_PIXELS:
                # one texture of the whole frame and its pyramid: not for giant frames
                info["glare_skipped"] = f"the frame has more than {MAX_GLARE_PIXELS} pixels"
                glare = "off"
            auto_key = None
            if exposure == "auto" and metering == "eye":
                auto_key = 2.0**compensation_ev * eye_key(adapted)
            frame.image, scale = self._display_image(
                last if last is not None else data, state, camera, (w, h), tonemap, scale, measured,
                metering=metering, glare=glare, adaptation=adapted, auto_key=auto_key,
            )  # fmt: skip
            info["tonemap"] = tonemap
            info["metering"] = metering
            info["glare"] = glare
            if self.night_vision:
                info["night_vision"] = True
            if self.overlays:
                info["overlays"] = list(self.overlays)
        if scale is not None:
            info["exposure_ev100"] = scale_to_ev100(scale)
        return frame

    def _read_tile(self, texture, tw: int, th: int) -> np.ndarray:
        """A tile's float texture read back, row 0 at the top (through a staging array kept
        per size: a fresh bytes object per read costs ~5x more above glibc's 32 MB mmap
        threshold, and page faults cost more than reads)."""
        staging = self._staging.get((tw, th))
        if staging is None:
            staging = self._staging[(tw, th)] = np.empty((th, tw, 4), np.float32)
        texture.read_into(staging, alignment=1)
        return staging[::-1]

    def display_image(
        self, source, state, camera, size, tonemap: str, scale: float, *,
        metering: str = DEFAULT_METERING, glare: str | None = DEFAULT_GLARE,
        adaptation: float | None = None, compensation_ev: float = 0.0,
    ):  # fmt: skip
        """The 8-bit image (uint8 (H, W, 3), row 0 at the top) of a frame texture (GL rows,
        e.g. :meth:`frame_texture`'s) at a fixed exposure ``scale`` (m^2/cd): glare, the
        eye's colours (metering ``eye``) or night vision, the tone map and the overlays, as
        :meth:`render` makes ``Frame.image`` (for time-lapses). With metering ``eye`` and an
        ``adaptation`` luminance (cd/m^2, an adapting eye's), the exposure is the eye's key
        of it over the mesopic adaptation luminance, as ``render`` chooses it (``scale`` is
        then unused). :attr:`last_display_scale` holds the scale used (m^2/cd)."""
        self.make_current()
        metering = check_metering(metering)
        auto_key = None
        if metering == "eye" and adaptation is not None:
            auto_key = 2.0**compensation_ev * eye_key(adaptation)
        image, self.last_display_scale = self._display_image(
            source, state, camera, size, tonemap, scale, metering=metering,
            glare=check_glare(glare), adaptation=adaptation, auto_key=auto_key,
        )  # fmt: skip
        return image

    def _display_image(
        self, source, state, camera, size, tonemap: str, scale: float, measured: bool = False,
        *, metering: str = "average", glare: str = "off", adaptation: float | None = None,
        auto_key: float | None = None,
    ):  # fmt: skip
        """The 8-bit image of a frame (a texture in GL rows, or the read-back frame), and
        the exposure scale used: glare, night vision (or the eye's colours), tone map and
        overlays on the GPU, one read-back. ``auto_key``: the exposure is ``auto_key`` over
        the mesopic adaptation luminance the eye's pass measures (metering ``eye``)."""

        overlays = self._overlay_pass(state)
        eye = self.night_vision or metering == "eye"
        if not eye and overlays is None and glare == "off":
            return gpu_tonemap(source, tonemap, scale, ctx=self.ctx), scale
        owned = None
        if isinstance(source, np.ndarray):
            source = owned = upload_frame(self.ctx, source)
        try:
            texture, halo, mesopic = self._glare_and_eye(
                source, state, camera, size, glare, eye=eye, measured=measured,
                adaptation=adaptation,
            )  # fmt: skip
            if eye and auto_key is not None:
                nv = self._eye_pass(colour_only=not self.night_vision)
                scale = auto_key / nv.last_state["lmes"]
            draw = None if overlays is None else (lambda fbo, s: overlays.draw(fbo, camera, s))
            return gpu_tonemap(
                texture, tonemap, scale, ctx=self.ctx, overlay=draw, glare_halo=halo,
                mesopic=mesopic,
            ), scale  # fmt: skip
        finally:
            if owned is not None:
                owned.release()

    def _glare_and_eye(
        self, texture, state, camera, size, glare: str, *, eye: bool, measured: bool,
        adaptation: float | None,
    ):  # fmt: skip
        """(the texture the tone map reads, the glare it adds as it reads it: a GlareHalo
        or None, the eye's colours it applies after: a MesopicBlend or None). The eye's
        colours alone (metering ``eye`` without night vision) at a known ``adaptation``
        are a blend the tone map applies, measured on the frame with its halo: no pass over
        the frame but the tone map's. Else, when nothing after the glare reads the glared
        frame (no eye pass, or one that leaves the frame as it is at a photopic
        ``adaptation``: ``display.night_vision.leaves_frame``), the tone map adds the halo;
        else the glared frame is made and goes through the eye's pass (``_eye``)."""
        known = adaptation is not None
        if eye and known and not self.night_vision:
            halo = self._glare_halo(texture, camera, size, glare)
            mesopic = self._eye_pass(colour_only=True).colours(
                texture, size, adaptation=adaptation, glare_halo=halo
            )
            return texture, halo, mesopic
        halo = None
        if eye and not (known and leaves_frame(adaptation)):
            shown = self._glared(texture, camera, size, glare)
        else:  # the eye's pass, if any, runs no pass: it sets its state (the exposure's key)
            shown, halo = texture, self._glare_halo(texture, camera, size, glare)
        if eye:
            shown = self._eye(
                shown, state, camera, size, measured=measured, adaptation=adaptation,
                colour_only=not self.night_vision,
            )  # fmt: skip
        return shown, halo, None

    def _glared(self, texture, camera, size, glare: str):
        """``texture`` with the halo of ``glare`` added (post/glare_composite.glsl), or as
        it is without one (see ``_glare_halo``)."""
        halo = self._glare_halo(texture, camera, size, glare)
        if halo is None:
            return texture
        with self._section("glare"):
            return self._glare.composite(texture, size, halo)

    def _glare_halo(self, texture, camera, size, glare: str):
        """The halo of ``glare`` (display.glare) over ``texture``, not yet added; None when
        off or for a cube map's strip or a direction map (their neighbouring pixels need
        not be neighbours in the sky)."""
        if glare == "off" or not isinstance(
            camera, (PerspectiveCamera, FisheyeCamera, EquirectCamera)
        ):
            return None
        if self._glare is None:
            self._glare = GpuGlare(self.ctx)
        # the eye's halo in the angles it sees: a narrow field's magnified sky (display.glare)
        magnification = eye_magnification(_field_deg(camera)) if glare == "eye" else 1.0
        with self._section("glare"):
            return self._glare.halo(
                texture, size, pixel_angle_rad=camera.pixel_angle(*size) * magnification,
                glare=glare,
            )  # fmt: skip

    def _exposure_scale(
        self,
        exposure,
        compensation_ev,
        texture,
        data,
        metering: str = "average",
        weighting: str | None = None,
    ) -> tuple[float | None, float | None]:
        """(exposure scale, metered luminance): the scale (m^2/cd, compensation included;
        None without an exposure) and, for ``"auto"``, the frame's luminance (cd/m^2) under
        ``metering`` (the whole frame's for ``eye``, whose key :func:`eye_key` follows it)."""
        if exposure is None:
            return None, None
        if isinstance(exposure, str):
            if exposure != "auto":
                raise ParameterError(f"exposure {exposure!r} must be 'auto' or a scale in m^2/cd")
            weighting = weighting or metering  # the weights measured with (the key: metering's)
            if texture is None:  # several tiles: the same average over the read-back frame
                lum = metered_luminance(data, weighting)
            else:
                exposure_pass = self.exposure_pass()
                exposure_pass.measure(texture, weighting)
                lum = exposure_pass.read()
            key = eye_key(lum) if metering == "eye" else DEFAULT_KEY
            return 2.0**compensation_ev * key / lum, lum
        return float(exposure) * 2.0**compensation_ev, None

    def exposure_pass(self):
        if self._exposure is None:
            self._exposure = GpuExposure(self.ctx)
        return self._exposure

    def draw(
        self,
        state,
        framebuffer,
        camera: Camera,
        *,
        altitude_m: float,
        size: tuple[int, int] | None = None,
        exposure: str | float = "auto",
        compensation_ev: float = 0.0,
        tonemap: str = "filmic",
        measure: bool = False,
        read_back: bool = False,
        texture=None,
        metering: str = DEFAULT_METERING,
        glare: str | None = DEFAULT_GLARE,
        adaptation: float | None = None,
    ) -> float | None:
        """Draw the frame into ``framebuffer`` (a moderngl framebuffer, e.g. a window's
        ``ctx.screen``), tone-mapped, with no read-back. ``size`` defaults to the
        framebuffer's viewport size. One tile: the frame must fit GL's limits. With a fixed
        ``exposure`` and ``measure``, the exposure pass measures the frame all the same
        (``exposure_pass().read()``: an eye adapting over time reads it). With ``"auto"``
        and ``read_back``, the measured log-average is read back (one texel) and applied
        as a fixed scale: the same exposure, without the per-pixel lookup of the
        AUTO_EXPOSURE tone map (which costs a CPU rasterizer more than the read-back).
        ``texture``: the float frame of ``state`` and ``camera`` at this size, drawn already
        (:meth:`frame_texture`): only the post passes run (a viewer's static view shown at a
        new exposure). ``metering`` and ``glare`` as in :meth:`render`: a metering other
        than ``average`` reads the measure back (one texel). ``adaptation``: with metering
        ``eye``, an adapting eye's luminance (cd/m^2): the exposure is then the eye's key of
        it over the mesopic adaptation luminance (``exposure`` unused), as in
        :meth:`display_image`.
        Returns the exposure scale used (m^2/cd) when it is known on the CPU, else None."""
        self.make_current()
        metering = check_metering(metering)
        glare = check_glare(glare)
        w, h = size or tuple(framebuffer.viewport[2:]) or framebuffer.size
        if texture is None:
            self.update(state)
            texture = self.draw_tile(camera, (w, h), (0, 0, w, h), altitude_m)
        if self._post is None:
            self._post = GpuToneMapper(self.ctx, quantize=False)
        weighting = (
            "average" if exposure != "auto" else metering_weighting(metering, _field_deg(camera))
        )
        if exposure == "auto" or measure:
            with self._section("exposure"):
                self.exposure_pass().measure(texture, weighting)
        scale = None
        adapted = adaptation if metering == "eye" else None
        eye = self.night_vision or metering == "eye"
        if exposure == "auto" and (read_back or metering != "average"):
            adapted = self.exposure_pass().read()
            key = eye_key(adapted) if metering == "eye" else DEFAULT_KEY
            exposure = key / adapted
            measure = weighting in ("average", "eye")  # the pass holds this frame's average
        with self._section("display"):
            shown, halo, mesopic = self._glare_and_eye(
                texture, state, camera, (w, h), glare, eye=eye,
                measured=measure or exposure == "auto", adaptation=adapted,
            )  # fmt: skip
            if exposure == "auto":
                key = 2.0**compensation_ev * DEFAULT_KEY
                self._post.draw(
                    shown, framebuffer, (w, h), tonemap, key,
                    auto_exposure=self.exposure_pass(), glare_halo=halo, mesopic=mesopic,
                )  # fmt: skip
            else:
                scale = float(exposure) * 2.0**compensation_ev
                if adapted is not None and metering == "eye":
                    nv = self._eye_pass(colour_only=not self.night_vision)
                    scale = 2.0**compensation_ev * eye_key(adapted) / nv.last_state["lmes"]
                self._post.draw(
                    shown, framebuffer, (w, h), tonemap, scale, glare_halo=halo,
                    mesopic=mesopic,
                )  # fmt: skip
            overlays = self._overlay_pass(state)
            if overlays is not None:
                overlays.draw(framebuffer, camera, (w, h))
        return scale

    # ------------------------------------------------------------------ display passes

    def set_display(
        self, *, night_vision: bool | None = None, overlays=None, seed: int | None = None
    ) -> None:
        """Display settings: ``night_vision`` (the eye's night vision on the image),
        ``overlays`` (names from ``skydome.display.overlays.OVERLAYS`` or a comma list),
        ``seed`` (the night-vision noise)."""
        if night_vision is not None:
            self.night_vision = bool(night_vision)
        if seed is not None:
            self.night_vision_seed = int(seed)
            if self._night_vision is not None:
                self._night_vision.release()
                self._night_vision = None
        if overlays is not None:
            names: tuple[str, ...] = ()
            if overlays:
                names = parse_overlays(overlays)
            if names != self.overlays and self._overlays is not None:
                self._overlays.release()
                self._overlays = None
            self.overlays = names

    def _eye_pass(self, colour_only: bool) -> NightVision:
        """The eye's pass: its colours alone (the eye metering's) or night vision."""
        if colour_only:
            if self._eye_colour is None:
                self._eye_colour = NightVision(self.ctx, noise=False, acuity=False)
            return self._eye_colour
        if self._night_vision is None:
            self._night_vision = NightVision(self.ctx, seed=self.night_vision_seed)
        return self._night_vision

    def _eye(
        self, texture, state, camera: Camera, size: tuple[int, int], *, measured: bool = False,
        adaptation: float | None = None, colour_only: bool = False,
    ):  # fmt: skip
        """``texture`` through the night-vision pass (``colour_only``: its mesopic colours
        alone, no blur or noise: the eye metering's). The adaptation is ``adaptation``
        (cd/m^2) or the frame's own log-average luminance, measured on the GPU (already,
        when ``measured``: the exposure pass holds this texture's average)."""
        nv = self._eye_pass(colour_only)
        meter = self.exposure_pass()
        if adaptation is not None:
            meter = adaptation
        elif not measured:
            meter.measure(texture)
        # Seconds of the UTC day: drives the temporal noise (same time, same image).
        time_s = 0.0 if state.time is None else float(state.time.jd_utc - 0.5) % 1.0 * 86400.0
        return nv.apply(
            texture,
            size,
            pixel_angle_rad=camera.pixel_angle(*size),
            adaptation=meter,
            time_s=time_s,
        )

    def _overlay_pass(self, state):
        """The overlays, updated for ``state``; None when there are none."""
        if not self.overlays:
            return None

        if self._overlays is None:
            self._overlays = Overlays(self.ctx, self.overlays)
        self._overlays.update(state)
        return self._overlays

    def release(self) -> None:
        """Free the targets, the post passes and every layer's GPU resources."""
        self.make_current()
        self.generation += 1
        for texs, fbos, depth in self._targets.values():
            release_all(*fbos, *texs, depth)
        self._targets.clear()
        self._staging.clear()
        for obj in (
            self._post,
            self._exposure,
            self._night_vision,
            self._eye_colour,
            self._glare,
            self._overlays,
            self._smooth_pass,
        ):
            if obj is not None:
                obj.release()
        self._post = self._exposure = self._night_vision = self._overlays = None
        self._eye_colour = self._glare = None
        self._smooth_pass = None
        for layer in self.layers:
            layer.release()


def _field_deg(camera) -> float | None:
    """A perspective camera's horizontal field (deg), None for the wide maps."""
    return camera.fov_deg if isinstance(camera, PerspectiveCamera) else None
