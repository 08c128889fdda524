"""Frames: float32 (H, W, 4) arrays, row 0 at the top; RGB linear sRGB with Y in cd/m^2 and
channel 3 the scotopic luminance (scotopic cd/m^2)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from skydome.spectra import SRGB_LUMINANCE


@dataclass
class Frame:
    """A rendered frame in absolute units, and how it was made."""

    data: np.ndarray
    info: dict = field(default_factory=dict)
    #: The tone-mapped uint8 sRGB image (H, W, 3), when one was asked for.
    image: np.ndarray | None = None

    @property
    def rgb(self) -> np.ndarray:
        """Linear sRGB, cd/m^2 (Y = luminance)."""
        return self.data[..., :3]

    @property
    def scotopic(self) -> np.ndarray:
        """Scotopic luminance, scotopic cd/m^2."""
        return self.data[..., 3]

    @property
    def luminance(self) -> np.ndarray:
        """Photopic luminance, cd/m^2."""
        return self.data[..., :3] @ SRGB_LUMINANCE.astype(np.float32)

    @property
    def shape(self) -> tuple[int, int]:
        return self.data.shape[:2]
