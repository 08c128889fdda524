"""``skydome timelapse``: a sky over a place from one time to another, as an MP4 or frames."""

from __future__ import annotations

import math
import statistics
import time

import typer

from skydome.cli.describe import (
    LOOKS,
    PlaceTimeSun,
    observer_from_flags,
    place_from_flags,
    precompute_progress,
    report_light_pollution,
    report_time,
    sky_description,
    time_zone_from_flags,
)
from skydome.cli.options import with_flags
from skydome.cli.parsing import parse_exposure, parse_size, parse_step, parse_time
from skydome.errors import ParameterError, check_choice, check_range

#: Time-lapses longer than this need --yes (100,000 frames is 56 minutes at 30 fps).
MAX_FRAMES_WITHOUT_YES = 100_000
#: Frames kept on the GPU per frame must be one tile.
MAX_SIDE = 2048
#: Astronomy is computed for this many frames at a time (vectorized).
CHUNK = 1000


#: Time-lapse frames draw the night layers while the Sun is below this apparent elevation
#: (deg). Above it the brightest of them, Venus at -4.7 (1.6e-4 lx: ~5 cd/m^2 at its peak
#: pixel at 640x360 and 90 deg), adds under 0.6 % to the darkest sky above 5 deg (832 cd/m^2
#: at Sun 10 deg, `earth`): under one 8-bit code value near mid-grey, and Sirius 20 times
#: less; so they are left out by day, for speed.
NIGHT_SKY_BELOW_DEG = 10.0
#: ... and while a solar eclipse hides at least this fraction of the Sun: the day sky's light
#: falls with the Sun's visible part (to first order; far more in the umbra), so near
#: totality Venus's 0.6 % of the darkest sky at 10 deg becomes 6 % and more (the planets
#: and the brightest stars come out in totality).
NIGHT_SKY_ECLIPSE_HIDDEN = 0.9


def show_night_sky(graph, state) -> None:
    """Turn the night layers of ``graph`` on while the Sun is below NIGHT_SKY_BELOW_DEG or a
    solar eclipse hides NIGHT_SKY_ECLIPSE_HIDDEN of it."""
    from skydome.description import NIGHT_LAYERS

    eclipse = state.solar_eclipse
    on = state.sun.elevation_deg < NIGHT_SKY_BELOW_DEG or (
        eclipse is not None and eclipse.hidden_fraction >= NIGHT_SKY_ECLIPSE_HIDDEN
    )
    for layer in graph.layers:
        if layer.name in NIGHT_LAYERS:
            layer.enabled = on


def register(app: typer.Typer) -> None:
    @app.command()
    @with_flags("place", "camera", "air", "display", "clouds", "weather")
    def timelapse(
        start: str = typer.Option(
            ...,
            "--start",
            help="First frame's time, ISO 8601 (without an offset or Z: the --place's local "
            "time, UTC with --lat/--lon or --utc).",
        ),
        end: str = typer.Option(
            ..., "--end", help="Last frame's time (at most), ISO 8601 (read as --start)."
        ),
        step: str = typer.Option("1min", "--step", help="Time between frames: 30s, 1min, 2h..."),
        fps: float = typer.Option(30.0, "--fps", help="Frames per second of the MP4 (1..240)."),
        output: str = typer.Option(
            ..., "-o", "--output", help="day.mp4, or a folder (frames/) for numbered frames."
        ),
        frame_format: str = typer.Option(
            "png", "--format", help="Frames in a folder: png | jpg | exr | hdr | npy."
        ),
        size: str = typer.Option("640x360", "--size", help="WIDTHxHEIGHT in pixels."),
        exposure: str = typer.Option(
            "adapt",
            "--exposure",
            help="adapt (an eye adapting over time: Krawczyk et al. 2005, Pattanaik et al. "
            "2000) or a fixed EV100. Never per-frame auto exposure, which flickers.",
        ),
        adaptation_speed: float = typer.Option(
            1.0, "--adaptation-speed", help="Eye adaptation speed-up (1 = a human eye)."
        ),
        yes: bool = typer.Option(
            False, "--yes", help=f"Allow more than {MAX_FRAMES_WITHOUT_YES:,} frames."
        ),
        replace: bool = typer.Option(
            False,
            "--replace",
            help="Delete the frames of an earlier run in the -o folder first (a folder that "
            "holds any other file is refused all the same). An MP4 is always replaced, once "
            "the new one is complete.",
        ),
        flags=None,
    ) -> None:
        """Render a time-lapse of the sky over a place: an H.264 MP4 or numbered frames."""
        import numpy as np
        from rich.console import Console

        from skydome.core.cameras import (
            CAMERAS,
            FOV_RANGE_DEG,
            MAX_ALTITUDE_M,
            PITCH_RANGE_DEG,
            YAW_RANGE_DEG,
            make_camera,
        )
        from skydome.display import TONEMAPS, ev100_to_scale, scale_to_ev100
        from skydome.display.exposure import DEFAULT_KEY, METERINGS
        from skydome.display.glare import GLARES
        from skydome.io.progress import eta_progress
        from skydome.io.video import (
            FrameSequenceWriter,
            Mp4Writer,
            check_frame_folder,
            check_video_output,
            remove_frames,
        )

        # Everything is checked before any work: bad input writes nothing.
        observer = observer_from_flags(flags)
        if observer is None:
            raise ParameterError("a time-lapse needs a place: --place NAME or --lat and --lon")
        zone = time_zone_from_flags(flags)
        t0, t1 = parse_time("--start", start, zone), parse_time("--end", end, zone)
        step_s = parse_step(step)
        # To the millisecond: Julian Dates near 2.46e6 days hold ~40 us.
        span_s = round((float(t1.jd_utc) - float(t0.jd_utc)) * 86400.0, 3)
        if span_s < 0:
            raise ParameterError(f"--end {end} is before --start {start}")
        frames = int(math.floor(span_s / step_s + 1e-9)) + 1
        if frames > MAX_FRAMES_WITHOUT_YES and not yes:
            raise ParameterError(
                f"{frames:,} frames (more than {MAX_FRAMES_WITHOUT_YES:,}): add --yes, or a "
                "longer --step"
            )
        check_range("--fps", fps, 1.0, 240.0, "fps")
        width, height = parse_size(size)
        if max(width, height) > MAX_SIDE:
            raise ParameterError(f"--size {size}: time-lapse frames are at most {MAX_SIDE} a side")
        check_choice("--camera", flags.camera, CAMERAS, "camera")
        if flags.look is not None:
            check_choice("--look", flags.look, LOOKS, "view")
        check_range("--fov", flags.fov, *FOV_RANGE_DEG, "deg")
        if flags.yaw is not None:
            check_range("--yaw", flags.yaw, *YAW_RANGE_DEG, "deg")
        if flags.pitch is not None:
            check_range("--pitch", flags.pitch, *PITCH_RANGE_DEG, "deg")
        if flags.altitude is not None:
            check_range("--altitude", flags.altitude, 0.0, MAX_ALTITUDE_M, "m")
        check_choice("--tonemap", flags.tonemap, TONEMAPS, "tone map")
        check_choice("--metering", flags.metering, METERINGS, "metering")
        check_choice("--glare", flags.glare, GLARES, "glare")
        adapt = exposure.strip().lower() == "adapt"
        ev = None if adapt else parse_exposure(exposure)
        if not adapt and ev is None:
            raise ParameterError("--exposure auto flickers in a time-lapse: use adapt or an EV100")
        check_range("--adaptation-speed", adaptation_speed, 0.01, 1e6, "")
        check_range("--exposure-compensation", flags.compensation, -20.0, 20.0, "EV")
        check_choice("--format", frame_format, ("png", "jpg", "exr", "hdr", "npy"), "format")
        # The night sky too (the stars turn, the Milky Way rises), and the clouds moved by
        # the time (their wind and weather), frame by frame. Small frames: sky-view tables
        # of a quarter of the texels, re-aimed every frame for a quarter of the cost
        # (<= 0.16 % RMS at 640 x 360, AtmosphereLayer).
        pts = PlaceTimeSun(observer, t0, 30.0, 180.0, flags.look, place_from_flags(flags), zone)
        description = sky_description(
            flags, pts, sky_view_size=(128, 128) if max(width, height) <= 1280 else None
        )
        target = check_video_output(output)
        to_mp4 = target.suffix.lower() == ".mp4"
        if to_mp4 and (width % 2 or height % 2):
            raise ParameterError(f"--size {size}: an MP4 (4:2:0) needs an even width and height")
        # A folder must be new or empty: frames of two runs must not mix. --replace deletes
        # the old frames (only files named like frames) once the sky is ready, below.
        old_frames = (
            [] if to_mp4 else check_frame_folder(target, replace=replace, replace_hint="--replace")
        )

        from skydome.cli.blas_threads import single_blas_thread
        from skydome.display.adaptation import EyeAdaptation
        from skydome.scene import state_series
        from skydome.sky import Sky, aim_camera

        single_blas_thread()  # its spinning threads would take cores from the rasterizer

        console = Console(soft_wrap=True)
        with precompute_progress(console) as report:
            sky = Sky(description, progress=report)
        report_time(t0, zone, end=t1)
        report_light_pollution(description, pts.place, None)
        graph = sky.graph
        view = flags.look or ("south" if float(observer.latitude) >= 0 else "north")

        def camera_for(state):
            aimed = aim_camera(state, view)
            return make_camera(
                flags.camera,
                fov_deg=flags.fov,
                yaw_deg=aimed.yaw_deg if flags.yaw is None else flags.yaw,
                pitch_deg=aimed.pitch_deg if flags.pitch is None else flags.pitch,
            )

        key = "eye" if flags.metering == "eye" else DEFAULT_KEY
        eye = EyeAdaptation(key, speed=adaptation_speed) if adapt else None
        fixed = None if adapt else ev100_to_scale(ev, flags.compensation)
        jd0 = float(t0.jd_utc)
        altitude = sky.altitude_m(flags.altitude)
        timings: list[float] = []
        evs: list[float] = []
        remove_frames(old_frames)
        if to_mp4:
            # x264 "veryfast": the encoder shares the CPU with a software rasterizer.
            writer = Mp4Writer(target, fps, (width, height), preset="veryfast")
        else:
            writer = FrameSequenceWriter(target, "." + frame_format, frame_count=frames)
        bar = eta_progress(console, "rendering", transient=not console.is_terminal)
        try:
            with writer, bar:
                task = bar.add_task("frames", total=frames)
                for first in range(0, frames, CHUNK):
                    count = min(CHUNK, frames - first)
                    jds = jd0 + (first + np.arange(count)) * step_s / 86400.0
                    for state in state_series(observer, jds):
                        t_start = time.perf_counter()
                        show_night_sky(graph, state)
                        cam = camera_for(state)
                        tex = graph.frame_texture(state, cam, width, height, altitude_m=altitude)
                        if adapt:
                            meter = graph.exposure_pass()
                            meter.measure(tex, flags.metering)
                            eye.update(meter.read(), step_s)
                            scale = eye.exposure_scale(flags.compensation)
                        else:
                            scale = fixed
                        if to_mp4 or not writer.hdr:
                            image = graph.display_image(
                                tex, state, cam, tex.size, flags.tonemap, scale,
                                metering=flags.metering, glare=flags.glare,
                                adaptation=eye.adapted_luminance if adapt else None,
                                compensation_ev=flags.compensation,
                            )  # fmt: skip
                            scale = graph.last_display_scale
                        else:
                            tw, th = tex.size
                            data = np.empty((th, tw, 4), np.float32)
                            tex.read_into(data, alignment=1)
                            image = data[::-1]  # GL rows are bottom-up
                        writer.write(image)
                        evs.append(scale_to_ev100(scale))
                        timings.append(time.perf_counter() - t_start)
                        bar.advance(task)
        except KeyboardInterrupt:
            # The writers have closed: the MP4 plays, the folder holds complete frames only.
            done = len(timings)
            console.print(f"interrupted: {target} holds the {done} frames rendered", style="bold")
            raise typer.Exit(130) from None
        what = (
            f"{target} ({frames} frames, {frames / fps:.1f} s at {fps:g} fps)"
            if to_mp4
            else (f"{frames} frames in {target}")
        )
        console.print(f"wrote [bold]{what}[/bold]")
        console.print(
            f"{statistics.median(timings) * 1e3:.1f} ms per frame (median), exposure EV100 "
            f"{min(evs):.2f} to {max(evs):.2f}" + (" (eye adaptation)" if adapt else "")
        )
