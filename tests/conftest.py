"""Shared fixtures: one headless GL context and cached renderers for the whole session."""

from __future__ import annotations

import functools

import pytest

from skydome.atmosphere import preset
from skydome.gpu import shared_context


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
