"""Jobs: one sky, one camera, one size; their deterministic names; the sky and the camera
each one describes.

A :class:`Job` holds plain values only (it travels to Dask workers in other processes and is
written to the manifest as it is). Its :attr:`Job.name` is made from its parameters: the
place (or the Sun's angles), the UTC time, the weather, the clouds, the camera and the size
that people read, then 8 hex digits of a SHA-256 of every parameter, so two jobs that differ
in anything have different names, and the same job has the same name in every run.
"""

from __future__ import annotations

import hashlib
import json
import re
from dataclasses import asdict, dataclass, field
from itertools import product

from skydome.astro.places import Place, normalise
from skydome.batch.spec import BatchSpec
from skydome.core.cameras import Camera, make_camera
from skydome.description import SkyDescription
from skydome.errors import ParameterError
from skydome.sky import aim_camera, default_look

__all__ = ["Job", "expand_jobs"]


@dataclass(frozen=True)
class Job:
    """One frame (or, with no formats, only the light) of a batch.

    Attributes:
        place: the place as the spec gave it ("Valletta", "48.85, 2.35"), "" for a Sun alone.
        latitude_deg, longitude_deg, elevation_m: where (NaN-free; 0 for a Sun alone).
        timezone: the IANA zone of the place ("" for UTC).
        time_utc: the instant, ISO 8601 UTC ("2018-03-01T19:00:00Z"), "" for a Sun alone.
        sun_elevation_deg, sun_azimuth_deg: the Sun of the abstract mode (None with a place).
        atmosphere: a preset name; weather, clouds: preset names or None.
        bortle: "auto" (the place's own light pollution), None, or a Bortle class.
        night: with a place, the night sky's layers.
        camera, camera_name, fov_deg, yaw_deg, pitch_deg, look: the camera (the command
            line's names; yaw/pitch None: aimed by ``look``, or by what the sky shows).
        width, height: pixels.
        formats: the files ("exr", "png", "npy"); empty: the light only.
        exposure: "auto" or EV100; tonemap: for PNG.
        lighting_size, lights: the lighting's map (width, height) and its lights.
    """

    place: str = ""
    latitude_deg: float = 0.0
    longitude_deg: float = 0.0
    elevation_m: float = 0.0
    timezone: str = ""
    time_utc: str = ""
    sun_elevation_deg: float | None = None
    sun_azimuth_deg: float | None = None
    atmosphere: str = "earth"
    weather: str | None = None
    clouds: str | None = None
    bortle: int | str | None = "auto"
    night: bool = True
    camera: str = "equirect"
    camera_name: str = "equirect"
    fov_deg: float = 90.0
    yaw_deg: float | None = None
    pitch_deg: float | None = None
    look: str | None = None
    width: int = 512
    height: int = 256
    formats: tuple[str, ...] = ("exr",)
    exposure: str | float = "auto"
    tonemap: str = "filmic"
    lighting_size: tuple[int, int] = (256, 128)
    lights: int = 16
    _place_obj: Place | None = field(default=None, repr=False, compare=False)

    @property
    def abstract(self) -> bool:
        """True for a Sun alone (no place or time)."""
        return not self.place

    def parameters(self) -> dict:
        """Every parameter, JSON-able (the name's hash, the manifest's columns)."""
        d = asdict(self)
        d.pop("_place_obj")
        d["formats"] = list(self.formats)
        d["lighting_size"] = list(self.lighting_size)
        return d

    @property
    def name(self) -> str:
        """The job's file stem (see the module docstring)."""
        digest = hashlib.sha256(json.dumps(self.parameters(), sort_keys=True).encode()).hexdigest()[
            :8
        ]
        if self.abstract:
            where = f"sun{self.sun_elevation_deg:+05.1f}_az{self.sun_azimuth_deg % 360:05.1f}"
        else:
            stamp = self.time_utc.replace("-", "").replace(":", "")
            where = f"{_slug(self.place)}_{stamp}"
        parts = [where]
        if self.atmosphere != "earth":
            parts.append(self.atmosphere)
        if self.weather is not None:
            parts.append(self.weather)
        if self.clouds is not None:
            parts.append(f"clouds-{self.clouds}")
        parts += [f"{self.camera_name}-{self.width}x{self.height}", digest]
        return "_".join(parts)

    def files(self) -> dict[str, str]:
        """The file names it writes, by format (``{"exr": "NAME.exr"}``)."""
        return {f: f"{self.name}.{f}" for f in self.formats}

    # ------------------------------------------------------------------ what it draws

    def place_value(self):
        """What ``Sky``/``SkyDescription.of`` takes as the place: the gazetteer ``Place``,
        or (lat, lon, elevation) for a place given as numbers."""
        if self._place_obj is not None:
            return self._place_obj
        return (self.latitude_deg, self.longitude_deg, self.elevation_m)

    def description(self) -> SkyDescription:
        """The sky of this job, as ``Sky(place, time, atmosphere, weather=..., clouds=...)``
        makes it."""
        common = {"clouds": self.clouds, "weather": self.weather, "night": self.night}
        if self.abstract:
            return SkyDescription.of(
                None, None, self.atmosphere, sun_elevation_deg=self.sun_elevation_deg,
                sun_azimuth_deg=self.sun_azimuth_deg, **common,
            )  # fmt: skip
        return SkyDescription.of(
            self.place_value(), self.time_utc, self.atmosphere,
            light_pollution=self.bortle, utc=not self.timezone, **common,
        )  # fmt: skip

    def make_camera(self, state) -> Camera:
        """The camera (``state``: the sky's SkyState, which aims a perspective camera by
        ``look``, by default at what :func:`skydome.sky.default_look` says, as the command
        line does)."""
        if self.camera != "perspective":
            return make_camera(self.camera)
        look = self.look or default_look(state)
        aim = aim_camera(state, look, fov_deg=self.fov_deg)
        return make_camera(
            "perspective",
            fov_deg=self.fov_deg,
            yaw_deg=aim.yaw_deg if self.yaw_deg is None else self.yaw_deg,
            pitch_deg=aim.pitch_deg if self.pitch_deg is None else self.pitch_deg,
        )


def _slug(text: str) -> str:
    """A file-name-safe spelling of a place: ``"Mt. Wilson"`` -> ``mount-wilson``,
    ``"48.85, 2.35"`` -> ``48.85_2.35``."""
    if re.fullmatch(r"[-+\d., e]+", text):
        return re.sub(r"[^0-9.+-]+", "_", text).strip("_")
    return re.sub(r"[^a-z0-9]+", "-", normalise(text)).strip("-") or "place"


def expand_jobs(spec: BatchSpec) -> list[Job]:
    """The jobs of a checked spec: the product of its axes, in a fixed order (places, times,
    atmospheres, weathers, clouds, light pollution, cameras, sizes), each once."""
    common = {
        "formats": spec.formats, "exposure": spec.exposure, "tonemap": spec.tonemap,
        "lighting_size": spec.lighting_size, "lights": spec.lights, "night": spec.night,
    }  # fmt: skip
    wheres: list[dict] = []
    if spec.abstract:
        for el, az in spec.suns:
            wheres.append({"sun_elevation_deg": el, "sun_azimuth_deg": az % 360.0})
    else:
        for p, times in zip(spec.places, spec.times, strict=True):
            for t in times:
                wheres.append({
                    "place": p.label, "latitude_deg": p.place.latitude_deg,
                    "longitude_deg": p.place.longitude_deg, "elevation_m": p.place.elevation_m,
                    "timezone": p.zone, "time_utc": t,
                    "_place_obj": None if p.given_as_numbers else p.place,
                })  # fmt: skip
    jobs: dict[str, Job] = {}
    checked: set[tuple] = set()
    for where, air, weather, clouds, bortle, cam, (w, h) in product(
        wheres, spec.atmospheres, spec.weathers, spec.clouds, spec.bortles, spec.cameras,
        spec.sizes,
    ):  # fmt: skip
        job = Job(
            **where, atmosphere=air, weather=weather, clouds=clouds,
            bortle=bortle if not spec.abstract else None, camera=cam.type,
            camera_name=cam.name, fov_deg=cam.fov, yaw_deg=cam.yaw, pitch_deg=cam.pitch,
            look=cam.look, width=w, height=h, **common,
        )  # fmt: skip
        jobs.setdefault(job.name, job)
        kind = (job.place, job.abstract, air, weather, clouds, bortle)
        if kind not in checked:  # each kind of sky described once, before anything is drawn
            checked.add(kind)
            try:
                job.description()
            except ParameterError as exc:
                what = ", ".join(f"{k} {v}" for k, v in (("atmosphere", air),
                                 ("weather", weather), ("clouds", clouds)) if v)  # fmt: skip
                raise ParameterError(
                    f"spec key 'sky': {job.place or 'a Sun alone'} ({what}): {exc}"
                ) from None
    return list(jobs.values())
