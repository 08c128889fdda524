"""Astronomy layer: time scales, reference frames, Sun, Moon, planets, stars, photometry, events.

Pure NumPy; every function is vectorized over arrays of times. The main entry point:

>>> from skydome.astro import Observer
>>> sky = Observer(latitude=39.74, longitude=-105.18, elevation_m=1830).sky(
...     "2003-10-17T19:30:30Z", bodies=("sun", "moon", "venus"))
>>> sky["sun"].alt_deg, sky["sun"].az_deg

Modules: :mod:`~skydome.astro.time` (UTC/UT1/TT, Julian Dates, Delta T, sidereal time),
:mod:`~skydome.astro.frames` (precession, nutation, aberration, horizontal coordinates,
refraction), :mod:`~skydome.astro.sun`, :mod:`~skydome.astro.moon`,
:mod:`~skydome.astro.planets`, :mod:`~skydome.astro.photometry`,
:mod:`~skydome.astro.events` and, when present, :mod:`~skydome.astro.stars` (imported
lazily by :meth:`Observer.sky`).
"""

from skydome.astro import frames, photometry
from skydome.astro.events import Events, events, moon_phases, rise_set, transits, twilight
from skydome.astro.observer import BODIES, BodyPosition, Observer, SkyPositions
from skydome.astro.time import Time, gast, gmst, julian_date, to_time

__all__ = [
    "BODIES",
    "BodyPosition",
    "Events",
    "Observer",
    "SkyPositions",
    "Time",
    "events",
    "frames",
    "gast",
    "gmst",
    "julian_date",
    "moon_phases",
    "photometry",
    "rise_set",
    "to_time",
    "transits",
    "twilight",
]
