"""Jumps of the viewer's time to the next event: sunrise, sunset, moonrise, full Moon, and
the greatest phase of the next eclipse seen from the place (solar or lunar).

Each finds the first event strictly after a time, from ``skydome.astro.events``.
"""

from __future__ import annotations

import numpy as np

from skydome.astro.events import eclipse_events, moon_phases, rise_set
from skydome.astro.time import Time
from skydome.errors import ParameterError

#: The events the viewer can jump to, and how far ahead each is looked for (days).
JUMPS = {
    "sunrise": 2.0, "sunset": 2.0, "moonrise": 3.0, "moonset": 3.0, "full_moon": 31.0,
    "eclipse": 3.0 * 365.25,
}  # fmt: skip
#: An event closer than this after the current time is skipped (s): a second press goes on
#: to the next one instead of staying put.
MIN_AHEAD_S = 60.0


def next_event(observer, jd_utc: float, kind: str) -> float | None:
    """The UTC Julian Date of the first ``kind`` (a key of JUMPS) after ``jd_utc`` seen by
    ``observer`` (the full Moon needs none: pass any), or None when there is none within
    the search span (a polar day has no sunset; no eclipse is seen from the place within
    three years)."""

    if kind not in JUMPS:
        raise ParameterError(f"jump {kind!r} must be one of {', '.join(JUMPS)}")
    start = float(jd_utc) + MIN_AHEAD_S / 86400.0
    t = Time.from_utc(start)
    days = JUMPS[kind]
    if kind == "full_moon":
        jd, phase = moon_phases(t, days)
        found = jd[phase == 2]
    elif kind == "eclipse":
        rows = eclipse_events(observer, t, days)
        found = np.array([jd for jd, name, _, _ in rows if name.endswith("_eclipse_max")])
    else:
        body = "sun" if kind.startswith("sun") else "moon"
        rises, sets = rise_set(observer, t, days, body)
        found = rises if kind.endswith("rise") else sets
    found = found[found > start]
    return float(found.min()) if found.size else None
