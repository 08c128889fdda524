"""``skydome view``: the interactive viewer (a glfw window with a Dear ImGui panel)."""

from __future__ import annotations

import typer

from skydome.cli.cloud_options import CloudFlags, with_cloud_options
from skydome.cli.place_options import (
    elevation_option,
    lat_option,
    lon_option,
    place_option,
    place_time_sun,
)
from skydome.cli.render_cmd import (
    MAX_ORDERS,
    atmosphere_with_knobs,
    check_int,
    knob_option,
    parse_exposure,
    parse_size,
    precompute_progress,
)
from skydome.errors import ParameterError, check_choice, check_range

#: Most frames ``--frames`` accepts.
MAX_FRAMES = 1_000_000


def register(app: typer.Typer) -> None:
    @app.command()
    @with_cloud_options
    def view(
        place: str = place_option(),
        lat: float = lat_option(),
        lon: float = lon_option(),
        elevation: float = elevation_option(),
        when: str = typer.Option(
            None,
            "--time",
            help="ISO 8601 date and time, e.g. 2018-03-01T19:00Z (default with a place: now).",
        ),
        look: str = typer.Option(
            None, "--look", help="sun | moon | zenith | north | east | south | west."
        ),
        sun_elevation: float = typer.Option(
            None, "--sun-elevation", help="Sun elevation, degrees, without a place (default 30)."
        ),
        sun_azimuth: float = typer.Option(
            None, "--sun-azimuth", help="Sun azimuth, degrees, without a place (default 180)."
        ),
        altitude: float = typer.Option(
            None, "--altitude", help="Camera altitude above the ground, metres (0..1e6)."
        ),
        camera: str = typer.Option(
            "perspective", "--camera", help="perspective | fisheye | equirect."
        ),
        size: str = typer.Option("1280x720", "--size", help="Window size WIDTHxHEIGHT."),
        fov: float = typer.Option(90.0, "--fov", help="Horizontal field of view, degrees."),
        yaw: float = typer.Option(None, "--yaw", help="View azimuth, degrees."),
        pitch: float = typer.Option(None, "--pitch", help="View elevation, degrees."),
        atmosphere: str = typer.Option("earth", "--atmosphere", help="Atmosphere preset."),
        albedo: float = knob_option("--albedo"),
        aod: float = knob_option("--aod"),
        angstrom: float = knob_option("--angstrom"),
        ozone: float = knob_option("--ozone"),
        orders: int = typer.Option(4, "--orders", help="Scattering orders of the tables."),
        spectral: str = typer.Option(
            "accurate", "--spectral", help="Wavelength set: accurate (16) | fast (4)."
        ),
        exposure: str = typer.Option(
            "auto", "--exposure", help="'auto', 'adapt' (an eye adapting) or EV100."
        ),
        compensation: float = typer.Option(
            0.0, "--exposure-compensation", help="EV added to the exposure."
        ),
        tonemap: str = typer.Option(
            "filmic", "--tonemap", help="filmic | reinhard | exponential | hvs | linear."
        ),
        bortle: int = typer.Option(None, "--bortle", help="Light pollution, Bortle 1..9."),
        night: bool = typer.Option(
            True, "--night/--no-night", help="Draw the night sky's layers (stars...)."
        ),
        night_vision: bool = typer.Option(False, "--night-vision", help="Night vision on."),
        overlay: str = typer.Option(None, "--overlay", help="lines,labels,grid."),
        play: bool = typer.Option(False, "--play", help="Start with the time running."),
        speed: float = typer.Option(
            60.0, "--speed", help="Time speed, simulated seconds per second (-864000..864000)."
        ),
        vsync: bool = typer.Option(False, "--vsync/--no-vsync", help="Swap at the refresh rate."),
        panel: bool = typer.Option(True, "--panel/--no-panel", help="Show the control panel."),
        frames: int = typer.Option(
            None, "--frames", help="Draw this many frames, print the median fps and exit."
        ),
        screenshot: list[str] = typer.Option(
            None,
            "--screenshot",
            help="Save the last frame (with --frames): .png/.jpg (the screen), .exr/.hdr/.npy "
            "(the same frame in cd/m^2). Repeatable.",
        ),
        cloud_flags: CloudFlags = None,
    ) -> None:
        """Open the interactive viewer: mouse look, scroll zoom, W/A/S/D walk, Q/E climb,
        Space play; a panel for time, place, camera, atmosphere and display."""
        from rich.console import Console

        from skydome.atmosphere.presets import PRESETS
        from skydome.display import TONEMAPS
        from skydome.io import check_output_path
        from skydome.spectra.grids import MODES
        from skydome.viewer import INSTALL_HINT
        from skydome.viewer.controls import (
            PROJECTIONS,
            SPEED_RANGE,
            VIEW_ALTITUDE_RANGE_M,
            VIEW_FOV_RANGE_DEG,
            VIEW_PITCH_RANGE_DEG,
        )

        pts = place_time_sun(
            place, lat, lon, elevation, when, sun_elevation, sun_azimuth, look, default_now=True
        )
        observer, t, abstract = pts.observer, pts.time, pts.abstract
        el, az = pts.sun_elevation_deg, pts.sun_azimuth_deg
        width, height = parse_size(size)
        from skydome.viewer.app import MAX_WINDOW_SIDE

        if width > MAX_WINDOW_SIDE or height > MAX_WINDOW_SIDE:
            raise ParameterError(f"--size {size}: a window has sides of 1 to {MAX_WINDOW_SIDE}")
        mode = "ev"
        ev = 14.0
        if exposure.strip().lower() in ("auto", "adapt"):
            mode = exposure.strip().lower()
        else:
            ev = parse_exposure(exposure)
        check_range("--exposure-compensation", compensation, -20.0, 20.0, "EV")
        if altitude is not None:
            check_range("--altitude", altitude, *VIEW_ALTITUDE_RANGE_M, "m")
        check_choice("--tonemap", tonemap, TONEMAPS, "tone map")
        check_choice("--camera", camera, PROJECTIONS, "camera")
        check_choice("--atmosphere", atmosphere, PRESETS, "atmosphere preset")
        check_choice("--spectral", spectral, MODES, "wavelength set")
        check_int("--orders", orders, 1, MAX_ORDERS)
        check_range("--fov", fov, *VIEW_FOV_RANGE_DEG, "deg")
        if pitch is not None:
            check_range("--pitch", pitch, *VIEW_PITCH_RANGE_DEG, "deg")
        if yaw is not None:
            check_range("--yaw", yaw, -360.0, 360.0, "deg")
        check_range("--speed", speed, *SPEED_RANGE, "s/s")
        if bortle is not None:
            if abstract:
                raise ParameterError("--bortle needs a place and a time (--place or --lat/--lon)")
            check_int("--bortle", bortle, 1, 9)
        overlays: tuple[str, ...] = ()
        if overlay is not None:
            from skydome.display.overlays import parse_overlays

            overlays = parse_overlays(overlay)
        if frames is not None:
            check_int("--frames", frames, 1, MAX_FRAMES)
        shots = [check_output_path(p) for p in (screenshot or [])]
        if shots and frames is None:
            raise ParameterError("--screenshot saves the last of --frames N frames: add --frames")
        params = atmosphere_with_knobs(atmosphere, albedo, aod, angstrom, ozone)
        sky_clouds = cloud_flags.clouds()
        try:
            import glfw  # noqa: F401

            if panel:
                import imgui_bundle  # noqa: F401
        except ImportError as exc:
            raise ParameterError(f"skydome view needs {exc.name}: {INSTALL_HINT}") from None

        from skydome.atmosphere.layer import AtmosphereLayer
        from skydome.atmosphere.precompute_config import PrecomputeConfig
        from skydome.scene import Sky
        from skydome.scene.sky import default_layers
        from skydome.viewer.app import ViewerWindow
        from skydome.viewer.controls import Controls
        from skydome.viewer.scene import ViewerScene, initial_state

        console = Console(soft_wrap=True)
        config = PrecomputeConfig(wavelengths=spectral, orders=orders)
        with ViewerWindow(width, height, vsync=vsync, panel=panel) as window:
            with precompute_progress(console) as report:
                air = AtmosphereLayer(params, config=config, progress=report)
                layers = default_layers(air, night=night and not abstract, light_pollution=bortle)
                display = {"night_vision": night_vision, "overlays": overlays}
                if sky_clouds is not None:
                    # on a CPU rasterizer the interactive march (an eighth of the resolution,
                    # accumulated over frames); a GPU marches the still frames' quality
                    from skydome.clouds.layer import CloudLayer
                    from skydome.gpu import gl_info

                    soft = gl_info(window.ctx).software
                    quality = "interactive" if soft else "full"
                    display["clouds"] = CloudLayer(sky_clouds, quality=quality)
                if abstract:
                    layers = [la for la in layers if la.name != "moon"]
                    sky = Sky(sun_elevation_deg=el, sun_azimuth_deg=az, layers=layers,
                              ctx=window.ctx, **display)  # fmt: skip
                else:
                    sky = Sky(observer, t, layers=layers, ctx=window.ctx, **display)
            fields = {
                "projection": camera,
                "fov_deg": fov,
                "altitude_m": altitude,
                "exposure_mode": mode,
                "ev100": ev,
                "compensation_ev": compensation,
                "tonemap": tonemap,
                "night_vision": night_vision,
                "overlays": overlays,
                "playing": play,
                "speed": speed,
                "vsync": vsync,
            }
            if look is not None:
                aim = sky.camera(look)
                fields.update(yaw_deg=aim.yaw_deg, pitch_deg=aim.pitch_deg)
            if yaw is not None:
                fields["yaw_deg"] = yaw
            if pitch is not None:
                fields["pitch_deg"] = pitch
            scene = ViewerScene(sky, Controls(initial_state(sky, **fields)))
            if window.panel is not None:
                window.panel.configure(atmosphere=params, config=config, night=night,
                                       light_pollution=bortle)  # fmt: skip
            try:
                timer = window.run(scene, frames=frames, screenshot=shots)
            finally:
                if window.panel is not None:
                    window.panel.stop_rebuild()
            if frames is not None:
                fps = timer.fps()
                typer.echo(f"{fps:.1f} fps" if fps else "0.0 fps")
                report_times(timer)
                for p in getattr(window, "saved", []):
                    typer.echo(f"wrote {p}")
            scene.release()


def report_times(timer) -> None:
    """One line of median CPU stage times and GPU pass times (ms)."""
    r = timer.report()
    cpu = ", ".join(f"{k} {v:.1f}" for k, v in r["cpu"].items())
    gpu = ", ".join(f"{k} {v:.1f}" for k, v in r["gpu"].items())
    typer.echo(f"cpu ms: {cpu}" + (f"; gpu ms: {gpu}" if gpu else ""))
