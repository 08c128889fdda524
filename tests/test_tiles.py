"""Frames in pixels: the box filter of a supersampled frame, and per-pixel inputs given to
each of a pixel's rays (skydome.core.tiles)."""

from __future__ import annotations

import numpy as np
import pytest

from skydome.core.tiles import MAX_SUPERSAMPLE, block_mean, check_supersample, repeat_pixels
from skydome.errors import ParameterError


def test_block_mean_is_a_box_filter_that_keeps_the_flux():
    # A point source in one of a pixel's 3 x 3 rays: the pixel holds a ninth of its value,
    # so the sum over the frame (the flux, at the small pixels' solid angle x 9) is kept.
    big = np.zeros((6, 9, 4), np.float32)
    big[4, 7] = (9.0, 18.0, 27.0, 1.0)
    small = block_mean(big, 3)
    assert small.shape == (2, 3, 4) and small.dtype == np.float32
    np.testing.assert_allclose(small[1, 2], (1.0, 2.0, 3.0, 1.0 / 9.0), rtol=1e-7)
    assert small.sum() * 9 == pytest.approx(big.sum(), rel=1e-6)
    assert block_mean(big, 1) is big
    # float32 frames are summed in float64: 1 + 16 values of 1e-8 keep their 1.6e-7
    fine = np.full((4, 4, 1), 1e-8, np.float32)
    fine[0, 0] = 1.0
    assert float(block_mean(fine, 4)[0, 0, 0]) == pytest.approx((1.0 + 15e-8) / 16, rel=1e-7)


def test_repeat_pixels_gives_every_ray_its_pixels_value():
    depth = np.arange(6.0).reshape(2, 3)
    big = repeat_pixels(depth, 2)
    assert big.shape == (4, 6)
    np.testing.assert_array_equal(block_mean(big, 2), depth)
    np.testing.assert_array_equal(big[2:4, 4:6], 5.0)


def test_check_supersample():
    assert [check_supersample(n) for n in range(1, MAX_SUPERSAMPLE + 1)] == [1, 2, 3, 4]
    assert check_supersample(np.int64(2)) == 2
    for bad in (0, MAX_SUPERSAMPLE + 1, 2.0, True, "2", None):
        with pytest.raises(ParameterError, match=r"supersample .* must be an integer in \[1, 4\]"):
            check_supersample(bad)
