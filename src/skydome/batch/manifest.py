"""The manifest of a batch: a row per job (its name, ``job``, is the key: never two rows for
one job), in Parquet (``manifest.parquet``, with pyarrow) and CSV (``manifest.csv``), both
written atomically by the process that collects the results.

Columns (units in the names): the job's parameters (:meth:`Job.parameters`, less the
abstract mode's Sun, which ``sun_altitude_deg``/``sun_azimuth_deg`` repeat); ``status`` ("ok"
or "failed") and ``error`` (the failure's text); where the lights were (``sun_altitude_deg``,
``sun_azimuth_deg``, apparent, degrees from north through east; ``moon_*``); the light at
the ground (``direct_horizontal_lux``, ``diffuse_horizontal_lux``,
``global_horizontal_lux``, ``zenith_luminance_cd_m2``, ``eclipse_fraction``;
``sun_normal_lux``/``moon_normal_lux``: each disk's illuminance on a surface facing it);
the sky's irradiance as 9 spherical harmonics x RGB (``sh_0_r`` .. ``sh_8_b``, lx,
:mod:`skydome.lighting`'s convention) and its directional lights (``lights``, JSON); the
files (``file_exr``, ``sha256_exr``, ...; ``bytes``); timings (``setup_s``, ``render_s``,
``lighting_s``, ``write_s``, ``job_s``: seconds in the worker) and ``worker`` (host:pid).

A job is complete when its row says "ok" and each of its files exists with the SHA-256 the
row holds (:func:`complete`): a run skips those, and renders the others again.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from pathlib import Path

from skydome.batch.jobs import Job
from skydome.batch.runner import file_sha256
from skydome.batch.spec import FORMATS
from skydome.errors import ParameterError
from skydome.io.atomic import atomic_write

__all__ = ["COLUMNS", "MANIFEST_CSV", "MANIFEST_PARQUET", "Manifest", "complete", "job_row"]

MANIFEST_PARQUET = "manifest.parquet"
MANIFEST_CSV = "manifest.csv"

_F, _S, _I, _B = "float", "str", "int", "bool"
#: Every column, in order, with its type (float64, string, int64, bool; any may be null).
COLUMNS: dict[str, str] = {
    "job": _S, "status": _S, "error": _S,
    # the parameters
    "place": _S, "latitude_deg": _F, "longitude_deg": _F, "elevation_m": _F, "timezone": _S,
    "time_utc": _S, "time_local": _S, "atmosphere": _S, "weather": _S, "clouds": _S,
    "bortle": _S, "night": _B, "camera": _S, "camera_name": _S, "fov_deg": _F, "yaw_deg": _F,
    "pitch_deg": _F, "look": _S, "width": _I, "height": _I, "formats": _S, "exposure": _S,
    "tonemap": _S, "lighting_size": _S, "lights_n": _I,
    # the lights' places
    "sun_altitude_deg": _F, "sun_azimuth_deg": _F, "moon_altitude_deg": _F,
    "moon_azimuth_deg": _F, "moon_illuminated_fraction": _F,
    # the light
    "direct_horizontal_lux": _F, "diffuse_horizontal_lux": _F, "global_horizontal_lux": _F,
    "zenith_luminance_cd_m2": _F, "eclipse_fraction": _F, "sun_normal_lux": _F,
    "moon_normal_lux": _F, "exposure_ev100": _F,
    **{f"sh_{i}_{c}": _F for i in range(9) for c in "rgb"},
    "lights": _S,
    # the files
    **{k: _S for f in FORMATS for k in (f"file_{f}", f"sha256_{f}")},
    "bytes": _I,
    # the run
    "setup_s": _F, "render_s": _F, "lighting_s": _F, "write_s": _F, "job_s": _F,
    "worker": _S,
}  # fmt: skip


def job_row(job: Job) -> dict:
    """The parameter columns of ``job`` (strings where a value may be of several kinds)."""
    p = job.parameters()
    return {
        "job": job.name, "place": p["place"], "latitude_deg": p["latitude_deg"],
        "longitude_deg": p["longitude_deg"], "elevation_m": p["elevation_m"],
        "timezone": p["timezone"], "time_utc": p["time_utc"], "atmosphere": p["atmosphere"],
        "weather": p["weather"], "clouds": p["clouds"],
        "bortle": None if p["bortle"] is None else str(p["bortle"]), "night": p["night"],
        "camera": p["camera"], "camera_name": p["camera_name"], "fov_deg": p["fov_deg"],
        "yaw_deg": p["yaw_deg"], "pitch_deg": p["pitch_deg"], "look": p["look"],
        "width": p["width"], "height": p["height"], "formats": ",".join(p["formats"]),
        "exposure": str(p["exposure"]), "tonemap": p["tonemap"],
        "lighting_size": "x".join(str(v) for v in p["lighting_size"]), "lights_n": p["lights"],
    }  # fmt: skip


def _typed(name: str, value):
    """``value`` as column ``name``'s type (None, NaN and "" as null: the CSV writes null
    as an empty field)."""
    kind = COLUMNS[name]
    if value is None or (isinstance(value, str) and value == ""):
        return None
    if kind == _F:
        v = float(value)
        return None if math.isnan(v) else v
    if kind == _I:
        return int(float(value))
    if kind == _B:
        return value if isinstance(value, bool) else str(value).lower() == "true"
    return str(value)


class Manifest:
    """The rows of a batch's folder, by job name; :meth:`write` stores them."""

    def __init__(self, folder: str | os.PathLike, rows: dict[str, dict] | None = None):
        self.folder = Path(folder)
        self.rows: dict[str, dict] = dict(rows or {})

    @classmethod
    def load(cls, folder: str | os.PathLike) -> Manifest:
        """The manifest in ``folder``: its Parquet file, or its CSV when that is all there is
        (or the Parquet file cannot be read); empty when there is none."""
        folder = Path(folder)
        rows: list[dict] = []
        parquet, text = folder / MANIFEST_PARQUET, folder / MANIFEST_CSV
        if parquet.is_file():
            try:
                import pyarrow.parquet as pq  # optional: pyarrow

                rows = pq.read_table(parquet).to_pylist()
            except Exception:  # unreadable, or no pyarrow: the CSV says the same
                rows = []
        if not rows and text.is_file():
            with open(text, newline="", encoding="utf-8") as f:
                rows = list(csv.DictReader(f))
        out = {}
        for r in rows:
            row = {k: _typed(k, v) for k, v in r.items() if k in COLUMNS}
            if row.get("job"):
                out[row["job"]] = row
        return cls(folder, out)

    def add(self, row: dict) -> None:
        """Put a job's row in (replacing the job's earlier row)."""
        self.rows[row["job"]] = {k: _typed(k, row.get(k)) for k in COLUMNS}

    def table(self) -> list[dict]:
        """The rows, sorted by job name, every column present."""
        return [{k: r.get(k) for k in COLUMNS} for _, r in sorted(self.rows.items())]

    def write(self) -> list[Path]:
        """Write ``manifest.csv`` and (with pyarrow) ``manifest.parquet`` atomically; return
        the paths written."""
        rows = self.table()
        written = [atomic_write(self.folder / MANIFEST_CSV, lambda tmp: _write_csv(tmp, rows))]
        try:
            import pyarrow as pa  # optional: pyarrow
            import pyarrow.parquet as pq
        except ImportError:
            return written
        types = {_F: pa.float64(), _S: pa.string(), _I: pa.int64(), _B: pa.bool_()}
        schema = pa.schema([(k, types[t]) for k, t in COLUMNS.items()])
        table = pa.Table.from_pylist(rows, schema=schema)
        written.append(
            atomic_write(self.folder / MANIFEST_PARQUET, lambda tmp: pq.write_table(table, tmp))
        )
        return written


def _write_csv(path: Path, rows: list[dict]) -> None:
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(COLUMNS), lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: ("" if v is None else repr(v) if isinstance(v, float) else v)
                    for k, v in r.items()})  # fmt: skip
    Path(path).write_text(buf.getvalue(), encoding="utf-8")


def complete(job: Job, row: dict | None, folder: str | os.PathLike) -> bool:
    """Whether ``job`` is done in ``folder``: its row says "ok" and each of its files is there
    with the SHA-256 the row recorded (read and hashed now)."""
    if row is None or row.get("status") != "ok":
        return False
    folder = Path(folder)
    for fmt, name in job.files().items():
        path, digest = folder / name, row.get(f"sha256_{fmt}")
        if not digest or row.get(f"file_{fmt}") != name or not path.is_file():
            return False
        if file_sha256(path) != digest:
            return False
    return True


def lights_of(row: dict) -> list[dict]:
    """A row's directional lights (``{"direction": [x, y, z], "illuminance": [R, G, B]}``)."""
    text = row.get("lights")
    if not text:
        raise ParameterError(f"job {row.get('job')!r} has no lights in the manifest")
    return json.loads(text)
