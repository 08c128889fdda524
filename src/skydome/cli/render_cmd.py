"""``skydome render``: render a sky to EXR / HDR / NPY / PNG / JPEG files."""

from __future__ import annotations

import contextlib
import re
import time

import typer

from skydome.cli.cloud_options import CloudFlags, with_cloud_options
from skydome.cli.place_options import (
    describe_state,
    elevation_option,
    lat_option,
    lon_option,
    place_option,
    place_time_sun,
)
from skydome.errors import ParameterError, check_choice, check_range

#: Frames larger than this many pixels are refused (a 16k x 8k equirect is 128 Mpixel).
MAX_PIXELS = 134_217_728
#: Largest --size side (pixels), as skydome.render.cameras.MAX_SIDE.
MAX_SIDE = 16384
#: Ray-march samples per view ray accepted by the single-scattering model.
MAX_VIEW_SAMPLES = 4096
#: Scattering orders accepted by the precomputed model.
MAX_ORDERS = 20


def check_int(flag: str, value: int, lo: int, hi: int) -> int:
    """``value`` if it is an integer in [lo, hi], else ParameterError naming ``flag``."""
    if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
        raise ParameterError(f"{flag} {value} must be an integer from {lo} to {hi}")
    return value


def parse_size(text: str) -> tuple[int, int]:
    """Parse 'WxH' (e.g. 1280x720) into positive ints."""
    m = re.fullmatch(r"\s*(\d+)\s*[xX×]\s*(\d+)\s*", text or "")
    if not m:
        raise ParameterError(f"--size {text} must look like WIDTHxHEIGHT, e.g. 1280x720")
    w, h = int(m.group(1)), int(m.group(2))
    if w < 1 or h < 1 or w > MAX_SIDE or h > MAX_SIDE or w * h > MAX_PIXELS:
        raise ParameterError(
            f"--size {text} must have sides of 1 to {MAX_SIDE} pixels and at most "
            f"{MAX_PIXELS} pixels in all"
        )
    return w, h


def parse_exposure(text: str) -> float | None:
    """'auto' -> None, else an EV100 number."""
    if text.strip().lower() == "auto":
        return None
    try:
        ev = float(text)
    except ValueError:
        raise ParameterError(
            f"--exposure {text} must be auto or an EV100 number such as 14.5"
        ) from None
    return check_range("--exposure", ev, -20.0, 40.0, "EV")


#: Help of the atmosphere knob options of ``render``, ``illuminance`` and ``precompute``; the
#: ranges are those of skydome.atmosphere.params (*_RANGE), written out here so that the
#: command line starts without importing NumPy (tests/test_cli_knobs.py checks they agree).
KNOB_HELP = {
    "--albedo": "Ground albedo, 0..1, on top of --atmosphere (default: the preset's, earth 0.3).",
    "--aod": "Aerosol optical depth at 550 nm, 0..5, on top of --atmosphere (default: the "
    "preset's, earth 0.1, typical 0.151, hazy 0.27, earth_bruneton 0.0053).",
    "--angstrom": "Angstrom exponent of the aerosol optical depth, -0.5..3 (0 grey, 1.3 "
    "continental haze, 2+ smoke), on top of --atmosphere (default: the preset's spectrum).",
    "--ozone": "Total ozone column, Dobson units, 0..700, on top of --atmosphere (default: "
    "the preset's, earth 300 DU).",
}


def knob_option(flag: str):
    """A ``typer.Option`` for one atmosphere knob (default None: the preset's own value)."""
    return typer.Option(None, flag, help=KNOB_HELP[flag])


def atmosphere_with_knobs(
    atmosphere: str,
    albedo: float | None = None,
    aod: float | None = None,
    angstrom: float | None = None,
    ozone: float | None = None,
):
    """The ``--atmosphere`` preset with the knob options given (None keeps the preset's
    value); a bad value raises ParameterError naming its flag and range."""
    from skydome.atmosphere import (
        ALBEDO_RANGE,
        ANGSTROM_RANGE,
        AOD_550_RANGE,
        OZONE_DU_RANGE,
        preset,
    )

    for flag, value, valid, unit in (
        ("--albedo", albedo, ALBEDO_RANGE, ""),
        ("--aod", aod, AOD_550_RANGE, ""),
        ("--angstrom", angstrom, ANGSTROM_RANGE, ""),
        ("--ozone", ozone, OZONE_DU_RANGE, "DU"),
    ):
        if value is not None:
            check_range(flag, value, *valid, unit)
    return preset(atmosphere, albedo=albedo, aod_550=aod, angstrom=angstrom, ozone_du=ozone)


@contextlib.contextmanager
def precompute_progress(console):
    """A progress bar for table precomputation, shown only while a stage reports.

    Yields the ``report(stage, fraction)`` callback, to pass as ``progress=`` to what may
    precompute tables.
    """
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    bar = Progress(
        TextColumn("precomputing {task.description}"),
        BarColumn(),
        TextColumn("{task.percentage:>3.0f}%"),
        TimeElapsedColumn(),
        console=console,
        transient=True,
    )
    task = None

    def report(stage: str, fraction: float) -> None:
        nonlocal task
        if not console.is_terminal:  # no bar in logs and pipes
            return
        if task is None:
            bar.start()
            task = bar.add_task(stage, total=1.0)
        bar.update(task, completed=fraction, description=stage)

    try:
        yield report
    finally:
        if task is not None:
            bar.stop()


def register(app: typer.Typer) -> None:
    @app.command()
    @with_cloud_options
    def render(
        place: str = place_option(),
        lat: float = lat_option(),
        lon: float = lon_option(),
        elevation: float = elevation_option(),
        when: str = typer.Option(
            None,
            "--time",
            help="ISO 8601 date and time, e.g. 2018-03-01T19:00Z (an offset or Z; naive is "
            "UTC). With a place: the Sun and the Moon where they are.",
        ),
        look: str = typer.Option(
            None,
            "--look",
            help="Aim the camera: sun | moon | zenith | north | east | south | west (default: "
            "the Sun, or at night the Moon when it is up).",
        ),
        sun_elevation: float = typer.Option(
            None,
            "--sun-elevation",
            help="Sun elevation above the horizon, degrees (-90..90; default 30), without a "
            "place and time.",
        ),
        sun_azimuth: float = typer.Option(
            None,
            "--sun-azimuth",
            help="Sun azimuth from north through east, degrees (default 180), without a place.",
        ),
        altitude: float = typer.Option(
            None,
            "--altitude",
            help="Camera altitude above the ground, metres (default 1.7 m above the place).",
        ),
        camera: str = typer.Option(
            "perspective", "--camera", help="perspective | fisheye | equirect | cubemap."
        ),
        size: str = typer.Option(
            "1280x720", "--size", help="WIDTHxHEIGHT in pixels (cubemap: face size from HEIGHT)."
        ),
        fov: float = typer.Option(
            90.0, "--fov", help="Horizontal field of view of the perspective camera, degrees."
        ),
        yaw: float = typer.Option(
            None,
            "--yaw",
            help="View azimuth from north through east, degrees (default: the Sun's).",
        ),
        pitch: float = typer.Option(
            None, "--pitch", help="View elevation, degrees (default 15, or the --look target's)."
        ),
        roll: float = typer.Option(
            0.0, "--roll", help="Camera roll about the view direction, degrees."
        ),
        atmosphere: str = typer.Option(
            "earth",
            "--atmosphere",
            help="Preset: earth | typical | hazy | urban | maritime | desert | earth_bruneton | "
            "earth_nishita | mars.",
        ),
        albedo: float = knob_option("--albedo"),
        aod: float = knob_option("--aod"),
        angstrom: float = knob_option("--angstrom"),
        ozone: float = knob_option("--ozone"),
        model: str = typer.Option(
            "precomputed", "--model", help="precomputed (every scattering order) | single."
        ),
        orders: int = typer.Option(
            4, "--orders", help="Scattering orders of the precomputed model."
        ),
        samples: int = typer.Option(
            None,
            "--samples",
            help=f"Ray-march samples per view ray (1..{MAX_VIEW_SAMPLES}, default 16), for "
            "--model single only: the precomputed model has no ray march and refuses it.",
        ),
        spectral: str = typer.Option(
            "accurate", "--spectral", help="Wavelength set: accurate (16) | fast (4)."
        ),
        exposure: str = typer.Option(
            "auto", "--exposure", help="'auto' or EV100 (e.g. 15 for noon)."
        ),
        compensation: float = typer.Option(
            0.0, "--exposure-compensation", help="EV added to the exposure."
        ),
        tonemap: str = typer.Option(
            "filmic", "--tonemap", help="filmic | reinhard | exponential | hvs | linear."
        ),
        bortle: int = typer.Option(
            None,
            "--bortle",
            help="Light pollution of a Bortle class, 1 (darkest) to 9 (inner city), with a "
            "place (default: none).",
        ),
        night_vision: bool = typer.Option(
            False,
            "--night-vision",
            help="Show the image as a dark-adapted eye sees it: colour fades, blur, noise "
            "(the image only; EXR/HDR/NPY keep the physical frame).",
        ),
        overlay: str = typer.Option(
            None,
            "--overlay",
            help="Draw over the image, comma separated: lines (constellations), labels, grid.",
        ),
        output: list[str] = typer.Option(
            ["sky.png"],
            "-o",
            "--output",
            help="Output file(s), repeatable: .exr or .hdr (absolute units), .npy, "
            ".png or .jpg (tone mapped).",
        ),
        cloud_flags: CloudFlags = None,
    ) -> None:
        """Render a sky in absolute units (cd/m^2) and write it as EXR, HDR, NPY, or PNG and JPEG
        (tone mapped)."""
        from rich.console import Console

        from skydome.atmosphere.presets import PRESETS
        from skydome.display import (
            TONEMAPS,
            auto_exposure,
            ev100_to_scale,
            gpu_tonemap,
            scale_to_ev100,
        )
        from skydome.io import WRITERS, check_output_path, write_outputs
        from skydome.render import MODELS, get_renderer, make_camera
        from skydome.render.base import MAX_ALTITUDE_M
        from skydome.render.cameras import (
            CAMERAS,
            FOV_RANGE_DEG,
            PITCH_RANGE_DEG,
            ROLL_RANGE_DEG,
            YAW_RANGE_DEG,
            direction_from_angles,
        )
        from skydome.spectra.grids import MODES

        # Validate everything before any work, so bad input writes nothing.
        pts = place_time_sun(place, lat, lon, elevation, when, sun_elevation, sun_azimuth, look)
        observer, t, abstract = pts.observer, pts.time, pts.abstract
        el, az = pts.sun_elevation_deg, pts.sun_azimuth_deg
        width, height = parse_size(size)
        ev = parse_exposure(exposure)
        check_range("--exposure-compensation", compensation, -20.0, 20.0, "EV")
        if altitude is not None:
            check_range("--altitude", altitude, 0.0, MAX_ALTITUDE_M, "m")
        check_choice("--tonemap", tonemap, TONEMAPS, "tone map")
        check_choice("--model", model, MODELS, "model")
        check_choice("--camera", camera, CAMERAS, "camera")
        check_choice("--atmosphere", atmosphere, PRESETS, "atmosphere preset")
        check_choice("--spectral", spectral, MODES, "wavelength set")
        check_int("--orders", orders, 1, MAX_ORDERS)
        if samples is not None:
            if model != "single":
                raise ParameterError(
                    f"--samples applies only to --model single; the {model} model reads "
                    "every ray from its tables (drop --samples or add --model single)"
                )
            check_int("--samples", samples, 1, MAX_VIEW_SAMPLES)
        if model == "single" and not abstract:
            raise ParameterError(
                "--model single renders a Sun alone: use --sun-elevation, or the default model "
                "for a place and a time"
            )
        check_range("--fov", fov, *FOV_RANGE_DEG, "deg")
        if pitch is not None:
            check_range("--pitch", pitch, *PITCH_RANGE_DEG, "deg")
        check_range("--roll", roll, *ROLL_RANGE_DEG, "deg")
        if yaw is not None:
            check_range("--yaw", yaw, *YAW_RANGE_DEG, "deg")
        if bortle is not None:
            if abstract:
                raise ParameterError("--bortle needs a place and a time (--place or --lat/--lon)")
            check_int("--bortle", bortle, 1, 9)
        overlays = ()
        if overlay is not None:
            from skydome.display.overlays import parse_overlays

            overlays = parse_overlays(overlay)
        if model == "single" and (night_vision or overlays):
            raise ParameterError(
                "--night-vision and --overlay need the default model (a sky of the scene)"
            )
        sky_clouds = cloud_flags.clouds()
        if model == "single" and sky_clouds is not None:
            raise ParameterError("--clouds needs the default model (a sky of the scene)")
        params = atmosphere_with_knobs(atmosphere, albedo, aod, angstrom, ozone)
        paths = [check_output_path(p) for p in output]
        if len({str(p.resolve()) for p in paths}) != len(paths):
            raise ParameterError("-o/--output: the same path is given twice")

        console = Console(soft_wrap=True)
        if model == "single":
            cam = make_camera(
                camera,
                **{
                    "fov_deg": fov,
                    "yaw_deg": az if yaw is None else yaw,
                    "pitch_deg": 15.0 if pitch is None else pitch,
                    "roll_deg": roll,
                },
            )
            renderer = get_renderer(
                model, params, spectral=spectral, orders=orders,
                **({} if samples is None else {"samples": samples}),
            )  # fmt: skip
            frame = renderer.render(
                cam, width, height, sun_direction=direction_from_angles(el, az),
                altitude_m=1.7 if altitude is None else altitude,
            )  # fmt: skip
            scale = (
                auto_exposure(frame, compensation_ev=compensation, clip_percentile=99.5)
                if ev is None
                else ev100_to_scale(ev, compensation)
            )
            t0 = time.perf_counter()
            ldr = (
                gpu_tonemap(frame, tonemap, scale)
                if any(not WRITERS[p.suffix.lower()].hdr for p in paths)
                else None
            )
            tone_ms = (time.perf_counter() - t0) * 1e3
        else:
            from skydome.atmosphere.layer import AtmosphereLayer
            from skydome.atmosphere.precompute_config import PrecomputeConfig
            from skydome.scene import Sky
            from skydome.scene.sky import default_layers, default_look

            with precompute_progress(console) as report:
                air = AtmosphereLayer(
                    params,
                    config=PrecomputeConfig(wavelengths=spectral, orders=orders),
                    progress=report,
                )
                layers = default_layers(air, night=not abstract, light_pollution=bortle)
                display = {"night_vision": night_vision, "overlays": overlays}
                if abstract:
                    layers = [la for la in layers if la.name != "moon"]
                    sky = Sky(
                        sun_elevation_deg=el, sun_azimuth_deg=az, layers=layers,
                        clouds=sky_clouds, **display,
                    )  # fmt: skip
                else:
                    sky = Sky(observer, t, layers=layers, clouds=sky_clouds, **display)
            for line in describe_state(sky.state):
                console.print(line)
            if not abstract and sky.state.sun.elevation_deg < -12.0:
                from skydome.night.glow_layer import zenith_brightness

                glow = zenith_brightness(sky.state, sky.layers)
                console.print(
                    "night glow at the zenith, V mag/arcsec^2 outside the air: "
                    + ", ".join(f"{name} {m:.2f}" for name, m in glow.items())
                )
            target = look or (default_look(sky.state) if not abstract else None)
            if target is not None:
                aim = sky.camera(target)
                view_yaw, view_pitch = aim.yaw_deg, aim.pitch_deg
            else:
                view_yaw, view_pitch = az, 15.0
            cam = make_camera(
                camera,
                **{
                    "fov_deg": fov,
                    "yaw_deg": view_yaw if yaw is None else yaw,
                    "pitch_deg": view_pitch if pitch is None else pitch,
                    "roll_deg": roll,
                },
            )
            want_ldr = any(not WRITERS[p.suffix.lower()].hdr for p in paths)
            t0 = time.perf_counter()
            frame = sky.render(
                cam,
                width,
                height,
                altitude_m=altitude,
                exposure="auto" if ev is None else ev,
                compensation_ev=compensation,
                tonemap=tonemap if want_ldr else None,
            )
            tone_ms = 0.0
            ldr = frame.image
            scale = ev100_to_scale(frame.info["exposure_ev100"])
        metadata = {**frame.info, "exposure_ev100": scale_to_ev100(scale), "tonemap": tonemap}
        written = write_outputs(paths, frame.data, ldr, metadata=metadata)
        h, w = frame.shape
        for p in written:
            console.print(f"wrote [bold]{p}[/bold] ({w}x{h})")
        console.print(
            f"frame {frame.info['render_ms']:.1f} ms ({model}, {camera}, {params.name}), "
            f"tone map {tone_ms:.1f} ms, exposure EV100 {scale_to_ev100(scale):.2f}"
            + (" (auto)" if ev is None else "")
        )
