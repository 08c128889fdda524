"""Astronomy layer: time scales, reference frames, Sun, Moon, planets, stars, photometry, events.

Pure NumPy; every function is vectorized over arrays of times.
"""

from skydome.astro import frames

__all__ = ["frames"]
