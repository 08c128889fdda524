"""Rise, set, transit, twilight and Moon phase times, found by vectorized root finding.

Method: the event function is sampled on a regular grid over the whole date range,
every sign change of the right direction is bracketed, and all brackets are refined at
once by bisection (one vectorized evaluation per iteration; 24 iterations shrink a
10-minute bracket to 0.04 s). No Python loop runs over days or events.

Definitions (those of the Astronomical Almanac and of skyfield's ``almanac``):

* sunrise/sunset: the Sun's centre at geometric (airless) topocentric altitude
  -0.8333 deg (34' of standard refraction plus a 16' semidiameter);
* moonrise/moonset: the Moon's centre at -34' minus its topocentric semidiameter;
* planets: the centre at -34';
* civil, nautical, astronomical twilight: the Sun's centre at -6, -12, -18 deg
  ("dawn" when rising through it, "dusk" when setting);
* transit: upper culmination (topocentric apparent hour angle 0);
* Moon phases: the geocentric apparent ecliptic longitude of the Moon minus the Sun's
  equals 0 (new), 90 (first quarter), 180 (full), 270 deg (last quarter);
* eclipses (:func:`eclipse_events`, :mod:`skydome.astro.eclipses`): a solar eclipse's
  contacts at the place (C1..C4) and a lunar eclipse's (P1, U1..U4, P4), when the Sun or
  the Moon is up at one of them, with a note on the kind and the body's altitude.

Days without an event (a UTC day of the search, from its start) are events too, dated at
the start of the day: ``sun_never_sets`` / ``sun_never_rises`` (and the Moon's) when the
body stays above / below its rise-set altitude all day, ``no_<kind>_dusk`` when the Sun
never sinks below that twilight's depression on a day it does not stay up (only the
shallowest such depression: the deeper ones follow), and ``no_<kind>_dawn`` when it never
climbs to it (only the deepest one). :data:`ALL_DAY_DESCRIPTIONS` words them.

Event times are returned as UTC Julian Dates (and ISO strings).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from skydome.astro import eclipses, moon, sun
from skydome.astro.observer import BODIES, Observer
from skydome.astro.time import Time, to_time
from skydome.errors import ParameterError

__all__ = [
    "Events",
    "find_crossings",
    "rise_set",
    "transits",
    "twilight",
    "moon_phases",
    "events",
    "TWILIGHT_DEPRESSION_DEG",
    "ALL_DAY_DESCRIPTIONS",
    "all_day",
    "eclipse_events",
]

SUN_HORIZON_DEG = -0.8333
REFRACTION_HORIZON_DEG = -34.0 / 60.0
TWILIGHT_DEPRESSION_DEG = {"civil": 6.0, "nautical": 12.0, "astronomical": 18.0}
PHASE_NAMES = ("new_moon", "first_quarter", "full_moon", "last_quarter")
#: Samples per day of the all-day test: the 10-minute grid of :func:`rise_set`.
_DAY_SAMPLES = 145

#: Plain words for the whole-day events (kind -> description).
ALL_DAY_DESCRIPTIONS = {
    "sun_never_sets": "Sun never sets",
    "sun_never_rises": "Sun never rises",
    "moon_never_sets": "Moon never sets",
    "moon_never_rises": "Moon never rises",
    **{
        f"no_{k}_dusk": f"never gets dark enough to end {k} twilight (Sun above -{d:g} deg)"
        for k, d in TWILIGHT_DEPRESSION_DEG.items()
    },
    **{
        f"no_{k}_dawn": f"never gets light enough for {k} twilight (Sun below -{d:g} deg)"
        for k, d in TWILIGHT_DEPRESSION_DEG.items()
    },
}


@dataclass
class Events:
    """Events sorted by time: ``jd_utc`` (float array), ``kind`` and ``body`` (str arrays)."""

    jd_utc: np.ndarray
    kind: np.ndarray
    body: np.ndarray
    #: A few words on an event ("" for none): an eclipse's kind and the body's altitude.
    notes: np.ndarray | None = None

    def iso(self) -> list[str]:
        """UTC times as ISO 8601 strings (to the second)."""
        return [str(s) for s in Time(self.jd_utc, self.jd_utc, self.jd_utc).iso().ravel()]

    def as_list(self) -> list[dict[str, str]]:
        """``[{"time": iso, "event": kind, "body": body}, ...]``; whole-day events (dated at
        the start of their day) also carry ``"description"`` and ``"all_day": True``."""
        rows = []
        notes = self.notes if self.notes is not None else [""] * len(self)
        for t, k, b, n in zip(self.iso(), self.kind, self.body, notes, strict=True):
            row = {"time": t, "event": str(k), "body": str(b)}
            if k in ALL_DAY_DESCRIPTIONS:
                row.update(description=ALL_DAY_DESCRIPTIONS[k], all_day=True)
            if n:
                row["note"] = str(n)
            rows.append(row)
        return rows

    def __len__(self) -> int:
        return int(self.jd_utc.size)


def find_crossings(
    func: Callable[[np.ndarray], np.ndarray],
    jd_start: float,
    jd_end: float,
    step_days: float,
    rising: bool | None = True,
    iterations: int = 24,
) -> tuple[np.ndarray, np.ndarray]:
    """Roots of ``func(jd) -> values`` in [jd_start, jd_end), vectorized.

    ``rising``: True keeps crossings from negative to positive, False from positive to
    negative, None both. Returns ``(jd_roots, rising_flags)`` sorted. ``step_days`` must
    be shorter than the shortest interval between two roots.
    """
    n = max(int(np.ceil((jd_end - jd_start) / step_days)), 1)
    grid = jd_start + np.arange(n + 1) * ((jd_end - jd_start) / n)
    f = func(grid)
    neg = f < 0
    up = neg[:-1] & ~neg[1:]
    down = ~neg[:-1] & neg[1:]
    sel = up if rising is True else down if rising is False else (up | down)
    idx = np.flatnonzero(sel)
    lo, hi = grid[idx], grid[idx + 1]
    f_lo_neg = neg[idx]
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        fm_neg = func(mid) < 0
        go_hi = fm_neg == f_lo_neg  # root is in [mid, hi]
        lo = np.where(go_hi, mid, lo)
        hi = np.where(go_hi, hi, mid)
    return 0.5 * (lo + hi), up[idx]


def _altitude_function(observer: Observer, body: str, horizon_deg: float | None):
    def f(jd_utc: np.ndarray) -> np.ndarray:
        p = observer.sky(Time.from_utc(jd_utc), bodies=(body,))[body]
        if horizon_deg is not None:
            h = np.radians(horizon_deg)
        elif body == "sun":
            h = np.radians(SUN_HORIZON_DEG)
        elif body == "moon":
            h = np.radians(REFRACTION_HORIZON_DEG) - 0.5 * p.angular_diameter
        else:
            h = np.radians(REFRACTION_HORIZON_DEG)
        return p.alt_unrefracted - h

    return f


def _span(start: Any, days: float) -> tuple[float, float]:
    t0 = float(np.asarray(to_time(start).jd_utc).ravel()[0])
    if not (0 < days <= 3660):
        raise ParameterError(f"days = {days} is outside the valid range (0, 3660]")
    return t0, t0 + float(days)


def _check_body(body: str) -> str:
    b = str(body).lower()
    if b not in BODIES:
        raise ParameterError(f"unknown body {body!r}: expected one of {', '.join(BODIES)}")
    return b


def rise_set(
    observer: Observer, start: Any, days: float = 1.0, body: str = "sun", horizon_deg=None
) -> tuple[np.ndarray, np.ndarray]:
    """UTC Julian Dates of the risings and settings of ``body`` in [start, start + days).

    ``horizon_deg``: geometric altitude of the centre defining the event (default: see
    the module doc). Bodies that stay up or down give no events.
    """
    b = _check_body(body)
    t0, t1 = _span(start, days)
    f = _altitude_function(observer, b, horizon_deg)
    # 10-minute grid: two horizon crossings closer than that (a grazing body) may be
    # missed, which is the accepted limit of any sampling search.
    roots, up = find_crossings(f, t0, t1, 10.0 / 1440.0, rising=None)
    return roots[up], roots[~up]


def _daily_range(
    observer: Observer, start: Any, days: float, body: str, horizon_deg: float | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Start (UTC JD) of each day of [start, start + days) and the least and greatest value
    of the body's altitude function (rad, see :func:`rise_set`) sampled every 10 minutes
    over that day (the last day may be shorter)."""
    t0, t1 = _span(start, days)
    day0 = t0 + np.arange(int(np.ceil(t1 - t0 - 1e-9)))
    day1 = np.minimum(day0 + 1.0, t1)
    frac = np.linspace(0.0, 1.0, _DAY_SAMPLES)
    grid = day0[:, None] + (day1 - day0)[:, None] * frac
    f = _altitude_function(observer, body, horizon_deg)(grid.ravel()).reshape(grid.shape)
    return day0, f.min(axis=1), f.max(axis=1)


def all_day(
    observer: Observer, start: Any, days: float = 1.0, body: str = "sun", horizon_deg=None
) -> tuple[np.ndarray, np.ndarray]:
    """Starts (UTC JD) of the days of [start, start + days) on which ``body`` stays above,
    and those on which it stays below, its rise-set altitude (or ``horizon_deg``) all day.

    Sampled every 10 minutes, as :func:`rise_set` is: a day is "above" when every sample
    is, so a body grazing the horizon between two samples is missed by both.
    """
    day0, lo, hi = _daily_range(observer, start, days, _check_body(body), horizon_deg)
    return day0[lo > 0], day0[hi < 0]


def transits(observer: Observer, start: Any, days: float = 1.0, body: str = "sun") -> np.ndarray:
    """UTC Julian Dates of the upper culminations of ``body`` in [start, start + days)."""
    b = _check_body(body)
    t0, t1 = _span(start, days)

    def f(jd_utc):
        p = observer.sky(Time.from_utc(jd_utc), bodies=(b,))[b]
        return -p.enu_unrefracted[..., 0]  # east component: + before, - after culmination

    # The east component also vanishes at lower culmination, where it goes from - to +;
    # keep only the + -> - (rising of -e) crossings.
    roots, _ = find_crossings(f, t0, t1, 30.0 / 1440.0, rising=True)
    return roots


def twilight(
    observer: Observer, start: Any, days: float = 1.0, kind: str = "civil"
) -> tuple[np.ndarray, np.ndarray]:
    """UTC Julian Dates of dawn and dusk for ``kind`` in civil, nautical, astronomical."""
    if kind not in TWILIGHT_DEPRESSION_DEG:
        raise ParameterError(
            f"twilight kind {kind!r} must be one of {', '.join(TWILIGHT_DEPRESSION_DEG)}"
        )
    return rise_set(observer, start, days, "sun", -TWILIGHT_DEPRESSION_DEG[kind])


def moon_phases(start: Any, days: float = 30.0) -> tuple[np.ndarray, np.ndarray]:
    """UTC Julian Dates of the principal Moon phases and their index (0 new, 1 first
    quarter, 2 full, 3 last quarter) in [start, start + days)."""
    t0, t1 = _span(start, days)

    def elongation(jd_utc):
        t = Time.from_utc(jd_utc)
        return (
            moon.moon_apparent_geocentric(t.jd_tt)["lon"]
            - sun.sun_apparent_geocentric(t.jd_tt)["lon"]
        )

    out_t, out_k = [], []
    for k in range(4):  # four targets, each one vectorized search
        target = k * np.pi / 2

        def f(jd, target=target):
            return np.sin(elongation(jd) - target)

        roots, _ = find_crossings(f, t0, t1, 1.0, rising=True)
        out_t.append(roots)
        out_k.append(np.full(roots.size, k))
    jd = np.concatenate(out_t)
    k = np.concatenate(out_k)
    order = np.argsort(jd)
    return jd[order], k[order]


def events(observer: Observer, start: Any, days: float = 1.0) -> Events:
    """Every event of the module doc for ``observer`` in [start, start + days)."""
    jd, kind, body = [], [], []

    def add(times, name, b):
        jd.append(np.asarray(times, float))
        kind.append(np.full(np.size(times), name, dtype=object))
        body.append(np.full(np.size(times), b, dtype=object))

    r, s = rise_set(observer, start, days, "sun")
    add(r, "sunrise", "sun")
    add(s, "sunset", "sun")
    add(transits(observer, start, days, "sun"), "transit", "sun")
    for k in TWILIGHT_DEPRESSION_DEG:
        dawn, dusk = twilight(observer, start, days, k)
        add(dawn, f"{k}_dawn", "sun")
        add(dusk, f"{k}_dusk", "sun")
    # Whole days without sunrise/sunset or a twilight: one evaluation of the Sun's geometric
    # altitude; each threshold shifts the altitude function by a constant.
    day0, lo, hi = _daily_range(observer, start, days, "sun", 0.0)
    up = lo > np.radians(SUN_HORIZON_DEG)
    down = hi < np.radians(SUN_HORIZON_DEG)
    add(day0[up], "sun_never_sets", "sun")
    add(day0[down], "sun_never_rises", "sun")
    dark_reported = up.copy()  # the shallowest depression never reached, once per day
    for k, d in TWILIGHT_DEPRESSION_DEG.items():  # from shallow to deep
        never_dark = (lo > np.radians(-d)) & ~dark_reported
        add(day0[never_dark], f"no_{k}_dusk", "sun")
        dark_reported |= never_dark
    light_reported = np.zeros_like(down)  # the deepest depression never reached
    for k, d in reversed(TWILIGHT_DEPRESSION_DEG.items()):
        never_light = (hi < np.radians(-d)) & ~light_reported
        add(day0[never_light], f"no_{k}_dawn", "sun")
        light_reported |= never_light
    r, s = rise_set(observer, start, days, "moon")
    add(r, "moonrise", "moon")
    add(s, "moonset", "moon")
    add(transits(observer, start, days, "moon"), "transit", "moon")
    m_up, m_down = all_day(observer, start, days, "moon")
    add(m_up, "moon_never_sets", "moon")
    add(m_down, "moon_never_rises", "moon")
    ph, k = moon_phases(start, days)
    jd.append(ph)
    kind.append(np.array([PHASE_NAMES[i] for i in k], dtype=object))
    body.append(np.full(ph.size, "moon", dtype=object))
    notes = [np.full(x.size, "", dtype=object) for x in jd]
    eclipse_rows = eclipse_events(observer, start, days)  # solar and lunar eclipses seen here
    for row in eclipse_rows:
        jd.append(np.array([row[0]]))
        kind.append(np.array([row[1]], dtype=object))
        body.append(np.array([row[2]], dtype=object))
        notes.append(np.array([row[3]], dtype=object))
    all_jd = np.concatenate(jd)
    order = np.argsort(all_jd, kind="stable")
    return Events(
        all_jd[order],
        np.concatenate(kind)[order].astype(str),
        np.concatenate(body)[order].astype(str),
        np.concatenate(notes)[order].astype(str),
    )


def eclipse_events(observer: Observer, start: Any, days: float) -> list[tuple]:
    """Eclipses seen from ``observer`` in [start, start + days) as (jd_utc, kind, body, note)
    rows (``skydome.astro.eclipses``): a solar eclipse's contacts C1, C2, C3, C4 and greatest
    eclipse (``solar_eclipse_C1``..., body "sun") when the Sun's centre is above the horizon
    (-0.833 deg) at one of them, a lunar eclipse's P1, U1..U4, P4 and greatest eclipse
    (``lunar_eclipse_P1``..., body "moon") when the Moon is up at one of them; the note says
    the eclipse's kind and the body's altitude (deg, airless) at that instant."""
    from_jd = float(np.ravel(to_time(start).jd_utc)[0])
    out = []
    for e in eclipses.find_solar_eclipses(observer, from_jd - 0.5, days + 1.0):
        if max(e.sun_alt_deg.values()) < SUN_HORIZON_DEG:
            continue
        for name, t in e.contacts().items():
            if from_jd <= t < from_jd + days:
                alt = e.sun_alt_deg[name]
                note = f"{e.kind}, magnitude {e.magnitude:.3f}, Sun at {alt:.1f} deg"
                out.append((t, f"solar_eclipse_{name}", "sun", note))
    for e in eclipses.find_lunar_eclipses(from_jd - 0.5, days + 1.0, observer):
        if max(e.moon_alt_deg.values()) < REFRACTION_HORIZON_DEG:
            continue
        for name, t in e.contacts().items():
            if from_jd <= t < from_jd + days:
                alt = e.moon_alt_deg[name]
                note = f"{e.kind}, umbral magnitude {e.umbral_magnitude:.3f}"
                note += f", Moon at {alt:.1f} deg"
                out.append((t, f"lunar_eclipse_{name}", "moon", note))
    return out
