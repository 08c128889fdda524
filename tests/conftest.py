"""Shared fixtures: one headless GL context and cached renderers for the whole session."""

from __future__ import annotations

import os
import tempfile

import pytest

# Tests never touch the user's cache: one fresh cache directory per test session.
os.environ["SKYDOME_CACHE"] = tempfile.mkdtemp(prefix="skydome-test-cache-")

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


@pytest.fixture(scope="session")
def renderer_factory():
    from tests.air_frames import single_frames

    return single_frames
