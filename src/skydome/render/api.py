"""One call from settings to a frame: the library's front door for scripts and the CLI."""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable

from skydome.atmosphere import AtmosphereParams, preset
from skydome.errors import ParameterError, check_range
from skydome.render.cameras import Camera, PerspectiveCamera, direction_from_angles
from skydome.render.frame import Frame

MODELS = ("precomputed", "single")


#: Renderers kept for reuse by get_renderer, most recently used last. Two suffice for a
#: script that alternates two settings; older ones are dropped and their GL objects released
#: once nothing else holds them (the tables stay while another renderer shares them).
_KEEP = 2
_RENDERERS: OrderedDict[tuple, object] = OrderedDict()


def _renderer_key(model, params, spectral, samples, jitter, orders) -> tuple:
    # Only what changes the renderer: the precomputed model ignores samples and jitter, the
    # single-scattering one the orders.
    if model == "single":
        return (model, params, spectral, samples, jitter)
    return (model, params, spectral, orders)


def _make_renderer(model, params, spectral, samples, jitter, orders, progress):
    if model == "single":
        from skydome.render.single import SingleScatteringRenderer

        return SingleScatteringRenderer(
            params, spectral=spectral, view_samples=samples, jitter=jitter
        )
    from skydome.atmosphere.precompute_config import PrecomputeConfig
    from skydome.render.precomputed import PrecomputedRenderer

    return PrecomputedRenderer(
        params, PrecomputeConfig(wavelengths=spectral, orders=orders), progress=progress
    )


def clear_renderers() -> None:
    """Drop the renderers kept by get_renderer (their GL objects go with the last holder)."""
    _RENDERERS.clear()


def get_renderer(
    model: str = "precomputed",
    atmosphere: str | AtmosphereParams = "earth",
    *,
    spectral: str = "accurate",
    samples: int = 16,
    jitter: bool = True,
    orders: int = 4,
    progress: Callable[[str, float], None] | None = None,
):
    """A renderer for a model and atmosphere, kept so that repeated frames reuse its GL state.

    ``model="precomputed"`` (every scattering order, ``orders`` of them, tables from the disk
    cache; ``samples`` and ``jitter`` do not apply) or ``"single"`` (single scattering,
    ``samples`` per view ray, ``jitter``). ``progress(stage, fraction)`` reports a table
    precomputation, if one is needed.
    """
    params = preset(atmosphere) if isinstance(atmosphere, str) else atmosphere
    if model not in MODELS:
        raise ParameterError(f"unknown model {model!r}; choose one of {', '.join(MODELS)}")
    spectral_key = spectral if isinstance(spectral, str) else tuple(spectral)
    if not isinstance(orders, int) or not 1 <= orders <= 20:
        raise ParameterError(f"orders = {orders!r} must be an integer in [1, 20]")
    args = (model, params, spectral_key, int(samples), bool(jitter), orders)
    key = _renderer_key(*args)
    renderer = _RENDERERS.pop(key, None)
    if renderer is None:
        renderer = _make_renderer(*args, progress)
    _RENDERERS[key] = renderer
    while len(_RENDERERS) > _KEEP:
        _RENDERERS.popitem(last=False)
    return renderer


def render_sky(
    *,
    sun_elevation_deg: float = 30.0,
    sun_azimuth_deg: float = 180.0,
    altitude_m: float = 1.7,
    camera: Camera | None = None,
    width: int = 1280,
    height: int = 720,
    atmosphere: str | AtmosphereParams = "earth",
    model: str = "precomputed",
    spectral: str = "accurate",
    samples: int = 16,
    jitter: bool = True,
    orders: int = 4,
    progress: Callable[[str, float], None] | None = None,
) -> Frame:
    """Render the sky for a Sun position and camera; returns a Frame in cd/m^2.

    Example::

        frame = render_sky(sun_elevation_deg=5, sun_azimuth_deg=250,
                           camera=PerspectiveCamera(fov_deg=90, yaw_deg=250, pitch_deg=10))

    ``progress(stage, fraction)`` is called during a table precomputation, if one is needed.
    """
    el = check_range("sun elevation", sun_elevation_deg, -90.0, 90.0, "deg")
    az = check_range("sun azimuth", sun_azimuth_deg, -360.0, 360.0, "deg")
    cam = camera or PerspectiveCamera(fov_deg=90.0, yaw_deg=az, pitch_deg=15.0)
    if model == "precomputed":
        # The scene's frame graph (skydome.scene) in its abstract mode: the atmosphere and the
        # Sun's limb-darkened, refracted disk, as the command line and the viewer draw them.
        sky = get_sky(atmosphere, spectral=spectral, orders=orders, progress=progress)
        sky = sky.with_sun(el, az)
        frame = sky.render(cam, width, height, altitude_m=altitude_m, exposure=None)
        frame.info.update(model="precomputed", sun_direction=sky.state.sun.direction.tolist())
        return frame
    renderer = get_renderer(
        model,
        atmosphere,
        spectral=spectral,
        samples=samples,
        jitter=jitter,
        orders=orders,
        progress=progress,
    )
    return renderer.render(
        cam, width, height, sun_direction=direction_from_angles(el, az), altitude_m=altitude_m
    )


def get_sky(
    atmosphere: str | AtmosphereParams = "earth",
    *,
    spectral: str = "accurate",
    orders: int = 4,
    progress: Callable[[str, float], None] | None = None,
):
    """An abstract-mode Sky (the Sun and the atmosphere, skydome.scene) for ``render_sky``,
    kept like get_renderer's renderers so that repeated frames reuse its tables and passes."""
    from skydome.atmosphere.layer import AtmosphereLayer
    from skydome.atmosphere.precompute_config import PrecomputeConfig
    from skydome.celestial.sun import SunLayer
    from skydome.scene import Sky

    params = preset(atmosphere) if isinstance(atmosphere, str) else atmosphere
    if not isinstance(orders, int) or not 1 <= orders <= 20:
        raise ParameterError(f"orders = {orders!r} must be an integer in [1, 20]")
    spectral_key = spectral if isinstance(spectral, str) else tuple(spectral)
    key = ("scene", params, spectral_key, orders)
    sky = _RENDERERS.pop(key, None)
    if sky is None:
        config = PrecomputeConfig(wavelengths=spectral, orders=orders)
        air = AtmosphereLayer(params, config=config, progress=progress)
        sky = Sky(sun_elevation_deg=30.0, layers=[SunLayer(), air])
    _RENDERERS[key] = sky
    while len(_RENDERERS) > _KEEP:
        _RENDERERS.popitem(last=False)
    return sky
