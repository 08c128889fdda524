"""``skydome render``: render a sky to EXR / HDR / NPY / PNG / JPEG files."""

from __future__ import annotations

import typer

from skydome.cli.describe import (
    describe_state,
    place_time_sun,
    precompute_progress,
    report_light_pollution,
    report_time,
    sky_description,
)
from skydome.cli.options import with_flags
from skydome.cli.parsing import check_int, parse_exposure, parse_size
from skydome.errors import ParameterError, check_choice, check_range

#: Ray-march samples per view ray accepted by the single-scattering model.
MAX_VIEW_SAMPLES = 4096


def cie_settings(
    model: str, cie_type: int, illuminance: float | None, zenith: float | None, flags
) -> dict:
    """The --cie-* flags as SkyDescription settings, checked: only with --model cie, which
    needs exactly one scale and takes no clouds or light pollution."""
    if model != "cie":
        if illuminance is not None or zenith is not None or cie_type != 12:
            raise ParameterError("--cie-type, --cie-illuminance and --cie-zenith need --model cie")
        return {}
    check_int("--cie-type", cie_type, 1, 15)
    if (illuminance is None) == (zenith is None):
        raise ParameterError(
            "--model cie needs its scale: --cie-illuminance LX (the sky's diffuse horizontal "
            "illuminance) or --cie-zenith CD_M2, one of them"
        )
    if illuminance is not None:
        check_range("--cie-illuminance", illuminance, 0.0, 1e6, "lx")
    if zenith is not None:
        check_range("--cie-zenith", zenith, 0.0, 1e6, "cd/m^2")
    if getattr(flags, "clouds", None) is not None or getattr(flags, "bortle", None) is not None:
        raise ParameterError("--model cie is the standard's sky alone: no --clouds or --bortle")
    return {"cie_type": cie_type, "cie_illuminance": illuminance, "cie_zenith_luminance": zenith}


def register(app: typer.Typer) -> None:
    @app.command()
    @with_flags("place", "sun", "camera", "air", "tables", "night", "display", "clouds", "weather")
    def render(
        when: str = typer.Option(
            None,
            "--time",
            help="ISO 8601 date and time, e.g. 2018-03-01T20:00 or 2018-03-01T19:00Z. Without "
            "an offset or Z it is the --place's local time (its IANA time zone, daylight "
            "saving included), UTC with --lat/--lon or --utc.",
        ),
        size: str = typer.Option(
            "1280x720", "--size", help="WIDTHxHEIGHT in pixels (cubemap: face size from HEIGHT)."
        ),
        roll: float = typer.Option(
            0.0, "--roll", help="Camera roll about the view direction, degrees."
        ),
        supersample: int = typer.Option(
            1,
            "--supersample",
            help="Rays a pixel side, n (n x n rays a pixel, their mean; n^2 times the work; "
            "at most 4): antialiases detail finer than a pixel, above all clouds "
            "near the horizon.",
        ),
        model: str = typer.Option(
            "precomputed",
            "--model",
            help="precomputed (every scattering order) | single | cie (a CIE standard general "
            "sky, ISO 15469, in place of the air: give --cie-illuminance or --cie-zenith).",
        ),
        cie_type: int = typer.Option(
            12, "--cie-type", help="--model cie: the CIE sky type, 1 (overcast) to 15."
        ),
        cie_illuminance: float = typer.Option(
            None,
            "--cie-illuminance",
            help="--model cie: the sky's diffuse horizontal illuminance, lx (or --cie-zenith).",
        ),
        cie_zenith: float = typer.Option(
            None, "--cie-zenith", help="--model cie: the zenith luminance, cd/m^2."
        ),
        samples: int = typer.Option(
            None,
            "--samples",
            help=f"Ray-march samples per view ray (1..{MAX_VIEW_SAMPLES}, default 16), for "
            "--model single only: the precomputed model has no ray march and refuses it.",
        ),
        exposure: str = typer.Option(
            "auto", "--exposure", help="'auto' or EV100 (e.g. 15 for noon)."
        ),
        output: list[str] = typer.Option(
            ["sky.png"],
            "-o",
            "--output",
            help="Output file(s), repeatable: .exr or .hdr (absolute units), .npy, "
            ".png or .jpg (tone mapped).",
        ),
        flags=None,
    ) -> None:
        """Render a sky in absolute units (cd/m^2) and write it as EXR, HDR, NPY, or PNG and JPEG
        (tone mapped)."""
        from rich.console import Console

        from skydome.core.cameras import (
            CAMERAS,
            FOV_RANGE_DEG,
            MAX_ALTITUDE_M,
            PITCH_RANGE_DEG,
            ROLL_RANGE_DEG,
            YAW_RANGE_DEG,
            make_camera,
        )
        from skydome.core.tiles import MAX_SUPERSAMPLE
        from skydome.description import SKY_MODELS
        from skydome.display import TONEMAPS, ev100_to_scale, scale_to_ev100
        from skydome.display.exposure import METERINGS
        from skydome.display.glare import GLARES
        from skydome.io import WRITERS, check_output_path, write_outputs
        from skydome.sky import Sky, default_look

        # Validate everything before any work, so bad input writes nothing.
        pts = place_time_sun(flags, when)
        abstract = pts.abstract
        width, height = parse_size(size)
        ev = parse_exposure(exposure)
        check_range("--exposure-compensation", flags.compensation, -20.0, 20.0, "EV")
        if flags.altitude is not None:
            check_range("--altitude", flags.altitude, 0.0, MAX_ALTITUDE_M, "m")
        check_choice("--tonemap", flags.tonemap, TONEMAPS, "tone map")
        check_choice("--metering", flags.metering, METERINGS, "metering")
        check_choice("--glare", flags.glare, GLARES, "glare")
        check_choice("--model", model, SKY_MODELS, "model")
        cie = cie_settings(model, cie_type, cie_illuminance, cie_zenith, flags)
        check_choice("--camera", flags.camera, CAMERAS, "camera")
        if samples is not None:
            if model != "single":
                raise ParameterError(
                    f"--samples applies only to --model single; the {model} model reads "
                    "every ray from its tables (drop --samples or add --model single)"
                )
            check_int("--samples", samples, 1, MAX_VIEW_SAMPLES)
        check_range("--fov", flags.fov, *FOV_RANGE_DEG, "deg")
        if flags.pitch is not None:
            check_range("--pitch", flags.pitch, *PITCH_RANGE_DEG, "deg")
        check_range("--roll", roll, *ROLL_RANGE_DEG, "deg")
        check_int("--supersample", supersample, 1, MAX_SUPERSAMPLE)
        if flags.yaw is not None:
            check_range("--yaw", flags.yaw, *YAW_RANGE_DEG, "deg")
        description = sky_description(
            flags, pts, model=model, samples=16 if samples is None else samples, **cie
        )
        paths = [check_output_path(p) for p in output]
        if len({str(p.resolve()) for p in paths}) != len(paths):
            raise ParameterError("-o/--output: the same path is given twice")

        console = Console(soft_wrap=True)
        with precompute_progress(console) as report:
            sky = Sky(description, progress=report)
        with sky:
            for line in describe_state(sky.state):
                console.print(line)
            if not abstract and sky.state.sun.elevation_deg < -12.0:
                from skydome.night.glow_layer import zenith_brightness

                glow = zenith_brightness(sky.state, sky.layers)
                console.print(
                    "night glow at the zenith, V mag/arcsec^2 outside the air: "
                    + ", ".join(f"{name} {m:.2f}" for name, m in glow.items())
                )
            target = flags.look or (default_look(sky.state) if not abstract else None)
            if target is not None:
                aim = sky.camera(target)
                view_yaw, view_pitch = aim.yaw_deg, aim.pitch_deg
            else:
                view_yaw, view_pitch = pts.sun_azimuth_deg, 15.0
            cam = make_camera(
                flags.camera,
                fov_deg=flags.fov,
                yaw_deg=view_yaw if flags.yaw is None else flags.yaw,
                pitch_deg=view_pitch if flags.pitch is None else flags.pitch,
                roll_deg=roll,
            )
            want_ldr = any(not WRITERS[p.suffix.lower()].hdr for p in paths)
            rays = f", {supersample}x{supersample} rays a pixel" if supersample > 1 else ""
            # a spinner on a terminal (nothing when the output is piped)
            with console.status(f"rendering {width}x{height}{rays}..."):
                frame = sky.render(
                    cam,
                    width,
                    height,
                    altitude_m=flags.altitude,
                    exposure="auto" if ev is None else ev,
                    compensation_ev=flags.compensation,
                    tonemap=flags.tonemap if want_ldr else None,
                    metering=flags.metering,
                    glare=flags.glare,
                    supersample=supersample,
                )
        scale = ev100_to_scale(frame.info["exposure_ev100"])
        metadata = {
            **frame.info,
            "exposure_ev100": scale_to_ev100(scale),
            "tonemap": flags.tonemap,
        }
        written = write_outputs(paths, frame.data, frame.image, metadata=metadata)
        if not abstract:  # on stderr, once the frame is made (a failure prints one line)
            report_time(pts.time, pts.zone)
            report_light_pollution(description, pts.place, flags.bortle)
        h, w = frame.shape
        for p in written:
            console.print(f"wrote [bold]{p}[/bold] ({w}x{h})")
        console.print(
            f"frame {frame.info['render_ms']:.1f} ms ({model}, {flags.camera}, "
            + (f"type {cie_type}" if model == "cie" else description.atmosphere.name)
            + f"), exposure EV100 {scale_to_ev100(scale):.2f}"
            + (f" (auto, {flags.metering} metering)" if ev is None else "")
        )
        if model == "cie":
            console.print(
                f"CIE sky type {cie_type}: zenith {frame.info['cie_zenith_luminance']:.0f} "
                f"cd/m^2, diffuse horizontal {frame.info['cie_diffuse_horizontal_lux']:.0f} lx"
            )
        if description.weather is not None:
            wx = description.weather
            falling = "".join(
                f", {name} {rate:g} mm/h"
                for name, rate in (("rain", wx.rain_mm_h), ("snow", wx.snow_mm_h))
                if rate > 0
            )
            console.print(
                f"weather: {wx.preset}{falling}, visibility {description.visibility_km:.3g} km"
            )
        if frame.info.get("cloud_optical_depth_mean") is not None:
            i = frame.info
            console.print(
                f"clouds: {i['clouds']}, coverage {i['coverage']:.2f}, optical depth "
                f"{i['cloud_optical_depth']:.1f} per cloud; columns: mean "
                f"{i['cloud_optical_depth_mean']:.1f}, {100 * i['cloud_fraction']:.0f} % cloudy"
            )
