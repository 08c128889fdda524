"""Render the README gallery into docs/gallery/ (small PNGs, auto exposure, filmic).

Usage: python tools/make_gallery.py [--model single] [--size 480x270] [--scene] [--night]
       [--clouds] [--weather] [--optics]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from skydome import FisheyeCamera, PerspectiveCamera, Sky
from skydome.display import auto_exposure, ev100_to_scale, tonemap
from skydome.io import atomic_write, write_outputs, write_png
from skydome.scene.state import state_series

OUT = Path(__file__).resolve().parents[1] / "docs" / "gallery"


def render_sky(
    *,
    sun_elevation_deg,
    sun_azimuth_deg=180.0,
    camera,
    width,
    height,
    atmosphere="earth",
    model="precomputed",
    altitude_m=1.7,
    **frame_kwargs,
):
    """A frame (cd/m^2, no exposure) of a Sun alone over ``atmosphere`` (a Sky of the abstract
    mode: the Sun's disk and the air, or the single-scattering model's own)."""
    with Sky(sun_elevation_deg=sun_elevation_deg, sun_azimuth_deg=sun_azimuth_deg,
             atmosphere=atmosphere, model=model) as sky:  # fmt: skip
        return sky.render(camera, width, height, altitude_m=altitude_m, exposure=None,
                          **frame_kwargs)  # fmt: skip


# name: (sun elevation, sun azimuth, camera altitude m, camera or None, atmosphere)
# Exposure is automatic except where an EV100 is given: a sunset over a ground that single
# scattering leaves unlit drags the log-average far below the sky.
EV100 = {"sunset": 10.7}
VIEWS = {
    "noon": (60.0, 180.0, 1.7, PerspectiveCamera(fov_deg=90, yaw_deg=150, pitch_deg=20), "earth"),
    "sun10": (10.0, 250.0, 1.7, PerspectiveCamera(fov_deg=90, yaw_deg=250, pitch_deg=15), "earth"),
    "sunset": (0.0, 270.0, 1.7, PerspectiveCamera(fov_deg=90, yaw_deg=270, pitch_deg=15), "earth"),
    "sun-4": (-4.0, 270.0, 1.7, PerspectiveCamera(fov_deg=90, yaw_deg=270, pitch_deg=15), "earth"),
    "altitude10km": (
        20.0,
        200.0,
        10_000.0,
        PerspectiveCamera(fov_deg=100, yaw_deg=200, pitch_deg=0),
        "earth",
    ),
    "space1000km": (
        15.0,
        90.0,
        1_000_000.0,
        PerspectiveCamera(fov_deg=100, yaw_deg=60, pitch_deg=-28),
        "earth",
    ),
    "mars": (25.0, 180.0, 1.7, PerspectiveCamera(fov_deg=90, yaw_deg=170, pitch_deg=15), "mars"),
    "hazy": (15.0, 200.0, 1.7, PerspectiveCamera(fov_deg=90, yaw_deg=200, pitch_deg=15), "hazy"),
    "fisheye": (30.0, 135.0, 1.7, FisheyeCamera(), "earth"),
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", default="precomputed", help="precomputed | single")
    ap.add_argument("--size", default="480x270")
    ap.add_argument("--only", default="", help="comma-separated view names")
    ap.add_argument("--scene", action="store_true", help="only the place-and-time views")
    ap.add_argument("--night", action="store_true", help="only the night-sky views")
    ap.add_argument("--mars", action="store_true", help="only Mars at noon and at sunset")
    ap.add_argument("--clouds", action="store_true", help="only the cloud views")
    ap.add_argument("--weather", action="store_true", help="only the weather views")
    ap.add_argument("--optics", action="store_true", help="only the optics views")
    ap.add_argument("--ground", action="store_true", help="only the ground's kinds")
    args = ap.parse_args()
    w, h = (int(v) for v in args.size.split("x"))
    OUT.mkdir(parents=True, exist_ok=True)
    if args.mars:
        mars_views(w, h)
        return
    if args.clouds:
        cloud_views(w, h)
        return
    if args.weather:
        weather_views(w, h)
        return
    if args.optics:
        optics_views(w, h)
        return
    if args.ground:
        ground_views(w)
        return
    if args.scene or args.night:
        if args.scene:
            scene_views(w, h)
        if args.night:
            night_views(w, h)
        return
    names = [n for n in VIEWS if not args.only or n in args.only.split(",")]
    for name in names:
        el, az, alt, cam, atmosphere = VIEWS[name]
        size = (h, h) if isinstance(cam, FisheyeCamera) else (w, h)
        frame = render_sky(
            sun_elevation_deg=el,
            sun_azimuth_deg=az,
            altitude_m=alt,
            camera=cam,
            width=size[0],
            height=size[1],
            atmosphere=atmosphere,
            model=args.model,
        )
        ev = EV100.get(name)
        scale = auto_exposure(frame, clip_percentile=99.5) if ev is None else ev100_to_scale(ev)
        ldr = tonemap(frame, "filmic", scale)
        path = OUT / f"{args.model}-{name}.png"
        write_outputs([path], frame.data, ldr, metadata=frame.info)
        print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")
    if not args.only:
        side_by_side(w, h)
        if args.model == "precomputed":
            aerial_perspective(w, h)
            light_shafts(w, h)
            real_earth(w, h)
            scene_views(w, h)
            night_views(w, h)


def side_by_side(w: int, h: int) -> None:
    """Single vs multiple scattering at Sun -4 deg, one exposure for both (EV100 7)."""
    import numpy as np

    cam = PerspectiveCamera(fov_deg=90, yaw_deg=270, pitch_deg=15)
    halves = []
    for model in ("single", "precomputed"):
        frame = render_sky(
            sun_elevation_deg=-4.0,
            sun_azimuth_deg=270.0,
            camera=cam,
            width=w // 2,
            height=h,
            model=model,
        )
        halves.append(tonemap(frame, "filmic", ev100_to_scale(7.0)))
    both = np.concatenate(halves, axis=1)
    path = OUT / "compare-single-multiple-sun-4.png"
    atomic_write(
        path, lambda tmp: write_png(tmp, both, {"views": "single | precomputed, Sun -4 deg"})
    )
    print(f"{path.relative_to(OUT.parents[1])}")


def aerial_perspective(w: int, h: int) -> None:
    """Ridges at 3, 15 and 60 km composited through the aerial perspective of a depth image:
    composite = scene x transmittance + in-scattered light (Sun 6 deg, camera at 2 m)."""
    import numpy as np

    cam = PerspectiveCamera(fov_deg=90, yaw_deg=230, pitch_deg=5)
    x, y = np.arange(w)[None, :], np.arange(h)[:, None]
    depth_m = np.zeros((h, w))
    for dist_m, base, amp, freq in (
        (60e3, 0.42, 0.07, 8.3),
        (15e3, 0.49, 0.055, 13.4),
        (3e3, 0.57, 0.05, 21.0),
    ):
        top = h * (base + amp * np.sin(freq * x / w + dist_m / 1e4))
        depth_m = np.where(y > top, dist_m, depth_m)
    frame = render_sky(sun_elevation_deg=6.0, sun_azimuth_deg=250.0, camera=cam, width=w,
                       height=h, altitude_m=2.0, depth_m=depth_m)  # fmt: skip
    hills = np.where(depth_m[..., None] > 0, np.array([30.0, 40.0, 25.0]), 0.0)  # cd/m^2
    composite = frame.rgb + frame.info["transmittance"] * hills
    ldr = tonemap(composite, "filmic", auto_exposure(composite))
    path = OUT / "precomputed-aerial-perspective.png"
    atomic_write(path, lambda tmp: write_png(tmp, ldr, {"views": "ridges at 3, 15, 60 km"}))
    print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")


def light_shafts(w: int, h: int) -> None:
    """Crepuscular rays: 14 wedges around the Sun (4 deg) whose first 8 km lie in shadow."""
    import numpy as np

    cam = PerspectiveCamera(fov_deg=90, yaw_deg=250, pitch_deg=10)
    angle = np.arctan2((0.59 * h - np.arange(h))[:, None], (np.arange(w) - w / 2)[None, :])
    shadow_m = np.where(np.sin(14 * angle) > 0.3, 8000.0, 0.0)
    frame = render_sky(sun_elevation_deg=4.0, sun_azimuth_deg=250.0, camera=cam, width=w,
                       height=h, altitude_m=2.0, shadow_length_m=shadow_m)  # fmt: skip
    ldr = tonemap(frame, "filmic", auto_exposure(frame.rgb * (shadow_m[..., None] == 0)))
    path = OUT / "precomputed-light-shafts.png"
    atomic_write(
        path, lambda tmp: write_png(tmp, ldr, {"views": "shadow lengths of 8 km in wedges"})
    )
    print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")


def _strip(frames: list, ev100: float | None, path: Path, note: str) -> None:
    """Frames side by side (left to right), one exposure for all: ``ev100``, or automatic on
    the first frame."""
    import numpy as np

    scale = auto_exposure(frames[0], clip_percentile=99.5) if ev100 is None else None
    scale = scale if scale is not None else ev100_to_scale(ev100)
    both = np.concatenate([tonemap(f, "filmic", scale) for f in frames], axis=1)
    atomic_write(path, lambda tmp: write_png(tmp, both, {"views": note}))
    print(f"{path.relative_to(OUT.parents[1])}")


def real_earth(w: int, h: int) -> None:
    """The measured Earth against the seeds' Earth at Sun 30, 0, -6 and -12 deg (each pair at
    one exposure: earth_bruneton left, earth right), the aerosol types at Sun 10 deg (one
    exposure), Mars at noon and at sunset."""
    cam = PerspectiveCamera(fov_deg=90, yaw_deg=270, pitch_deg=10)
    for el, ev in ((30.0, 14.5), (0.0, 10.5), (-6.0, 4.0), (-12.0, -3.0)):
        frames = [
            render_sky(sun_elevation_deg=el, sun_azimuth_deg=270.0, camera=cam, width=w // 2,
                       height=h, atmosphere=name)
            for name in ("earth_bruneton", "earth")
        ]  # fmt: skip
        tag = f"{el:+.0f}".replace("+", "")
        _strip(
            frames,
            ev,
            OUT / f"compare-earth-bruneton-sun{tag}.png",
            f"earth_bruneton | earth, Sun {el} deg",
        )
    types = ("earth", "typical", "maritime", "desert", "urban")
    cam = PerspectiveCamera(fov_deg=70, yaw_deg=250, pitch_deg=12)
    frames = [
        render_sky(sun_elevation_deg=10.0, sun_azimuth_deg=250.0, camera=cam, width=w // 2,
                   height=h, atmosphere=name)
        for name in types
    ]  # fmt: skip
    _strip(frames, 13.0, OUT / "aerosol-types-sun10.png", " | ".join(types) + ", Sun 10 deg")
    mars_views(w, h)


def mars_views(w: int, h: int) -> None:
    """Mars at noon and at sunset, each at its own exposure."""
    mars = []
    for el, cam in (
        (70.0, PerspectiveCamera(fov_deg=90, yaw_deg=180, pitch_deg=20)),
        (2.0, PerspectiveCamera(fov_deg=70, yaw_deg=270, pitch_deg=8)),
    ):
        frame = render_sky(sun_elevation_deg=el, sun_azimuth_deg=270.0 if el < 10 else 200.0,
                           camera=cam, width=w // 2, height=h, atmosphere="mars")  # fmt: skip
        mars.append(tonemap(frame, "filmic", auto_exposure(frame, clip_percentile=99.5)))
    import numpy as np

    path = OUT / "mars-noon-sunset.png"
    atomic_write(path, lambda tmp: write_png(tmp, np.concatenate(mars, axis=1), {"views": "mars"}))
    print(f"{path.relative_to(OUT.parents[1])}")


def cloud_views(w: int, h: int) -> None:
    """Clouds (issues 12, 22), full quality, auto exposure: fair-weather cumulus at noon, a
    sunset under stratocumulus lit from below, the overcast, a rainy nimbostratus day, a
    storm, cirrus alone, a moonlit cloudy night, the view from 10 km above the clouds, and
    crepuscular rays (light shafts)."""
    from skydome.clouds.layer import CloudLayer
    from skydome.clouds.params import Clouds
    from skydome.core.cameras import PerspectiveCamera as Cam

    valletta = (35.8989, 14.5146, 56.0)
    # name: (time, clouds, look (yaw from the Sun's azimuth, pitch), fov, altitude m, shafts, note)
    views = {
        "clouds-fair-noon": ("2021-06-21T10:00Z", Clouds("fair", seed=3), (60, 20), 90, None,
                             None, "fair-weather cumulus, Valletta 2021-06-21 10:00 UTC"),
        "clouds-sunset-stratocumulus": (
            "2021-06-21T18:12Z", Clouds("broken", coverage=0.75, base_m=1800, seed=4), (0, 6),
            90, None, None, "sunset under stratocumulus lit from below"),
        "clouds-overcast": ("2021-06-21T10:00Z", Clouds("overcast", seed=5), (90, 15), 90, None,
                            None, "overcast: a closed stratus deck, optical depth 37.5"),
        "clouds-nimbostratus": ("2021-06-21T10:00Z", Clouds("nimbostratus", seed=5), (90, 10),
                                90, None, None, "a rainy day under nimbostratus"),
        "clouds-storm": ("2021-06-21T15:00Z", Clouds("storm", seed=6), (120, 15), 100, None,
                         None, "cumulonimbus with rain"),
        "clouds-cirrus": ("2021-06-21T08:00Z", Clouds("cirrus", seed=7), (40, 35), 90, None,
                          None, "cirrus and cirrostratus alone"),
        "clouds-above-10km": ("2021-06-21T09:00Z", Clouds("fair", coverage=0.55, seed=3),
                              (60, -20), 100, 10_000.0, None, "fair cumulus seen from 10 km"),
        "clouds-crepuscular-rays": (
            "2021-06-21T17:50Z", Clouds("fair", coverage=0.15, seed=1), (0, 18), 100, None, True,
            "crepuscular rays: the clouds' shadows in the air, converging on the low Sun"),
    }  # fmt: skip
    # a broken deck at the horizon is finer than a pixel: 2 x 2 rays a pixel there
    supersample = {"clouds-sunset-stratocumulus": 2}
    for name, (time, clouds, (dyaw, pitch), fov, alt, shafts, note) in views.items():
        sky = Sky(valletta, time, night=False,
                  clouds=CloudLayer(clouds, shafts=shafts))  # fmt: skip
        sun = sky.state.sun
        cam = Cam(fov_deg=fov, yaw_deg=(sun.azimuth_deg + dyaw) % 360, pitch_deg=pitch)
        frame = sky.render(cam, w, h, altitude_m=alt, tonemap="filmic",
                           supersample=supersample.get(name, 1))  # fmt: skip
        path = OUT / f"{name}.png"
        atomic_write(path, lambda tmp, f=frame, n=note: write_png(tmp, f.image, {"views": n}))
        print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")
        sky.release()
    # A moonlit cloudy night: Valletta, 2018-03-01 23:00 UTC, the full Moon 63 deg up.
    sky = Sky("Valletta", "2018-03-01T23:00Z", clouds=Clouds("fair", coverage=0.5, seed=3))
    moon = sky.state.moon
    cam = Cam(fov_deg=100, yaw_deg=moon.azimuth_deg, pitch_deg=moon.elevation_deg - 25)
    frame = sky.render(cam, w, h, tonemap="filmic", compensation_ev=-1.0)
    path = OUT / "clouds-moonlit-night.png"
    atomic_write(path, lambda tmp: write_png(tmp, frame.image, {"views": "moonlit cumulus"}))
    print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")


def hills_panorama(path: Path, width: int = 4096) -> None:
    """A made-up landscape panorama (skydome's own, for the gallery): rolling hills 1.5-6
    deg high, a ridge in the west, grass-green (sRGB 70, 95, 55), antialiased against a
    transparent sky; equirect, north at the left edge."""
    import numpy as np
    from PIL import Image

    h = width // 2
    az = (np.arange(width) + 0.5) / width * 360.0
    el = 90.0 - (np.arange(h) + 0.5) / h * 180.0
    hill = (3.0 + 1.5 * np.sin(np.radians(3 * az)) + np.sin(np.radians(7 * az + 40))
            + 2.5 * np.exp(-(((az - 270.0) / 25.0) ** 2)))  # fmt: skip
    coverage = np.clip((hill[None, :] - el[:, None]) / (180.0 / h) + 0.5, 0.0, 1.0)
    img = np.zeros((h, width, 4), np.uint8)
    img[..., :3] = (70, 95, 55)
    img[..., 3] = np.round(coverage * 255.0).astype(np.uint8)
    Image.fromarray(img).save(path)


def ground_views(w: int) -> None:
    """The ground's kinds (issue 26) in equirect maps of Valletta at dusk (the Sun 3 deg
    down), one exposure for the three: the default grey ground, none (the air's glow in
    front of a ground that reflects nothing), black (zero below the horizon); and a
    landscape panorama (hills_panorama) at sunset, looking west."""
    import tempfile

    from skydome.core.cameras import EquirectCamera

    where = {"place": "Valletta", "time": "2018-03-01T17:05Z"}
    ev100 = None
    for kind in ("default", "none", "black"):
        with Sky(ground=None if kind == "default" else kind, **where) as sky:
            frame = sky.render(EquirectCamera(), w, w // 2, exposure=None)
        if ev100 is None:
            ev100 = auto_exposure(frame, clip_percentile=99.5)
        ldr = tonemap(frame, "filmic", ev100)
        path = OUT / f"ground-{kind}.png"
        write_outputs([path], frame.data, ldr, metadata=frame.info)
        print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")
    with tempfile.TemporaryDirectory() as tmp:
        pano = Path(tmp) / "hills.png"
        hills_panorama(pano)
        with Sky("Valletta", "2018-03-01T16:45Z", ground=str(pano)) as sky:
            cam = PerspectiveCamera(fov_deg=70.0, yaw_deg=262.0, pitch_deg=6.0)
            frame = sky.render(cam, w, w * 9 // 16, tonemap="filmic")
    path = OUT / "ground-landscape.png"
    write_outputs([path], frame.data, frame.image, metadata=frame.info)
    print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")


def weather_views(w: int, h: int) -> None:
    """Weather (issue 23), full quality, auto exposure: a foggy morning with the Sun a pale
    disk, a fog sea seen from a hill, mist at sunrise, a rainy day under nimbostratus with
    rain falling, a thunderstorm with rain shafts, snow falling at dusk, showers' rainbows."""
    from skydome.core.cameras import PerspectiveCamera as Cam
    from skydome.weather import Weather

    # name: (sun elevation, azimuth, weather, (yaw, pitch), fov, altitude m, note)
    views = {
        "weather-fog-morning": (12.0, 100.0, Weather("fog", visibility_km=0.3),
                                (100, 8), 80, None, "a foggy morning: 300 m, the Sun a pale disk"),
        "weather-fog-sea": (6.0, 95.0, Weather("fog", visibility_km=0.2, fog_top_m=120),
                            (95, -3), 80, 250.0, "a fog sea from a hill 250 m up"),
        "weather-mist-sunrise": (2.0, 90.0, Weather("mist"), (90, 5), 90, None,
                                 "mist at sunrise: 2.5 km of visibility"),
        "weather-rain": (35.0, 180.0, Weather("rain", rain_mm_h=8, wind_m_s=(3.0, 0.0)),
                         (200, 2), 80, None, "8 mm/h of rain under nimbostratus"),
        "weather-thunderstorm": (40.0, 240.0, Weather("thunderstorm"), (120, 12), 100, None,
                                 "a thunderstorm: rain shafts under the cells"),
        "weather-snow-dusk": (1.0, 250.0, Weather("snow", snow_mm_h=2), (250, 5), 80, None,
                              "snow falling at dusk"),
        "weather-rainbow": (15.0, 270.0, Weather("rain", rain_mm_h=8, clouds="fair"),
                            (90, 25), 120, None,
                            "showers under fair cumulus, the Sun 15 deg up behind: rainbows"),
    }  # fmt: skip
    for name, (el, az, weather, (yaw, pitch), fov, alt, note) in views.items():
        with Sky(sun_elevation_deg=el, sun_azimuth_deg=az, weather=weather) as sky:
            cam = Cam(fov_deg=fov, yaw_deg=yaw, pitch_deg=pitch)
            frame = sky.render(cam, w, h, altitude_m=alt, tonemap="filmic")
        path = OUT / f"{name}.png"
        atomic_write(path, lambda tmp, f=frame, n=note: write_png(tmp, f.image, {"views": n}))
        print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")


def optics_views(w: int, h: int) -> None:
    """Optics (issue 24), full quality, auto exposure: the glory around the antisolar point
    seen from an aircraft 600 m above an overcast's top (the droplets' Mie phase function by
    output channel); a double rainbow at 18:00, a moonbow, a fogbow; ice halos in diamond
    dust and in cirrostratus (the crystals' ray-traced table)."""
    from skydome.core.cameras import PerspectiveCamera as Cam

    with Sky(sun_elevation_deg=35.0, sun_azimuth_deg=200.0, clouds="overcast") as sky:
        c = sky.layer("clouds").clouds
        sun = sky.state.sun
        cam = Cam(fov_deg=40, yaw_deg=(sun.azimuth_deg + 180.0) % 360.0,
                  pitch_deg=-sun.elevation_deg)  # fmt: skip
        frame = sky.render(
            cam, w, h, altitude_m=c.top_m + 600.0, tonemap="filmic", compensation_ev=1.5
        )  # a sunlit deck is white, not mid-grey
    path = OUT / "optics-glory.png"
    note = "the glory from 600 m above an overcast, the Sun 35 deg up behind"
    atomic_write(path, lambda tmp: write_png(tmp, frame.image, {"views": note}))
    print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")
    # bows: name: (place, time UTC, weather, light ("sun"/"moon"), pitch, note)
    import datetime as dt

    from skydome.weather import Weather

    bows = {
        "optics-double-rainbow": (
            "vienna", dt.datetime(2026, 9, 1, 16, 0, tzinfo=dt.timezone.utc),
            Weather("rain", rain_mm_h=6, clouds="fair"), "sun", 16.0,
            "Vienna, 2026-09-01 18:00 local, after a shower: both bows and Alexander's band",
        ),
        "optics-moonbow": (
            "valletta", dt.datetime(2018, 3, 1, 19, 0, tzinfo=dt.timezone.utc),
            Weather("rain", rain_mm_h=6, clouds="fair"), "moon", 12.0,
            "Valletta, 2018-03-01 19:00 UTC: a moonbow under the full Moon (a long exposure)",
        ),
    }  # fmt: skip
    for name, (place, time, weather, light, pitch, note) in bows.items():
        with Sky(place=place, time=time, weather=weather) as sky:
            body = sky.state.sun if light == "sun" else sky.state.moon
            cam = Cam(fov_deg=110, yaw_deg=(body.azimuth_deg + 180.0) % 360.0, pitch_deg=pitch)
            frame = sky.render(cam, w, h, tonemap="filmic")
        path = OUT / f"{name}.png"
        atomic_write(path, lambda tmp, f=frame, n=note: write_png(tmp, f.image, {"views": n}))
        print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")
    fog = Weather("fog", visibility_km=0.15, fog_top_m=40.0)
    with Sky(sun_elevation_deg=12.0, sun_azimuth_deg=90.0, weather=fog) as sky:
        frame = sky.render(sky.camera("antisun", fov_deg=110, pitch_deg=10), w, h,
                           tonemap="filmic")  # fmt: skip
    path = OUT / "optics-fogbow.png"
    note = "a fogbow in 40 m of fog (150 m visibility), the Sun 12 deg up behind"
    atomic_write(path, lambda tmp: write_png(tmp, frame.image, {"views": note}))
    print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")
    with Sky(sun_elevation_deg=15.0, sun_azimuth_deg=180.0,
             weather=Weather("diamond-dust")) as sky:  # fmt: skip
        frame = sky.render(Cam(fov_deg=110, yaw_deg=180.0, pitch_deg=23.0), w, h,
                           tonemap="filmic")  # fmt: skip
    path = OUT / "optics-diamond-dust.png"
    note = "diamond dust, the Sun 15 deg up: halos, sun dogs and arcs in clear air near the ground"
    atomic_write(path, lambda tmp: write_png(tmp, frame.image, {"views": note}))
    print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")
    # ice halos in a cirrostratus: name: (sun elevation, halos, (pitch, fov), note)
    views = {
        "optics-halo-sundogs": (20.0, "random:0.6,plates:0.25,columns:0.15", (20, 110),
                                "cirrostratus, the Sun 20 deg up: the 22 deg halo, sun dogs, "
                                "the upper tangent arc"),
        "optics-circumzenithal": (22.0, "plates:0.7,random:0.3", (62, 100),
                                  "plates in cirrus, the Sun 22 deg up: the circumzenithal "
                                  "arc 46 deg above it"),
    }  # fmt: skip
    from skydome.clouds.params import Clouds

    for name, (el, halos, (pitch, fov), note) in views.items():
        clouds = Clouds("cirrus", cirrus=0.9, halos=halos)
        with Sky(sun_elevation_deg=el, sun_azimuth_deg=180.0, clouds=clouds) as sky:
            frame = sky.render(Cam(fov_deg=fov, yaw_deg=180.0, pitch_deg=pitch), w, h,
                               tonemap="filmic")  # fmt: skip
        path = OUT / f"{name}.png"
        atomic_write(path, lambda tmp, f=frame, n=note: write_png(tmp, f.image, {"views": n}))
        print(f"{path.relative_to(OUT.parents[1])}: {frame.info['render_ms']:.0f} ms")


def scene_views(w: int, h: int) -> None:
    """The sky for a place and time (skydome.scene): Valletta 2018-03-01 19:00 UTC looking at
    the Moon, a setting (flattened) Sun, a crescent Moon with earthshine at dusk, a full-Moon
    night, and a strip from a 24-hour time-lapse."""
    import numpy as np

    from skydome.sky import aim_camera

    def save(name: str, image, note: str) -> None:
        path = OUT / f"{name}.png"
        atomic_write(path, lambda tmp: write_png(tmp, image, {"views": note}))
        print(f"{path.relative_to(OUT.parents[1])}")

    def shot(sky, cam, width, height, ev=None):
        return sky.render(
            cam, width, height, exposure="auto" if ev is None else ev, tonemap="filmic"
        ).image

    valletta = Sky("Valletta", "2018-03-01T19:00Z")
    wide = shot(valletta, valletta.camera("moon", fov_deg=90), w, h)
    zoom = shot(valletta, valletta.camera("moon", fov_deg=1.2), h, h, ev=11.0)
    save("scene-valletta-moon", np.concatenate([wide, zoom], axis=1),
         "Valletta 2018-03-01 19:00 UTC: the full Moon 28 deg up (auto exposure) and its disk (EV 11)")  # fmt: skip
    # Dusk at Valletta, 18:15 local: the Sun 4.5 deg down, the full Moon rising in the east
    # over the Earth's shadow, the afterglow in the west.
    dusk = Sky("Valletta", "2018-03-01T17:15Z")
    east = shot(dusk, dusk.camera("moon", fov_deg=80, pitch_deg=12), w, h)
    west = shot(dusk, aim_camera(dusk.state, "west", fov_deg=80, pitch_deg=12), w, h)
    save("scene-valletta-dusk", np.concatenate([east, west], axis=1),
         "Valletta 2018-03-01 18:15 local (17:15 UTC), Sun -4.5 deg: the full Moon rising in "
         "the east over the Earth's shadow, and the afterglow in the west")  # fmt: skip
    # Sunset at Valletta, 2018-03-01: the apparent Sun half a degree up.
    sunset = Sky("Valletta", "2018-03-01T16:52Z")
    flat = shot(sunset, sunset.camera("sun", fov_deg=2.0), h, h, ev=22.0)
    view = shot(sunset, sunset.camera("sun", fov_deg=70, pitch_deg=8), w, h)
    save("scene-setting-sun", np.concatenate([view, flat], axis=1),
         f"Valletta 2018-03-01 16:52 UTC, Sun {sunset.state.sun.elevation_deg:.2f} deg: flattened and reddened at its lower limb")  # fmt: skip
    crescent = Sky("Valletta", "2018-03-19T18:20Z")
    dusk = shot(crescent, crescent.camera("moon", fov_deg=60, pitch_deg=10), w, h)
    earthshine = shot(crescent, crescent.camera("moon", fov_deg=1.5), h, h, ev=0.0)
    save("scene-crescent-earthshine", np.concatenate([dusk, earthshine], axis=1),
         "Valletta 2018-03-19 18:20 UTC: a crescent at dusk; zoomed at EV 0 the earthlit side shows")  # fmt: skip
    night = Sky("Paranal", "2018-03-02T03:00Z")
    save("scene-full-moon-night", shot(night, night.camera("moon", fov_deg=100, pitch_deg=20), w, h),
         "Paranal 2018-03-02 03:00 UTC: a full-Moon night (auto exposure)")  # fmt: skip
    # A day at Valletta, 2018-03-01, every 3 hours from 01:30 UTC, one eye-adapted exposure
    # per frame as skydome timelapse makes them (here: auto exposure per still).
    states = state_series(valletta.observer, 2458178.5 + (1.5 + 3 * np.arange(8)) / 24)
    tiles = []
    for state in states:
        cam = aim_camera(state, "south", fov_deg=100)
        frame = valletta.graph.render(
            state, cam, w // 2, h // 2, altitude_m=57.7, exposure="auto", tonemap="filmic"
        )
        tiles.append(frame.image)
    save("scene-day-strip", np.concatenate([np.concatenate(tiles[:4], axis=1), np.concatenate(tiles[4:], axis=1)]),
         "Valletta 2018-03-01, looking south, 01:30 to 22:30 UTC every 3 h")  # fmt: skip


def night_views(w: int, h: int) -> None:
    """The night sky (issue 11): a moonless night at a dark site with the Milky Way, the same
    sky under Bortle 8 at the same exposure, night vision off and on, twilight with Venus,
    the stars turning over four hours, and the overlays."""
    import numpy as np

    def save(name: str, image, note: str) -> None:
        path = OUT / f"{name}.png"
        atomic_write(path, lambda tmp: write_png(tmp, image, {"views": note}))
        print(f"{path.relative_to(OUT.parents[1])}")

    def shot(sky, cam, width, height, ev=None):
        # Auto exposure sets the log-average to mid-grey, as a photograph of the night would;
        # 1.5 EV less keeps a night looking like one.
        exposure = "auto" if ev is None else ev
        kw = {"compensation_ev": -1.5} if ev is None else {}
        return sky.render(cam, width, height, exposure=exposure, tonemap="filmic", **kw).image

    # Paranal, 2024-07-05 04:00 UTC: a moonless midnight, the galactic centre 80 deg up.
    paranal = ("Paranal", "2024-07-05T04:00Z")
    dark = Sky(*paranal)
    fish = FisheyeCamera()
    south = PerspectiveCamera(fov_deg=100, yaw_deg=200, pitch_deg=35)
    save("night-milky-way", np.concatenate([shot(dark, fish, h, h), shot(dark, south, w, h)], axis=1),
         "Paranal 2024-07-05 04:00 UTC, moonless: all-sky fisheye and looking south-southwest (auto exposure)")  # fmt: skip
    city = Sky(*paranal, light_pollution=8)
    save("night-bortle8", np.concatenate([shot(dark, south, w, h), shot(city, south, w, h)], axis=1),
         "the same sky at a dark site and under Bortle 8 (18.2 mag/arcsec^2), each at its own auto exposure")  # fmt: skip
    dark.night_vision = True
    seen = shot(dark, south, w, h)
    dark.night_vision = False
    save("night-vision", np.concatenate([shot(dark, south, w, h), seen], axis=1),
         "night vision off and on (mesopic colour loss, blue shift, acuity blur, noise)")  # fmt: skip
    # Valletta, 2020-04-28 18:45 UTC: Venus at magnitude -4.7, 26 deg up in the dusk.
    dusk = Sky("Valletta", "2020-04-28T18:45Z")
    save("night-twilight-venus", shot(dusk, PerspectiveCamera(fov_deg=80, yaw_deg=285, pitch_deg=15), w, h),
         "Valletta 2020-04-28 18:45 UTC: Venus in the evening twilight")  # fmt: skip
    # Valletta, 2018-01-16 (new Moon): looking north every 80 minutes, the sky turns about
    # Polaris (36 deg up) by 20 deg each step.
    north = PerspectiveCamera(fov_deg=100, yaw_deg=0, pitch_deg=36)
    winter = Sky("Valletta", "2018-01-16T19:00Z")
    steps = [winter.at(f"2018-01-16T{19 + k * 4 // 3:02d}:{(k * 20) % 60:02d}Z") for k in range(4)]
    ev = steps[0].render(north, w // 2, h // 2, exposure="auto", compensation_ev=-1.5)
    ev = ev.info["exposure_ev100"]
    tiles = [shot(sky, north, w // 2, h // 2, ev=ev) for sky in steps]
    save("night-stars-turning", np.concatenate(tiles, axis=1),
         f"Valletta 2018-01-16, looking north at 19:00, 20:20, 21:40 and 23:00 UTC (EV100 {ev:.1f})")  # fmt: skip
    orion = Sky("Valletta", "2018-01-16T20:00Z", overlays="lines,labels,grid")
    save("night-overlays", shot(orion, PerspectiveCamera(fov_deg=90, yaw_deg=170, pitch_deg=40), w, h),
         "Valletta 2018-01-16 20:00 UTC looking south: constellation lines, labels and the alt/az grid")  # fmt: skip


if __name__ == "__main__":
    main()
