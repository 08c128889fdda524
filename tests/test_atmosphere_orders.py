"""Scattering orders until they converge (PrecomputeConfig.tolerance > 0): hazy air needs
many (Bruneton's users found about 20 for 3 km of visibility), and once the orders fall
geometrically the rest of the series is added at once. Checked against the same tables with
30 orders computed one by one (the series' remainder after 30 is below 0.1 % here)."""

from __future__ import annotations

from dataclasses import replace

import pytest

from skydome.atmosphere.illuminance import horizontal_illuminance
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.atmosphere.presets import preset
from skydome.atmosphere.tables import load_tables

pytestmark = pytest.mark.gl


def test_converged_orders_match_thirty(ctx):
    """Air of 3 km visibility: the converged series stops by order 12 and its diffuse
    illuminance and zenith luminance (Sun at 60, 10 and -3 deg) are within 1.5 % of 30
    orders' (measured <= 1.1 % on the default tables: the tail's shape is the last order's).
    Tables of half the default resolution (the tiny ones of the other tests gain energy from
    order to order: their series does not converge)."""
    air = preset("earth").with_visibility(3.0)
    half = PrecomputeConfig(
        wavelengths="fast", scattering_size=(16, 64, 16, 8), multiple_size=(16, 32, 32, 8),
        ms_size=(16, 32, 32, 8),
    )  # fmt: skip
    converged = replace(half, orders=50, tolerance=1e-3)
    thirty = replace(half, orders=30, tolerance=0.0)
    tables, _ = load_tables(ctx, air, converged)
    assert 4 <= tables.orders_computed <= 12
    a = horizontal_illuminance([60.0, 10.0, -3.0], atmosphere=air, config=converged)
    b = horizontal_illuminance([60.0, 10.0, -3.0], atmosphere=air, config=thirty)
    for x, y in zip(a, b, strict=True):
        assert x.diffuse_horizontal_lux == pytest.approx(y.diffuse_horizontal_lux, rel=0.015)
        assert x.zenith_luminance_cd_m2 == pytest.approx(y.zenith_luminance_cd_m2, rel=0.015)
