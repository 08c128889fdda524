"""Shared fixtures: one headless GL context and cached renderers for the whole session."""

from __future__ import annotations

import functools
import os
import tempfile

import pytest

# Tests never touch the user's cache: one fresh cache directory per test session.
os.environ["SKYDOME_CACHE"] = tempfile.mkdtemp(prefix="skydome-test-cache-")

from skydome.atmosphere import preset
from skydome.gpu import shared_context


def _tiny_tables():
    from skydome.atmosphere.precompute_config import PrecomputeConfig

    return PrecomputeConfig(
        wavelengths="fast",
        orders=2,
        scattering_size=(8, 32, 8, 4),
        ms_size=(8, 16, 8, 4),
        irradiance_size=(16, 8),
        transmittance_size=(64, 16),
    )


#: Tables small enough to precompute in a fraction of a second (cache and plumbing tests).
TINY_TABLES = _tiny_tables()


@pytest.fixture(scope="session")
def ctx():
    return shared_context()


@functools.cache
def single_renderer(
    atmosphere: str = "earth", spectral: str = "fast", samples: int = 16, jitter: bool = False
):
    from skydome.render.single import SingleScatteringRenderer

    return SingleScatteringRenderer(
        preset(atmosphere), spectral=spectral, view_samples=samples, jitter=jitter
    )


@pytest.fixture(scope="session")
def renderer_factory():
    return single_renderer


@functools.cache
def precomputed_renderer(
    atmosphere: str = "earth", spectral: str = "accurate", orders: int = 4, sky_view: bool = True
):
    """``sky_view=False``: every pixel looked up in the 4D tables (the same tables)."""
    from skydome.atmosphere.precompute_config import PrecomputeConfig
    from skydome.render.precomputed import PrecomputedRenderer

    return PrecomputedRenderer(
        preset(atmosphere),
        PrecomputeConfig(wavelengths=spectral, orders=orders),
        sky_view=sky_view,
    )
