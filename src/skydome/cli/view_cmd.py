"""``skydome view``: the interactive viewer (a glfw window with a Dear ImGui panel)."""

from __future__ import annotations

import typer

from skydome.cli.describe import (
    place_time_sun,
    precompute_progress,
    report_light_pollution,
    report_time,
    sky_description,
)
from skydome.cli.options import with_flags
from skydome.cli.parsing import check_int, parse_exposure, parse_size
from skydome.errors import ParameterError, check_choice, check_range

#: Most frames ``--frames`` accepts.
MAX_FRAMES = 1_000_000


def register(app: typer.Typer) -> None:
    @app.command()
    @with_flags("place", "sun", "camera", "air", "tables", "night", "display", "clouds", "weather")
    def view(
        when: str = typer.Option(
            None,
            "--time",
            help="ISO 8601 date and time, e.g. 2018-03-01T20:00 or 2018-03-01T19:00Z (default "
            "with a place: now). Without an offset or Z it is the --place's local time (its "
            "IANA time zone), UTC with --lat/--lon or --utc.",
        ),
        size: str = typer.Option("1280x720", "--size", help="Window size WIDTHxHEIGHT."),
        exposure: str = typer.Option(
            "auto", "--exposure", help="'auto', 'adapt' (an eye adapting) or EV100."
        ),
        night: bool = typer.Option(
            True, "--night/--no-night", help="Draw the night sky's layers (stars...)."
        ),
        play: bool = typer.Option(False, "--play", help="Start with the time running."),
        speed: float = typer.Option(
            60.0, "--speed", help="Time speed, simulated seconds per second (-864000..864000)."
        ),
        vsync: bool = typer.Option(False, "--vsync/--no-vsync", help="Swap at the refresh rate."),
        panel: bool = typer.Option(True, "--panel/--no-panel", help="Show the control panel."),
        frames: int = typer.Option(
            None,
            "--frames",
            help="Draw this many frames, print the drawn frames per second and exit.",
        ),
        turn: float = typer.Option(
            None,
            "--turn",
            help="Turn the camera by this many degrees of azimuth every frame (a scripted "
            "tour; every frame is then drawn anew), -180..180.",
        ),
        frame_budget: float = typer.Option(
            33.0,
            "--frame-budget",
            help="Dynamic resolution: draw a moving view at a reduced size chosen to hold this "
            "frame time (ms), upsampled; a still view is drawn again at full resolution. "
            "0: off (every frame at full resolution), up to 1000.",
        ),
        screenshot: list[str] = typer.Option(
            None,
            "--screenshot",
            help="Save the last frame (with --frames): .png/.jpg (the screen), .exr/.hdr/.npy "
            "(the same frame in cd/m^2). Repeatable.",
        ),
        flags=None,
    ) -> None:
        """Open the interactive viewer: mouse look, scroll zoom, W/A/S/D walk, Q/E climb,
        Space play; a panel for time, place, camera, atmosphere and display."""
        from rich.console import Console

        from skydome.display import TONEMAPS
        from skydome.display.exposure import METERINGS
        from skydome.display.glare import GLARES
        from skydome.io import check_output_path
        from skydome.viewer import INSTALL_HINT
        from skydome.viewer.controls import (
            PROJECTIONS,
            SPEED_RANGE,
            VIEW_ALTITUDE_RANGE_M,
            VIEW_FOV_RANGE_DEG,
            VIEW_PITCH_RANGE_DEG,
        )

        pts = place_time_sun(flags, when, default_now=True)
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
        check_range("--exposure-compensation", flags.compensation, -20.0, 20.0, "EV")
        if flags.altitude is not None:
            check_range("--altitude", flags.altitude, *VIEW_ALTITUDE_RANGE_M, "m")
        check_choice("--tonemap", flags.tonemap, TONEMAPS, "tone map")
        check_choice("--metering", flags.metering, METERINGS, "metering")
        check_choice("--glare", flags.glare, GLARES, "glare")
        check_choice("--camera", flags.camera, PROJECTIONS, "camera")
        check_range("--fov", flags.fov, *VIEW_FOV_RANGE_DEG, "deg")
        if flags.pitch is not None:
            check_range("--pitch", flags.pitch, *VIEW_PITCH_RANGE_DEG, "deg")
        if flags.yaw is not None:
            check_range("--yaw", flags.yaw, -360.0, 360.0, "deg")
        check_range("--speed", speed, *SPEED_RANGE, "s/s")
        if turn is not None:
            check_range("--turn", turn, -180.0, 180.0, "deg")
        if frames is not None:
            check_int("--frames", frames, 1, MAX_FRAMES)
        from skydome.viewer.dynamic_resolution import check_frame_budget

        frame_budget = check_frame_budget(frame_budget, "--frame-budget")
        shots = [check_output_path(p) for p in (screenshot or [])]
        if shots and frames is None:
            raise ParameterError("--screenshot saves the last of --frames N frames: add --frames")
        description = sky_description(flags, pts, night=night)
        try:
            import glfw  # noqa: F401

            if panel:
                import imgui_bundle  # noqa: F401
        except ImportError as exc:
            raise ParameterError(f"skydome view needs {exc.name}: {INSTALL_HINT}") from None

        from skydome.cli.blas_threads import single_blas_thread
        from skydome.gpu import gl_info
        from skydome.sky import Sky
        from skydome.viewer.app import ViewerWindow
        from skydome.viewer.controls import Controls
        from skydome.viewer.scene import ViewerScene, initial_state

        console = Console(soft_wrap=True)
        with ViewerWindow(width, height, vsync=vsync, panel=panel) as window:
            if gl_info(window.ctx).software:
                single_blas_thread()  # its spinning threads would take the rasterizer's cores
            if description.clouds is not None and gl_info(window.ctx).software:
                # on a CPU rasterizer the interactive march (an eighth of the resolution,
                # accumulated over frames); a GPU marches the still frames' quality
                description = description.with_(cloud_quality="interactive")
            with precompute_progress(console) as report:
                sky = Sky(description, progress=report, ctx=window.ctx)
            if not pts.abstract:
                report_time(pts.time, pts.zone)
                report_light_pollution(description, pts.place, flags.bortle)
            fields = {
                "projection": flags.camera,
                "fov_deg": flags.fov,
                "altitude_m": flags.altitude,
                "exposure_mode": mode,
                "ev100": ev,
                "compensation_ev": flags.compensation,
                "tonemap": flags.tonemap,
                "night_vision": description.night_vision,
                "overlays": description.overlays,
                "playing": play,
                "speed": speed,
                "vsync": vsync,
            }
            if flags.look is not None:
                aim = sky.camera(flags.look)
                fields.update(yaw_deg=aim.yaw_deg, pitch_deg=aim.pitch_deg)
            if flags.yaw is not None:
                fields["yaw_deg"] = flags.yaw
            if flags.pitch is not None:
                fields["pitch_deg"] = flags.pitch
            scene = ViewerScene(sky, Controls(initial_state(sky, **fields)))
            scene.metering, scene.glare = flags.metering, flags.glare
            scene.frame_budget_ms = frame_budget
            if window.panel is not None:
                window.panel.configure(description)
            on_frame = None
            if turn:

                def on_frame(_window, _i, controls=scene.controls, step=float(turn)):
                    controls.set(yaw_deg=controls.state.yaw_deg + step)

            try:
                timer = window.run(scene, frames=frames, screenshot=shots, on_frame=on_frame)
            finally:
                if window.panel is not None:
                    window.panel.stop_rebuild()
            if frames is not None:
                typer.echo(fps_report(timer, scene))
                report_times(timer)
                for p in getattr(window, "saved", []):
                    typer.echo(f"wrote {p}")
            scene.release()


def fps_report(timer, scene=None) -> str:
    """The line ``--frames`` prints: drawn frames per second and ms per redraw (frames that
    drew the sky anew; a still view shows its kept frame again), and every frame's rate;
    with the ``scene`` (a ViewerScene), the median render scale of the frames drawn anew
    (dynamic resolution) and the frame budget."""
    import statistics

    drawn, ms = timer.drawn_fps(), timer.median_redraw_ms()
    count = f"{timer.redraws} of {timer.frames} frames drawn anew"
    if not drawn:
        return f"0.0 fps drawn ({count})"
    line = f"{drawn:.1f} fps drawn ({ms:.1f} ms per redraw; {count})"
    scales = list(getattr(scene, "drawn_scales", ()))
    if scales:
        budget = scene.frame_budget_ms
        line += f"; render scale {statistics.median(scales):g} (median"
        line += f", frame budget {budget:g} ms)" if budget > 0 else ", dynamic resolution off)"
    return line


def report_times(timer) -> None:
    """One line of median CPU stage times and GPU pass times (ms)."""
    r = timer.report()
    cpu = ", ".join(f"{k} {v:.1f}" for k, v in r["cpu"].items())
    gpu = ", ".join(f"{k} {v:.1f}" for k, v in r["gpu"].items())
    typer.echo(f"cpu ms: {cpu}" + (f"; gpu ms: {gpu}" if gpu else ""))
