"""skydome: physically based skies in absolute units.

>>> from skydome import Sky
>>> frame = Sky("Valletta", "2018-03-01T19:00Z").render(look="moon", tonemap="filmic")
"""

from skydome.errors import SkydomeError

__version__ = "0.1.0"

__all__ = ["Sky", "SkydomeError", "__version__"]


def __getattr__(name: str):
    # Sky is imported on first use: the command line starts without NumPy or GL.
    if name == "Sky":
        from skydome.scene import Sky

        return Sky
    raise AttributeError(f"module 'skydome' has no attribute {name!r}")
