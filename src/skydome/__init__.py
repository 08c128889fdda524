"""skydome: physically based skies in absolute units.

>>> from skydome import Sky
>>> frame = Sky("Valletta", "2018-03-01T19:00Z").render(look="moon", tonemap="filmic")
"""

from skydome.errors import SkydomeError

__version__ = "0.1.0"

__all__ = ["Clouds", "Sky", "SkydomeError", "__version__"]


def __getattr__(name: str):
    # Sky is imported on first use: the command line starts without NumPy or GL. By name, not
    # by an import statement: the tables' cache key follows import statements
    # (atmosphere/cache.py), and the package's root must not pull the scene into it.
    if name == "Sky":
        import importlib

        return importlib.import_module("skydome.scene").Sky
    if name == "Clouds":
        import importlib

        return importlib.import_module("skydome.clouds.params").Clouds
    raise AttributeError(f"module 'skydome' has no attribute {name!r}")
