"""The segments' memo (``_series.SegmentMemo``): the Chebyshev coefficients of a segment of
time are computed once per process and reused by later calls on any times in it.

What must hold: a later call on other times of the same segments computes nothing new and
gives the same numbers as a fresh memo (the coefficients of a segment depend on it alone);
the span starts again when it would pass its memory bound; and what ``Observer.sky`` returns
for sparse random times (1e5 over 150 years: the case the memo is for) equals the series
summed term by term within the interpolation bar of ``test_chebyshev_interpolation_is_lossless``
(1e-4", 1 m), whatever was computed before.
"""

import numpy as np
import pytest

from skydome.astro import Observer, frames, moon, sun
from skydome.astro._series import J2000, SegmentMemo, smooth, vsop

ARCSEC = frames.ARCSEC


def _counting(func):
    calls = []

    def wrapped(jd):
        calls.append(np.asarray(jd).size)
        return func(jd)

    return wrapped, calls


def _random_jd(seed: int, n: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return 2415020.5 + rng.random(n) * 54786.0  # 1900 .. 2050


def test_later_calls_reuse_the_segments_and_agree_with_a_fresh_memo():
    series = vsop("earth").lbr
    memo = SegmentMemo()
    first, second = _random_jd(1, 80_000), _random_jd(2, 80_000)
    func, calls = _counting(series)
    smooth(func, first, 16.0, 12, memo=memo)
    assert calls and calls[0] % 13 == 0  # the segments' nodes, not the times
    n_first = len(calls)
    again = smooth(func, second, 16.0, 12, memo=memo)
    new_segments = np.setdiff1d(
        np.unique(np.floor((second - J2000) / 16.0)), np.unique(np.floor((first - J2000) / 16.0))
    )
    assert new_segments.size == 0  # 23 times a segment on average: every one was hit
    assert len(calls) == n_first  # nothing evaluated again
    fresh = smooth(series, second, 16.0, 12, memo=SegmentMemo())
    # the same coefficients, up to the matrix product's summation order (1e-15 relative)
    assert np.abs(again - fresh).max() < 1e-13
    direct = series(second)
    assert np.abs(again[:2] - direct[:2]).max() / ARCSEC < 1e-4


def test_sparse_times_in_two_eras_and_the_memory_bound():
    series = vsop("earth").lbr
    jd_a = _random_jd(3, 80_000)  # enough a segment that the cost rule interpolates
    jd_b = jd_a + 365250.0 * 3  # 3000 years later
    per_segment = 13 * 3 * 8  # bytes: (degree + 1) coefficients of 3 rows
    span_a = np.ptp(np.floor((jd_a - J2000) / 16.0)) + 1
    memo = SegmentMemo(max_bytes=int(1.5 * span_a * per_segment))
    a = smooth(series, jd_a, 16.0, 12, memo=memo)
    assert memo.coef is not None
    first_a = memo.first
    b = smooth(series, jd_b, 16.0, 12, memo=memo)  # both eras would pass the bound
    assert memo.first > first_a  # started again from era b
    assert memo.held.size == np.ptp(np.floor((jd_b - J2000) / 16.0)) + 1
    for jd, out in ((jd_a, a), (jd_b, b)):
        assert np.abs(out[:2] - series(jd)[:2]).max() / ARCSEC < 1e-4
    # a call on both eras: the span starts again from all of its segments, era a's included
    both = np.concatenate([jd_a[:40_000], jd_b[:40_000]])
    again = smooth(series, both, 16.0, 12, memo=memo)
    assert np.abs(again[:2] - series(both)[:2]).max() / ARCSEC < 1e-4
    tiny = SegmentMemo(max_bytes=per_segment)  # one call's span beyond the bound: not kept
    c = smooth(series, jd_a, 16.0, 12, memo=tiny)
    assert tiny.coef is None
    np.testing.assert_array_equal(c, a)


def test_the_moon_segments_are_kept_per_length():
    series = moon._LunarSeries()
    jd = _random_jd(4, 50_000)
    first = series(jd)
    used = [d for d in moon.SEGMENT_DAYS if series.memos[d].coef is not None]
    assert used  # sparse times over 150 years take the segments, not the direct sums
    calls = []
    original = series._segment_coefficients
    series._segment_coefficients = lambda s, d: calls.append(s.size) or original(s, d)
    again = series(jd[::-1].copy())
    assert calls == []  # every segment held
    np.testing.assert_allclose(again[:, ::-1], first, rtol=0, atol=1e-9)
    direct = series.direct(jd[:2000])
    got = series(jd[:2000])
    assert np.abs(got[:2] - direct[:2]).max() / ARCSEC < 1e-5  # the segments' bar


@pytest.mark.parametrize("order", ["sparse first", "dense first"])
def test_observer_sky_on_sparse_times_equals_the_direct_series(order):
    """Through the user's path: Sun and Moon from ``Observer.sky`` for 1e5 random times,
    before or after a dense call that filled other segments, against the geocentric series
    summed term by term (the Moon's longitude, the nutation and the Earth's position)."""
    obs = Observer(48.85, 2.35, 35.0)
    jd = _random_jd(5, 100_000)
    if order == "dense first":
        obs.sky(2460310.5 + np.linspace(0.0, 365.0, 100_000), bodies=("sun", "moon"))
    obs.sky(jd, bodies=("sun", "moon"))
    lam, beta, dist = moon.moon_ecliptic_of_date(jd)
    ref = moon._moon_direct(jd)
    dl = (ref[0] - lam + np.pi) % (2 * np.pi) - np.pi
    assert np.abs(dl).max() / ARCSEC < 1e-4 and np.abs(ref[1] - beta).max() / ARCSEC < 1e-4
    assert np.abs(ref[2] - dist).max() < 1e-3  # km
    nut = np.array(frames.nutation_angles(jd))
    assert np.abs(nut - frames._nutation_direct(jd)).max() / ARCSEC < 1e-4
    pos, _ = sun.earth_heliocentric_state(jd)
    ref_e = frames.spherical_to_cartesian(*vsop("earth").lbr(jd))
    assert np.abs(pos - ref_e).max() * frames.AU_KM < 1e-3  # km
