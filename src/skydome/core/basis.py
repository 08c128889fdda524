"""How spectral values become a frame's four output channels."""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from skydome.errors import ParameterError
from skydome.physics.packing import mat4_groups
from skydome.spectra import SRGB_LUMINANCE, conversion_matrix


@dataclass(frozen=True)
class SpectralBasis:
    """How spectral values become a frame's four channels.

    ``to_output`` (4, N) takes N transfer values (per unit of the tabulated solar spectral
    irradiance, at ``wavelengths_nm``) to the output channels: (R, G, B, scotopic) in cd/m^2
    for ``output="rgbs"`` (``spectral_to_rgbs_matrix``), or the 4 wavelengths themselves for
    ``output="spectral"`` (the identity). Every layer of one graph uses the same basis, the
    atmosphere's when it has one.
    """

    wavelengths_nm: np.ndarray
    to_output: np.ndarray
    output: str = "rgbs"

    @classmethod
    def for_wavelengths(cls, wavelengths_nm, output: str = "rgbs") -> SpectralBasis:
        """The basis of these wavelengths (nm) and output: one instance per set, so that
        what layers keep per basis (the stars' colours, ...) serves every sky made with it
        (``Sky.at``'s copies too). Its arrays are read-only."""
        wl = np.asarray(wavelengths_nm, dtype=np.float64)
        if cls is not SpectralBasis or wl.ndim != 1:
            return cls(wl, conversion_matrix(wl, output), output)
        return _basis_of(tuple(wl.tolist()), output)

    @property
    def groups(self) -> int:
        """Groups of 4 wavelengths (vec4s per spectral value in the shaders)."""
        return len(self.wavelengths_nm) // 4

    def group_matrices(self) -> list[float]:
        """``to_output`` as one GLSL mat4 per group of 4 wavelengths, flattened for a
        ``uniform mat4 u_spectral_to_rgbs[NUM_GROUPS]``."""
        return mat4_groups(self.to_output)

    def colour(self, relative_spectrum) -> np.ndarray:
        """Output channels per unit luminance of light with this spectral shape relative to
        the solar spectrum (e.g. the Moon's albedo): for ``rgbs``, RGB with Y = 1 and the
        scotopic-to-photopic ratio; for ``spectral``, the shape itself per unit luminance."""
        f = np.asarray(relative_spectrum, dtype=np.float64)
        rgbs = conversion_matrix(self.wavelengths_nm, "rgbs") @ f
        y = float(SRGB_LUMINANCE @ rgbs[:3])
        if not y > 0:
            raise ParameterError("a light's spectrum must have a positive luminance")
        return (self.to_output @ f) / y

    def colours(self, relative_spectra) -> np.ndarray:
        """:meth:`colour` of many spectra at once: ``relative_spectra`` (W, N) columns, one
        per light, of any scale; returns (N, 4)."""
        f = np.asarray(relative_spectra, dtype=np.float64)
        f = f / f.max(axis=0, keepdims=True)  # any scale: the colour is per unit luminance
        y = SRGB_LUMINANCE @ (conversion_matrix(self.wavelengths_nm, "rgbs") @ f)[:3]
        return (self.to_output @ f / y).T


@functools.lru_cache(maxsize=16)
def _basis_of(wavelengths_nm: tuple[float, ...], output: str) -> SpectralBasis:
    wl = np.array(wavelengths_nm, dtype=np.float64)
    to_output = conversion_matrix(wl, output)
    wl.setflags(write=False)
    to_output.setflags(write=False)
    return SpectralBasis(wl, to_output, output)
