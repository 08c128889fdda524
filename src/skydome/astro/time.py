"""Time scales: UTC, UT1 and TT, Julian Dates, Delta T and sidereal time.

Inputs accepted by :func:`to_time` (always vectorized, never a Python loop over times
except to parse strings or ``datetime`` objects):

* timezone-aware :class:`datetime.datetime` (converted to UTC), naive ones are UTC, or the
  local time of ``zone`` when one is given (a place's: see below);
* ISO 8601 strings (``"2024-03-20T03:06:00Z"``, ``"2003-10-17 12:30:30-07:00"``, a bare
  date; years outside 1..9999 such as ``"-0500-03-01"`` are read by NumPy, always as UTC);
  without an offset they are UTC, or ``zone``'s local time;
* :class:`numpy.datetime64` scalars or arrays (naive, i.e. UTC);
* numbers: Julian Dates in UTC;
* lists or arrays of any of these, or a :class:`Time` (returned unchanged).

Local time: ``to_time("2018-03-01T20:00", zone=ZoneInfo("Europe/Malta"))`` is 19:00 UTC. A
wall-clock time the zone skips (the hour lost when clocks go forward) or repeats (the hour
when they go back) raises :class:`LocalTimeError`, which says so and asks for an offset: no
instant is guessed. ``datetime64`` values and Julian Dates are instants, never local.

Calendar dates are proleptic Gregorian for all of these; :func:`julian_date` also takes
Julian-calendar dates (Meeus ch. 7).

How the scales are linked
-------------------------
* UT1 - UTC comes from the IERS table shipped in ``skydome/data/ut1_utc.npz`` (built by
  ``tools/build_iers_table.py``: IERS C04 since 1962-01-01 plus Bulletin A with its
  one-year prediction). Outside the table UT1 = UTC.
* TT - UTC inside the table is TAI - UTC + 32.184 s (leap seconds since 1972, the drifting
  offsets of 1962-1971 before that). Outside the table TT = UT1 + Delta T, with Delta T
  from the Espenak & Meeus (2006) polynomials, valid -1999..3000 (used, with a warning in
  the docs only, beyond that too). After the end of the table the polynomial is shifted to
  join the last tabulated Delta T, the shift fading out linearly over 100 years.
* Callers can fix Delta T (= TT - UT1, seconds) and/or UT1 - UTC (seconds) explicitly,
  e.g. to reproduce a published example that assumes given values.
"""

from __future__ import annotations

import datetime as _dt
import functools
from collections.abc import Iterable
from importlib import resources
from typing import Any

import numpy as np

from skydome.astro.frames import equation_of_equinoxes, julian_centuries
from skydome.errors import ParameterError
from skydome.physics.constants import ARCSEC_RAD, J2000_JD

__all__ = [
    "VALID_JD_RANGE",
    "J2000",
    "LocalTimeError",
    "Time",
    "format_local",
    "to_time",
    "julian_date",
    "calendar_date",
    "julian_centuries",
    "julian_millennia",
    "delta_t_espenak_meeus",
    "model_delta_t",
    "ut1_minus_utc",
    "tai_minus_utc",
    "earth_rotation_angle",
    "gmst",
    "gast",
]

J2000 = J2000_JD
MJD0 = 2400000.5
UNIX_EPOCH_JD = 2440587.5
#: The Julian Dates the astronomy holds for: years -3000 to 4000 (the precession-nutation
#: series, the star catalogue's space motion and the planetary theories are meant for a few
#: millennia around J2000).
VALID_JD_RANGE = (625_673.5, 3_182_395.5)
TT_MINUS_TAI = 32.184  # seconds
SECONDS_PER_DAY = 86400.0
_TWO_PI = 2.0 * np.pi


# ---------------------------------------------------------------------- calendar


def julian_date(year, month, day, hour=0.0, minute=0.0, second=0.0, calendar: str = "auto"):
    """Julian Date of a calendar date (Meeus ch. 7, eq. 7.1), vectorized.

    ``day`` may be fractional (``4.81``). ``calendar``: ``"gregorian"``, ``"julian"`` or
    ``"auto"`` (Julian before 1582 October 15, Gregorian from then on, as Meeus does).
    Years are astronomical (year 0 = 1 BC, -4712 = 4713 BC). The scale of the result is
    the scale of the input (UTC, TT...).
    """
    if calendar not in ("auto", "gregorian", "julian"):
        raise ParameterError(f"calendar = {calendar!r} must be 'auto', 'gregorian' or 'julian'")
    y = np.asarray(year, dtype=float)
    m = np.asarray(month, dtype=float)
    d = (
        np.asarray(day, dtype=float)
        + np.asarray(hour, float) / 24.0
        + np.asarray(minute, float) / 1440.0
        + np.asarray(second, float) / SECONDS_PER_DAY
    )
    jan_feb = m <= 2
    y = np.where(jan_feb, y - 1, y)
    m = np.where(jan_feb, m + 12, m)
    a = np.floor(y / 100.0)
    b_greg = 2 - a + np.floor(a / 4.0)
    if calendar == "gregorian":
        b = b_greg
    elif calendar == "julian":
        b = np.zeros_like(b_greg)
    else:  # Gregorian from 1582-10-15 (after the y/m shift, March = 3)
        key = y * 10000 + m * 100 + d  # y, m already shifted, comparison still monotone
        b = np.where(key >= 1582 * 10000 + 10 * 100 + 15, b_greg, 0.0)
    return np.floor(365.25 * (y + 4716)) + np.floor(30.6001 * (m + 1)) + d + b - 1524.5


def calendar_date(jd) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(year, month, fractional day) of Julian Dates (Meeus ch. 7, p. 63); Julian calendar
    before JD 2299161 (1582 October 15), Gregorian after."""
    jd = np.asarray(jd, dtype=float) + 0.5
    z = np.floor(jd)
    f = jd - z
    alpha = np.floor((z - 1867216.25) / 36524.25)
    a = np.where(z < 2299161, z, z + 1 + alpha - np.floor(alpha / 4.0))
    b = a + 1524
    c = np.floor((b - 122.1) / 365.25)
    d = np.floor(365.25 * c)
    e = np.floor((b - d) / 30.6001)
    day = b - d - np.floor(30.6001 * e) + f
    month = np.where(e < 14, e - 1, e - 13)
    year = np.where(month > 2, c - 4716, c - 4715)
    return year, month, day


def julian_millennia(jd_tt) -> np.ndarray:
    """Julian millennia since J2000.0, the tau of VSOP87 (Meeus eq. 32.1)."""
    return (np.asarray(jd_tt, dtype=float) - J2000) / 365250.0


# ---------------------------------------------------------------------- Delta T


def delta_t_espenak_meeus(year) -> np.ndarray:
    """Delta T = TT - UT1 in seconds from the Espenak & Meeus (2006) polynomials
    ("Five Millennium Canon of Solar Eclipses", NASA/TP-2006-214141, section 2.6),
    valid -1999..3000; ``year`` is a decimal year. Outside that span the long-term
    parabola -20 + 32 u^2 is used (uncertain by hours at -5000)."""
    y = np.asarray(year, dtype=float)
    out = np.empty_like(y)

    def seg(lo, hi):
        return (y >= lo) & (y < hi)

    u = (y - 1820.0) / 100.0
    out[...] = -20.0 + 32.0 * u * u  # before -500 and after 2150
    m = seg(-500, 500)
    u = y / 100.0
    out[m] = np.polyval(
        [0.0090316521, 0.022174192, -0.1798452, -5.952053, 33.78311, -1014.41, 10583.6], u[m]
    )
    m = seg(500, 1600)
    u = (y - 1000.0) / 100.0
    out[m] = np.polyval(
        [0.0083572073, -0.005050998, -0.8503463, 0.319781, 71.23472, -556.01, 1574.2], u[m]
    )
    m = seg(1600, 1700)
    t = y - 1600.0
    out[m] = np.polyval([1.0 / 7129.0, -0.01532, -0.9808, 120.0], t[m])
    m = seg(1700, 1800)
    t = y - 1700.0
    out[m] = np.polyval([-1.0 / 1174000.0, 0.00013336, -0.0059285, 0.1603, 8.83], t[m])
    m = seg(1800, 1860)
    t = y - 1800.0
    out[m] = np.polyval(
        [
            0.000000000875,
            -0.0000001699,
            0.0000121272,
            -0.00037436,
            0.0041116,
            0.0068612,
            -0.332447,
            13.72,
        ],
        t[m],
    )
    m = seg(1860, 1900)
    t = y - 1860.0
    out[m] = np.polyval([1.0 / 233174.0, -0.0004473624, 0.01680668, -0.251754, 0.5737, 7.62], t[m])
    m = seg(1900, 1920)
    t = y - 1900.0
    out[m] = np.polyval([-0.000197, 0.0061966, -0.0598939, 1.494119, -2.79], t[m])
    m = seg(1920, 1941)
    t = y - 1920.0
    out[m] = np.polyval([0.0020936, -0.076100, 0.84493, 21.20], t[m])
    m = seg(1941, 1961)
    t = y - 1950.0
    out[m] = np.polyval([1.0 / 2547.0, -1.0 / 233.0, 0.407, 29.07], t[m])
    m = seg(1961, 1986)
    t = y - 1975.0
    out[m] = np.polyval([-1.0 / 718.0, -1.0 / 260.0, 1.067, 45.45], t[m])
    m = seg(1986, 2005)
    t = y - 2000.0
    out[m] = np.polyval([0.00002373599, 0.000651814, 0.0017275, -0.060374, 0.3345, 63.86], t[m])
    m = seg(2005, 2050)
    t = y - 2000.0
    out[m] = np.polyval([0.005589, 0.32217, 62.92], t[m])
    m = seg(2050, 2150)
    u = (y - 1820.0) / 100.0
    out[m] = -20.0 + 32.0 * u[m] ** 2 - 0.5628 * (2150.0 - y[m])
    return out


def _decimal_year(jd) -> np.ndarray:
    return 2000.0 + (np.asarray(jd, dtype=float) - J2000) / 365.25


# ---------------------------------------------------------------------- IERS table


@functools.lru_cache(maxsize=1)
def _iers() -> dict[str, Any]:
    path = resources.files("skydome").joinpath("data/ut1_utc.npz")
    with path.open("rb") as fh, np.load(fh) as npz:
        d = {k: npz[k] for k in npz.files}
    mjd0 = float(d["mjd0"])
    ut1_tai = d["ut1_tai_us"] * 1e-6
    pre = d["tai_utc_pre1972_us"] * 1e-6
    tab = {
        "mjd0": mjd0,
        "mjd_end": mjd0 + ut1_tai.size - 1,
        "ut1_tai": ut1_tai,
        "pre_mjd0": mjd0,
        "tai_utc_pre": pre,
        "leap_mjd": d["leap_mjd"].astype(float),
        "leap_tai_utc": d["leap_tai_utc"].astype(float),
        "last_observed_mjd": float(d["last_observed_mjd"]),
    }
    # Delta T at the end of the table, for the continuity shift of the polynomial
    end = tab["mjd_end"]
    dt_end = TT_MINUS_TAI - ut1_tai[-1]  # TT - UT1 = 32.184 + TAI - UT1
    tab["delta_t_end"] = dt_end
    tab["year_end"] = float(_decimal_year(end + MJD0))
    tab["shift_end"] = dt_end - float(delta_t_espenak_meeus(tab["year_end"]))
    return tab


def _in_table(mjd: np.ndarray) -> np.ndarray:
    t = _iers()
    return (mjd >= t["mjd0"]) & (mjd <= t["mjd_end"])


def tai_minus_utc(jd_utc) -> np.ndarray:
    """TAI - UTC in seconds: leap-second table from 1972, the drifting offsets of 1962-1971
    (interpolated from daily values) before; NaN before 1962 (UTC undefined)."""
    t = _iers()
    mjd = np.asarray(jd_utc, dtype=float) - MJD0
    idx = np.searchsorted(t["leap_mjd"], mjd, side="right") - 1
    leap = t["leap_tai_utc"][np.clip(idx, 0, None)]
    pre = t["tai_utc_pre"]
    x = mjd - t["pre_mjd0"]
    pre_val = np.interp(x, np.arange(pre.size, dtype=float), pre)
    out = np.where(idx >= 0, leap, pre_val)
    return np.where(mjd >= t["mjd0"], out, np.nan)


def ut1_minus_utc(jd_utc) -> np.ndarray:
    """UT1 - UTC in seconds from the packaged IERS table; 0 outside it (1962 to about a
    year after the package was built)."""
    t = _iers()
    mjd = np.asarray(jd_utc, dtype=float) - MJD0
    inside = _in_table(mjd)
    x = np.clip(mjd - t["mjd0"], 0, t["ut1_tai"].size - 1)
    ut1_tai = np.interp(x, np.arange(t["ut1_tai"].size, dtype=float), t["ut1_tai"])
    tai_utc = np.nan_to_num(tai_minus_utc(jd_utc))
    return np.where(inside, ut1_tai + tai_utc, 0.0)


def model_delta_t(jd_ut1) -> np.ndarray:
    """Model Delta T = TT - UT1 (s) used outside the IERS table: Espenak & Meeus, shifted
    after the table end to join the last tabulated value (shift fading over 100 years)."""
    t = _iers()
    y = _decimal_year(jd_ut1)
    dt = delta_t_espenak_meeus(y)
    fade = np.clip(1.0 - (y - t["year_end"]) / 100.0, 0.0, 1.0)
    return np.where(y > t["year_end"], dt + t["shift_end"] * fade, dt)


# ---------------------------------------------------------------------- Time


class Time:
    """An array of instants carried in three scales (Julian Dates, float64).

    Attributes ``jd_utc``, ``jd_ut1``, ``jd_tt`` share one shape. Build it with
    :func:`to_time`, :meth:`from_utc` or :meth:`from_jd`.
    """

    __slots__ = ("jd_utc", "jd_ut1", "jd_tt")

    def __init__(self, jd_utc, jd_ut1, jd_tt) -> None:
        self.jd_utc = np.asarray(jd_utc, dtype=float)
        self.jd_ut1 = np.asarray(jd_ut1, dtype=float)
        self.jd_tt = np.asarray(jd_tt, dtype=float)

    @classmethod
    def from_utc(cls, jd_utc, delta_t: Any = None, ut1_utc: Any = None) -> Time:
        """Time from UTC Julian Dates; ``delta_t`` (TT - UT1, s) and ``ut1_utc`` (s) may be
        given to override the tables (scalars or arrays broadcasting with ``jd_utc``)."""
        jd_utc = np.asarray(jd_utc, dtype=float)
        if not np.all(np.isfinite(jd_utc)):
            raise ParameterError("times must be finite Julian Dates")
        mjd = jd_utc - MJD0
        inside = _in_table(mjd)
        dut1 = ut1_minus_utc(jd_utc) if ut1_utc is None else np.asarray(ut1_utc, float)
        dut1 = np.broadcast_to(dut1, jd_utc.shape)
        jd_ut1 = jd_utc + dut1 / SECONDS_PER_DAY
        if delta_t is not None:
            jd_tt = jd_ut1 + np.asarray(delta_t, dtype=float) / SECONDS_PER_DAY
        else:
            tai_utc = tai_minus_utc(jd_utc)
            tt_utc = np.where(
                inside, np.nan_to_num(tai_utc) + TT_MINUS_TAI, dut1 + model_delta_t(jd_ut1)
            )
            jd_tt = jd_utc + tt_utc / SECONDS_PER_DAY
        return cls(jd_utc, jd_ut1, np.broadcast_to(jd_tt, jd_utc.shape).copy())

    @classmethod
    def from_jd(cls, jd_tt, jd_ut1=None, jd_utc=None) -> Time:
        """Time from explicit TT (and optionally UT1/UTC) Julian Dates. Missing UT1 is
        derived with the model Delta T; missing UTC is taken equal to UT1."""
        jd_tt = np.asarray(jd_tt, dtype=float)
        if jd_ut1 is None:
            jd_ut1 = jd_tt - model_delta_t(jd_tt) / SECONDS_PER_DAY
            jd_ut1 = jd_tt - model_delta_t(jd_ut1) / SECONDS_PER_DAY
        jd_ut1 = np.broadcast_to(np.asarray(jd_ut1, dtype=float), jd_tt.shape)
        jd_utc = jd_ut1 if jd_utc is None else np.asarray(jd_utc, dtype=float)
        return cls(jd_utc, jd_ut1, jd_tt)

    @property
    def shape(self) -> tuple[int, ...]:
        return self.jd_tt.shape

    def __len__(self) -> int:
        return len(self.jd_tt)

    def __getitem__(self, item) -> Time:
        return Time(self.jd_utc[item], self.jd_ut1[item], self.jd_tt[item])

    @property
    def delta_t(self) -> np.ndarray:
        """TT - UT1 in seconds."""
        return (self.jd_tt - self.jd_ut1) * SECONDS_PER_DAY

    def to_datetime64(self) -> np.ndarray:
        """UTC as ``datetime64[us]`` (proleptic Gregorian)."""
        us = np.round((self.jd_utc - UNIX_EPOCH_JD) * SECONDS_PER_DAY * 1e6)
        return us.astype(np.int64).astype("datetime64[us]")

    def iso(self) -> np.ndarray:
        """UTC as ISO 8601 strings with a 'Z' suffix, rounded to the second."""
        sec = np.round((self.jd_utc - UNIX_EPOCH_JD) * SECONDS_PER_DAY).astype(np.int64)
        strings = [str(s) + "Z" for s in sec.astype("datetime64[s]").ravel()]
        return np.array(strings).reshape(self.shape)

    def __repr__(self) -> str:
        if self.jd_tt.ndim == 0:
            return f"Time({self.iso()!s} UTC, JD_TT {float(self.jd_tt):.6f})"
        return f"Time(shape={self.shape}, JD_TT {self.jd_tt.min():.4f}..{self.jd_tt.max():.4f})"


class LocalTimeError(ParameterError):
    """A wall-clock time that a time zone skips or repeats (a daylight-saving change)."""


def _offset(delta: _dt.timedelta) -> str:
    """``UTC+01:00`` for a UTC offset."""
    minutes = round(delta.total_seconds() / 60)
    sign = "-" if minutes < 0 else "+"
    return f"UTC{sign}{abs(minutes) // 60:02d}:{abs(minutes) % 60:02d}"


def _localize(naive: _dt.datetime, zone: _dt.tzinfo) -> float:
    """The UTC Julian Date of ``naive`` read as a wall-clock time of ``zone`` (years 1-9999,
    also where UTC falls outside them); LocalTimeError where the zone's clocks skip it or
    show it twice."""
    first, second = naive.replace(tzinfo=zone, fold=0), naive.replace(tzinfo=zone, fold=1)
    o1, o2 = first.utcoffset(), second.utcoffset()
    if o1 != o2:
        name = getattr(zone, "key", str(zone))
        shown = naive.isoformat(timespec="minutes" if naive.second == 0 else "seconds")
        back = first.astimezone(_dt.timezone.utc).astimezone(zone).replace(tzinfo=None)
        if back != naive:
            raise LocalTimeError(
                f"time {shown} does not exist in {name}: the clocks skip it going from "
                f"{_offset(o1)} to {_offset(o2)}; give another time or an offset "
                f"(e.g. {shown}{_offset(o1)[3:]})"
            )
        raise LocalTimeError(
            f"time {shown} is ambiguous in {name}: the clocks show it twice, at "
            f"{_offset(o1)} and then at {_offset(o2)}; add the offset "
            f"(e.g. {shown}{_offset(o1)[3:]} or {shown}{_offset(o2)[3:]})"
        )
    # in datetime64 microseconds, as a UTC time is read: the same instant, the same bits
    shift = np.timedelta64(o1 // _dt.timedelta(microseconds=1), "us")
    return float(_datetime64_to_jd(np.datetime64(naive, "us") - shift))


def _parse_one(value: Any, zone: _dt.tzinfo | None = None) -> float:
    """UTC Julian Date of one datetime/str/datetime64/number (naive datetimes and strings
    in ``zone``'s local time when it is given)."""
    if isinstance(value, _dt.datetime):
        if value.tzinfo is not None:
            value = value.astimezone(_dt.timezone.utc).replace(tzinfo=None)
        elif zone is not None:
            return _localize(value, zone)
        return _datetime64_to_jd(np.datetime64(value, "us"))
    if isinstance(value, _dt.date):
        if zone is not None:
            return _parse_one(_dt.datetime(value.year, value.month, value.day), zone)
        return _datetime64_to_jd(np.datetime64(value, "us"))
    if isinstance(value, np.datetime64):
        return _datetime64_to_jd(value)
    if isinstance(value, str):
        s = value.strip()
        try:
            d = _dt.datetime.fromisoformat(s.replace("Z", "+00:00") if s.endswith("Z") else s)
        except ValueError:
            pass
        else:
            return _parse_one(d, zone)
        if zone is not None and not s.endswith("Z"):
            raise ParameterError(
                f"time {value!r} is not an ISO 8601 date/time of years 1-9999 that a local "
                "time can be read from; give it in UTC with a Z (e.g. -0500-03-01T12:00Z)"
            )
        try:
            return _datetime64_to_jd(np.datetime64(s.rstrip("Z")))
        except ValueError:
            raise ParameterError(
                f"time {value!r} is not an ISO 8601 date/time (e.g. 2024-03-20T12:00:00Z)"
            ) from None
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        try:
            return float(value)
        except OverflowError:
            raise ParameterError(f"time {value!r} is too large for a Julian Date") from None
    raise ParameterError(
        f"time {value!r} must be a datetime, ISO 8601 string, numpy datetime64 or Julian Date"
    )


def _datetime64_to_jd(a) -> np.ndarray:
    a = np.asarray(a)
    if np.any(np.isnat(a)):
        raise ParameterError("times contain NaT (not a time)")
    us = a.astype("datetime64[us]").astype(np.int64)
    return UNIX_EPOCH_JD + us / (SECONDS_PER_DAY * 1e6)


def to_time(
    times: Any, *, delta_t: Any = None, ut1_utc: Any = None, zone: _dt.tzinfo | None = None
) -> Time:
    """Convert ``times`` (see module doc) to a :class:`Time`.

    ``delta_t`` (TT - UT1, s) and ``ut1_utc`` (UT1 - UTC, s) override the built-in
    tables; they broadcast against the times. ``zone`` (a ``tzinfo``, e.g.
    ``zoneinfo.ZoneInfo("Europe/Paris")``): strings and datetimes without an offset are its
    local time (LocalTimeError for one its clocks skip or repeat); None: they are UTC.
    """
    if isinstance(times, Time):
        if delta_t is None and ut1_utc is None:
            return times
        return Time.from_utc(times.jd_utc, delta_t=delta_t, ut1_utc=ut1_utc)
    if isinstance(times, np.ndarray) and np.issubdtype(times.dtype, np.datetime64):
        jd = _datetime64_to_jd(times)
    elif isinstance(times, np.ndarray) and np.issubdtype(times.dtype, np.number):
        jd = times.astype(float)
    elif isinstance(times, (str, _dt.date, np.datetime64, int, float, np.number)):
        jd = np.asarray(_parse_one(times, zone))
    elif isinstance(times, Iterable):
        items = list(np.asarray(times, dtype=object).ravel())
        shape = np.shape(np.asarray(times, dtype=object))
        jd = np.array([_parse_one(v, zone) for v in items], dtype=float).reshape(shape)
    else:
        jd = np.asarray(_parse_one(times, zone))
    return Time.from_utc(jd, delta_t=delta_t, ut1_utc=ut1_utc)


def format_local(time: Time, zone: _dt.tzinfo | None) -> str:
    """One instant as a reader wants it: ``"2018-03-01 20:00:00 CET (UTC+01:00)"`` in
    ``zone``'s local time (its abbreviation and offset), ``"2018-03-01 19:00:00 UTC"`` without
    a zone or outside the years 1-9999 (to the second)."""
    if np.shape(time.jd_utc) != ():
        raise ParameterError("format_local takes one instant")
    sec = int(np.round((float(time.jd_utc) - UNIX_EPOCH_JD) * SECONDS_PER_DAY))
    utc_text = str(np.datetime64(sec, "s")).replace("T", " ") + " UTC"
    if zone is None:
        return utc_text
    try:
        utc = _dt.datetime(1970, 1, 1, tzinfo=_dt.timezone.utc) + _dt.timedelta(seconds=sec)
        local = utc.astimezone(zone)
    except (OverflowError, ValueError):
        return utc_text
    return f"{local:%Y-%m-%d %H:%M:%S} {local.tzname()} ({_offset(local.utcoffset())})"


# ---------------------------------------------------------------------- sidereal time


def earth_rotation_angle(jd_ut1) -> np.ndarray:
    """Earth rotation angle (rad), IERS Conventions 2010 eq. 5.15."""
    du = np.asarray(jd_ut1, dtype=float) - J2000
    frac = np.mod(du, 1.0)
    return np.mod(_TWO_PI * (frac + 0.7790572732640 + 0.00273781191135448 * du), _TWO_PI)


def gmst(jd_ut1, jd_tt=None, model: str = "iau2006") -> np.ndarray:
    """Greenwich mean sidereal time (rad).

    ``model="iau2006"`` (default, as SOFA and skyfield): ERA(UT1) + polynomial in TT
    centuries (IERS Conventions 2010 eq. 5.32); ``jd_tt`` defaults to UT1 + model Delta T
    (the polynomial moves 0.0001" per minute of TT error). ``model="iau1982"``: Meeus
    eq. 12.4 in UT1 only; it differs from IAU 2006 by a few milliseconds of time over
    1900-2100 (3.3 ms in 1987).
    """
    jd_ut1 = np.asarray(jd_ut1, dtype=float)
    if model == "iau1982":
        du = jd_ut1 - J2000
        t = du / 36525.0
        deg = 280.46061837 + 360.0 * np.mod(du, 1.0) + 0.98564736629 * du
        deg = deg + t * t * (0.000387933 - t / 38710000.0)
        return np.mod(np.radians(np.mod(deg, 360.0)), _TWO_PI)
    if model != "iau2006":
        raise ParameterError(f"gmst model = {model!r} must be 'iau2006' or 'iau1982'")
    if jd_tt is None:
        jd_tt = jd_ut1 + model_delta_t(jd_ut1) / SECONDS_PER_DAY
    t = julian_centuries(jd_tt)
    poly = 0.014506 + t * (
        4612.156534 + t * (1.3915817 + t * (-0.00000044 + t * (-0.000029956 + t * -0.0000000368)))
    )
    return np.mod(earth_rotation_angle(jd_ut1) + poly * ARCSEC_RAD, _TWO_PI)


def gast(jd_ut1, jd_tt=None, model: str = "iau2006") -> np.ndarray:
    """Greenwich apparent sidereal time (rad) = GMST + equation of the equinoxes
    (Meeus ch. 12 p. 88; nutation IAU 1980, see :mod:`skydome.astro.frames`)."""

    jd_ut1 = np.asarray(jd_ut1, dtype=float)
    if jd_tt is None:
        jd_tt = jd_ut1 + model_delta_t(jd_ut1) / SECONDS_PER_DAY
    return np.mod(gmst(jd_ut1, jd_tt, model) + equation_of_equinoxes(jd_tt), _TWO_PI)
