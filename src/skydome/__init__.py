"""skydome: physically based skies in absolute units."""

from skydome.errors import SkydomeError

__version__ = "0.1.0"

__all__ = ["SkydomeError", "__version__"]
